#include "preview/settings_panel.h"
#include "color/detector_registry.h"

#include "color/detector.h"
#include "radiosity/scene_radiosity.h"

#include <imgui.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace metamer::preview {

namespace {

// A combo over `items`; `current` is listed first when it is not among them. Returns the new
// choice, or "" when nothing was chosen.
std::string combo(const char* label, const std::string& current, const std::vector<std::string>& items) {
    std::string chosen;
    if (ImGui::BeginCombo(label, current.c_str())) {
        std::vector<std::string> all = items;
        if (std::find(all.begin(), all.end(), current) == all.end()) all.insert(all.begin(), current);
        for (const auto& item : all)
            if (ImGui::Selectable(item.c_str(), item == current) && item != current) chosen = item;
        ImGui::EndCombo();
    }
    return chosen;
}

const char* lightType(Light::Type t) {
    switch (t) {
        case Light::Type::Ambient: return "ambient";
        case Light::Type::Directional: return "directional";
        case Light::Type::Point: return "point";
        case Light::Type::Hemisphere: return "hemisphere";
    }
    return "?";
}

}  // namespace

void setOverride(std::vector<std::string>& overrides, const std::string& key, const std::string& value) {
    std::string prefix = key + "=";
    auto it = std::find_if(overrides.begin(), overrides.end(),
                           [&](const std::string& o) { return o.rfind(prefix, 0) == 0; });
    if (it != overrides.end()) {
        // Later overrides win: move the edited one to the end.
        overrides.erase(it);
    }
    overrides.push_back(prefix + value);
}

void setInterreflection(std::vector<std::string>& overrides, bool on) {
    const std::string undo = on ? "interreflection=false" : "interreflection=true";
    const auto it = std::find(overrides.begin(), overrides.end(), undo);
    if (it != overrides.end())
        overrides.erase(it);
    else
        setOverride(overrides, "interreflection", on ? "true" : "false");
}

Grid gridWithStep(const Grid& grid, double step_nm) {
    Grid g = grid;
    g.step_nm = step_nm;
    double k = std::floor((grid.end_nm - grid.start_nm) / step_nm + 1e-9);
    g.end_nm = grid.start_nm + std::max(0.0, k) * step_nm;
    return g;
}

std::string transmittanceKey(const Material& m) { return "materials." + m.name + ".transmittance"; }
std::string absorbanceKey(const Material& m) { return "materials." + m.name + ".absorbance"; }
std::string dyeConcentrationKey(const Material& m, size_t dye) {
    return fmt::format("materials.{}.dyes.{}.concentration", m.name, dye);
}

std::string layerThicknessKey(const Material& m, size_t layer) {
    return fmt::format("materials.{}.layers.{}.thickness", m.name, layer);
}

std::string pigmentConcentrationKey(const Material& m, size_t layer, size_t pigment) {
    return fmt::format("materials.{}.layers.{}.pigments.{}.concentration", m.name, layer, pigment);
}

SettingsPanel::SettingsPanel(const SpectrumLibrary& library) {
    for (const auto& n : library.names()) {
        if (n.rfind("illuminants/", 0) == 0) lightSpectra_.push_back(n);
        if (n.rfind("filters/", 0) == 0) filterSpectra_.push_back(n);
        if (n.rfind("media/", 0) == 0) mediumSpectra_.push_back(n);
    }
    detectors_ = detectorNames(library);
}

