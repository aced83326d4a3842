#include "preview/spectrum_plot.h"

#include <imgui.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace metamer::preview {

void plotSpectra(const char* id, const std::vector<double>& x, const std::vector<std::string>& channelNames,
                 const std::vector<PlotSeries>& series, const char* yUnit, float width, float height) {
    ImGui::PushID(id);
    const bool spectral = channelNames.empty();
    float lo = 0.0f, hi = 0.0f;
    for (const PlotSeries& s : series)
        for (float v : s.values)
            if (std::isfinite(v)) {
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
    if (!(hi > lo)) hi = lo + 1.0f;
    const float axisH = ImGui::GetTextLineHeight();
    ImVec2 origin = ImGui::GetCursorScreenPos();
    ImGui::InvisibleButton("plot", ImVec2(width, height + axisH));
    ImDrawList* dl = ImGui::GetWindowDrawList();
    ImVec2 p0 = origin, p1(origin.x + width, origin.y + height);
    dl->AddRectFilled(p0, p1, IM_COL32(25, 25, 30, 255));
    dl->AddRect(p0, p1, IM_COL32(90, 90, 100, 255));
    const size_t n = x.size();
    auto px = [&](size_t i) { return p0.x + (n > 1 ? float(i) / float(n - 1) : 0.5f) * (width - 1.0f); };
    auto py = [&](float v) { return p1.y - (v - lo) / (hi - lo) * (height - 1.0f); };
    if (lo < 0.0f) dl->AddLine(ImVec2(p0.x, py(0.0f)), ImVec2(p1.x, py(0.0f)), IM_COL32(90, 90, 100, 255));
    for (const PlotSeries& s : series) {
        std::vector<ImVec2> pts;
        for (size_t i = 0; i < n && i < s.values.size(); ++i)
            if (std::isfinite(s.values[i])) pts.emplace_back(px(i), py(s.values[i]));
        if (pts.size() == 1) dl->AddCircleFilled(pts[0], 2.5f, s.colour);
        else if (pts.size() > 1) dl->AddPolyline(pts.data(), int(pts.size()), s.colour, 0, 1.5f);
    }
    // Axis labels: the first and last x, the largest y and its unit.
    auto xLabel = [&](size_t i) {
        return spectral ? fmt::format("{:g} nm", x[i]) : (i < channelNames.size() ? channelNames[i] : fmt::format("{}", i));
    };
    if (n > 0) {
        dl->AddText(ImVec2(p0.x, p1.y + 1), IM_COL32(180, 180, 190, 255), xLabel(0).c_str());
        std::string last = xLabel(n - 1);
        float w = ImGui::CalcTextSize(last.c_str()).x;
        dl->AddText(ImVec2(p1.x - w, p1.y + 1), IM_COL32(180, 180, 190, 255), last.c_str());
    }
    std::string top = fmt::format("{:.4g} {}", hi, yUnit);
    dl->AddText(ImVec2(p0.x + 3, p0.y + 1), IM_COL32(180, 180, 190, 255), top.c_str());
    // Hover: the nearest x and every series' value there.
    if (ImGui::IsItemHovered() && n > 0) {
        float t = (ImGui::GetIO().MousePos.x - p0.x) / std::max(1.0f, width - 1.0f);
        size_t i = size_t(std::clamp(std::lround(t * float(n - 1)), 0L, long(n - 1)));
        dl->AddLine(ImVec2(px(i), p0.y), ImVec2(px(i), p1.y), IM_COL32(200, 200, 200, 120));
        ImGui::BeginTooltip();
        ImGui::TextUnformatted(xLabel(i).c_str());
        for (const PlotSeries& s : series)
            if (i < s.values.size())
                ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(s.colour), "%s: %.5g %s", s.label.c_str(),
                                   s.values[i], yUnit);
        ImGui::EndTooltip();
    }
    ImGui::PopID();
}

}  // namespace metamer::preview