bool SettingsPanel::draw(const View& view, RenderJob& job) {
    job = view.job();
    bool changed = false;
    const Scene& scene = view.scene();
    const TonemapPlan& plan = view.plan();

    if (ImGui::CollapsingHeader("Lights", ImGuiTreeNodeFlags_DefaultOpen)) {
        for (size_t i = 0; i < scene.lights.size(); ++i) {
            const Light& light = scene.lights[i];
            ImGui::PushID(int(i));
            ImGui::Text("%s (%s)", light.name.c_str(), lightType(light.type));
            std::string pick = combo("spectrum", light.spectrum.spectrum.source, lightSpectra_);
            if (!pick.empty()) {
                setOverride(job.overrides, light.name + ".spectrum", pick);
                changed = true;
            }
            double scale = light.scale;
            ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.45f);
            if (ImGui::InputDouble("scale", &scale, 0.0, 0.0, "%.6g", ImGuiInputTextFlags_EnterReturnsTrue) &&
                scale != light.scale) {
                setOverride(job.overrides, light.name + ".scale", fmt::format("{:.9g}", scale));
                changed = true;
            }
            ImGui::SameLine();
            if (ImGui::SmallButton("\u00d7\u00bd")) {  // ×½
                setOverride(job.overrides, light.name + ".scale", fmt::format("{:.9g}", light.scale * 0.5));
                changed = true;
            }
            ImGui::SameLine();
            if (ImGui::SmallButton("\u00d72")) {  // ×2
                setOverride(job.overrides, light.name + ".scale", fmt::format("{:.9g}", light.scale * 2.0));
                changed = true;
            }
            if (light.type == Light::Type::Directional || light.type == Light::Type::Point) {
                bool shadows = light.shadows;
                if (ImGui::Checkbox("shadows", &shadows)) {
                    setOverride(job.overrides, light.name + ".shadows", shadows ? "true" : "false");
                    changed = true;
                }
            }
            ImGui::PopID();
        }
        if (scene.lights.empty()) ImGui::TextDisabled("the scene has no lights");
    }

    if (scene.hasTransparency() && ImGui::CollapsingHeader("Transparent objects", ImGuiTreeNodeFlags_DefaultOpen)) {
        // A filter's spectrum from the library's filters/, a medium's from media/, a dye's
        // concentration halved or doubled (its transmittance squared or rooted).
        for (size_t i = 0; i < scene.materials.size(); ++i) {
            const Material& m = scene.materials[i];
            if (!m.isTransparent()) continue;
            ImGui::PushID(int(1000 + i));
            ImGui::Text("%s (%s)", m.name.c_str(), m.isFilter() ? "filter" : "medium");
            if (m.transmittance) {
                const std::string pick = combo("transmittance", m.transmittance->spectrum.source, filterSpectra_);
                if (!pick.empty()) {
                    setOverride(job.overrides, transmittanceKey(m), pick);
                    changed = true;
                }
            }
            if (m.absorbance) {
                const std::string pick = combo("absorbance", m.absorbance->spectrum.source, mediumSpectra_);
                if (!pick.empty()) {
                    setOverride(job.overrides, absorbanceKey(m), pick);
                    changed = true;
                }
            }
            for (size_t d = 0; d < m.dyes.size(); ++d) {
                ImGui::PushID(int(d));
                ImGui::Text("dye %zu: %s, %.4g mol/L", d, m.dyes[d].absorptivity.spectrum.source.c_str(),
                            m.dyes[d].concentration);
                ImGui::SameLine();
                const double c = m.dyes[d].concentration;
                if (ImGui::SmallButton("\u00d7\u00bd")) {  // ×½
                    setOverride(job.overrides, dyeConcentrationKey(m, d), fmt::format("{:.9g}", c * 0.5));
                    changed = true;
                }
                ImGui::SameLine();
                if (ImGui::SmallButton("\u00d72")) {  // ×2
                    setOverride(job.overrides, dyeConcentrationKey(m, d), fmt::format("{:.9g}", c * 2.0));
                    changed = true;
                }
                ImGui::PopID();
            }
            ImGui::PopID();
        }
    }

    if (std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.isPaint(); }) &&
        ImGui::CollapsingHeader("Paints", ImGuiTreeNodeFlags_DefaultOpen)) {
        // A layer's thickness and a pigment's concentration halved or doubled: the scene reloads
        // and Kubelka–Munk runs again for that material (once, not per frame).
        auto halveOrDouble = [&](const std::string& key, double value) {
            ImGui::SameLine();
            if (ImGui::SmallButton("\u00d7\u00bd")) {  // ×½
                setOverride(job.overrides, key, fmt::format("{:.9g}", value * 0.5));
                changed = true;
            }
            ImGui::SameLine();
            if (ImGui::SmallButton("\u00d72")) {  // ×2
                setOverride(job.overrides, key, fmt::format("{:.9g}", value * 2.0));
                changed = true;
            }
        };
        for (size_t i = 0; i < scene.materials.size(); ++i) {
            const Material& m = scene.materials[i];
            if (!m.isPaint()) continue;
            ImGui::PushID(int(2000 + i));
            ImGui::Text("%s", m.name.c_str());
            for (size_t l = 0; l < m.paint->layers.size(); ++l) {
                const Material::Paint::Layer& layer = m.paint->layers[l];
                ImGui::PushID(int(l));
                if (std::isinf(layer.thickness_m)) {
                    ImGui::Text("  layer %zu: opaque", l);
                } else {
                    ImGui::Text("  layer %zu: %.4g \u00b5m%s", l, layer.thickness_m * 1e6,
                                layer.thicknessMap >= 0 ? " \u00d7 map" : "");
                    halveOrDouble(layerThicknessKey(m, l), layer.thickness_m);
                }
                for (size_t p = 0; p < layer.pigments.size(); ++p) {
                    ImGui::PushID(int(p));
                    const Material::Paint::Pigment& pigment = layer.pigments[p];
                    ImGui::Text("    %s %.4g", pigment.name.empty() ? "(k, s)" : pigment.name.c_str(), pigment.concentration);
                    halveOrDouble(pigmentConcentrationKey(m, l, p), pigment.concentration);
                    ImGui::PopID();
                }
                ImGui::PopID();
            }
            ImGui::PopID();
        }
    }

    if (ImGui::CollapsingHeader("Interreflection", ImGuiTreeNodeFlags_DefaultOpen)) {
        // Light that bounces: on or off, and its element size halved or doubled (the form factors
        // are computed again; a light's spectrum change above re-solves them).
        bool on = scene.interreflection.has_value();
        if (ImGui::Checkbox("light bounces", &on)) {
            setInterreflection(job.overrides, on);
            changed = true;
        }
        if (scene.interreflection) {
            const double size = radiosity::elementSize(scene);
            ImGui::Text("elements \u2264 %.4g m", size);
            ImGui::SameLine();
            if (ImGui::SmallButton("\u00d7\u00bd")) {  // ×½
                setOverride(job.overrides, "interreflection.element_size", fmt::format("{:.9g}", size * 0.5));
                changed = true;
            }
            ImGui::SameLine();
            if (ImGui::SmallButton("\u00d72")) {  // ×2
                setOverride(job.overrides, "interreflection.element_size", fmt::format("{:.9g}", size * 2.0));
                changed = true;
            }
        }
    }

    if (ImGui::CollapsingHeader("Detector and display", ImGuiTreeNodeFlags_DefaultOpen)) {
        std::string pick = combo("detector", plan.detector.name, detectors_);
        if (!pick.empty()) {
            job.detector = pick;
            changed = true;
        }
        static const std::vector<std::string> adaptations = {"none", "vonkries-xyz", "vonkries", "bradford", "cat02",
                                                             "cat16"};
        pick = combo("adaptation", adaptationName(plan.settings.adaptation), adaptations);
        if (!pick.empty()) {
            job.adaptation = pick;
            changed = true;
        }
        static const std::vector<std::string> displays = {"srgb", "crt"};
        pick = combo("display", plan.settings.display, displays);
        if (!pick.empty()) {
            job.display = pick;
            changed = true;
        }
    }

    if (ImGui::CollapsingHeader("Spectra", ImGuiTreeNodeFlags_DefaultOpen)) {
        static const std::vector<std::string> modes = {"full",    "rgb",      "ac1c2:3",  "ac1c2:4",
                                                       "ac1c2:6", "ac1c2:8",  "linear:3", "linear:6",
                                                       "linear:9", "linear:12"};
        std::string pick = combo("mode", view.loaded().representation.mode.name(), modes);
        if (!pick.empty()) {
            job.mode = pick;
            changed = true;
        }
        const Grid& grid = view.grid();
        static const std::vector<double> steps = {0.5, 1, 2, 5, 10, 20, 50};
        std::vector<std::string> stepNames;
        for (double s : steps) stepNames.push_back(fmt::format("{:g} nm", s));
        pick = combo("grid step", fmt::format("{:g} nm", grid.step_nm), stepNames);
        if (!pick.empty()) {
            double step = std::stod(pick);
            job.grid = gridWithStep(grid, step);
            changed = true;
        }
        ImGui::TextDisabled("%d bands, %g–%g nm", grid.bands(), grid.start_nm, grid.end_nm);
    }
    return changed;
}

}  // namespace metamer::preview
