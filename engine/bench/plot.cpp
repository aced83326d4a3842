#include "bench/plot.h"

#include "core/error.h"
#include "io/image_file.h"

#include "io/oiio_module.h"
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <map>

namespace metamer {

namespace {

using Color = std::array<float, 3>;
constexpr Color kBlack{0, 0, 0}, kGrid{0.88f, 0.88f, 0.88f}, kAxisText{0.2f, 0.2f, 0.2f}, kFront{0.25f, 0.25f, 0.25f};
// Distinct hues that stay apart for the common colour-vision deficiencies (Okabe & Ito's set).
constexpr std::array<Color, 7> kPalette{{{0.00f, 0.45f, 0.70f},
                                         {0.84f, 0.37f, 0.00f},
                                         {0.00f, 0.62f, 0.45f},
                                         {0.80f, 0.47f, 0.65f},
                                         {0.90f, 0.62f, 0.00f},
                                         {0.34f, 0.71f, 0.91f},
                                         {0.50f, 0.50f, 0.50f}}};

struct Rect {
    int x0, y0, x1, y1;  // inclusive
    long area() const { return long(x1 - x0 + 1) * (y1 - y0 + 1); }
    long overlap(const Rect& o) const {
        int w = std::min(x1, o.x1) - std::max(x0, o.x0) + 1, h = std::min(y1, o.y1) - std::max(y0, o.y0) + 1;
        return w > 0 && h > 0 ? long(w) * h : 0;
    }
};

// A log10 axis mapped onto pixels [p0, p1].
struct LogAxis {
    double l0 = 0, l1 = 1;
    int p0 = 0, p1 = 1;
    double pixel(double v) const { return p0 + (std::log10(v) - l0) / (l1 - l0) * (p1 - p0); }
};

// The decades spanned by the data, padded a little so markers do not sit on the frame, and at
// least one decade wide so that a tight cluster still reads as a log scale.
void fitLog(LogAxis& a, double lo, double hi, double padLo, double padHi) {
    a.l0 = std::log10(lo) - padLo;
    a.l1 = std::log10(hi) + padHi;
    if (a.l1 - a.l0 < 1.0) {
        double mid = 0.5 * (a.l0 + a.l1);
        a.l0 = mid - 0.5;
        a.l1 = mid + 0.5;
    }
}

std::string tickLabel(double v) {
    if (v >= 1e-3 && v < 1e6) return fmt::format("{:g}", v);
    int e = int(std::floor(std::log10(v) + 1e-9));
    double m = v / std::pow(10.0, e);
    return fmt::format("{:g}e{}", std::round(m * 10) / 10, e);
}

// Ticks at 1, 2, 5 × 10^k inside the axis; labels on all of them over short ranges, else on the
// decades only (the others become unlabelled minor ticks).
struct Tick {
    double value;
    bool labelled;
};
std::vector<Tick> logTicks(const LogAxis& a) {
    std::vector<Tick> t;
    bool dense = a.l1 - a.l0 <= 2.6;
    for (int e = int(std::floor(a.l0)); e <= int(std::ceil(a.l1)); ++e)
        for (int m = 1; m <= 9; ++m) {
            double v = m * std::pow(10.0, e);
            double l = std::log10(v);
            if (l < a.l0 || l > a.l1) continue;
            bool major = m == 1 || (dense && (m == 2 || m == 5));
            t.push_back({v, major});
        }
    return t;
}

// The drawing, by OpenImageIO's ImageBufAlgo in its module (io/oiio_module: loaded only by the
// processes that draw a plot).
class Canvas {
public:
    using AX = ImageCanvas::AlignX;
    using AY = ImageCanvas::AlignY;
    Canvas(int w, int h, std::filesystem::path font) : font_(std::move(font)) {
        text_ = !font_.empty() && std::filesystem::exists(font_);
        canvas_ = makeImageCanvas(w, h, text_ ? font_ : std::filesystem::path());
        width_ = w;
        height_ = h;
    }
    bool hasText() const { return text_; }

    void line(double x0, double y0, double x1, double y1, const Color& c, int width = 1) {
        for (int k = 0; k < width; ++k) {
            int o = k - width / 2;
            bool steep = std::fabs(y1 - y0) > std::fabs(x1 - x0);
            int dx = steep ? o : 0, dy = steep ? 0 : o;
            canvas_->line(int(std::lround(x0)) + dx, int(std::lround(y0)) + dy, int(std::lround(x1)) + dx,
                          int(std::lround(y1)) + dy, c);
        }
    }
    void box(const Rect& r, const Color& c, bool fill) { canvas_->box(r.x0, r.y0, r.x1, r.y1, c, fill); }
    // The rectangle `s` would cover with its baseline's left end at (x, y).
    Rect textRect(const std::string& s, int x, int y, int size) const {
        int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
        if (!text_ || !canvas_->textBox(s, size, x0, y0, x1, y1)) return {x, y, x, y};
        return {x + x0, y + y0, x + x1, y + y1};
    }
    int textWidth(const std::string& s, int size) const {
        Rect r = textRect(s, 0, 0, size);
        return r.x1 - r.x0 + 1;
    }
    void text(const std::string& s, int x, int y, int size, const Color& c, AX ax = AX::Left, AY ay = AY::Baseline) {
        if (text_) canvas_->text(s, x, y, size, c, ax, ay);
    }
    std::vector<uint16_t> counts() const {
        const std::vector<float> f = canvas_->pixels();
        std::vector<uint16_t> out(f.size());
        for (size_t i = 0; i < f.size(); ++i) out[i] = uint16_t(std::lround(std::clamp(f[i], 0.0f, 1.0f) * 255.0f));
        return out;
    }

private:
    std::unique_ptr<ImageCanvas> canvas_;
    std::filesystem::path font_;
    bool text_ = false;
    int width_ = 0, height_ = 0;
};

}  // namespace

std::filesystem::path benchPlotFont() {
    if (const char* env = std::getenv("METAMER_FONT"); env && *env) return env;
    return "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
}

bool writeBenchPlot(const std::filesystem::path& path, const BenchResult& result, const BenchPlotOptions& options) {
    using AX = ImageCanvas::AlignX;
    using AY = ImageCanvas::AlignY;
    const int W = options.width, H = options.height;
    // Text is ASCII only: OpenImageIO 2.4's render_text draws no glyph for most non-ASCII
    // characters (Δ, ×, ≤ came out as boxes), so the plot writes dE, x and <=.
    Canvas cv(W, H, options.font);
    if (!cv.hasText())
        warn(Where{options.font.string()},
             "font not found (Debian: apt-get install fonts-dejavu-core; or set METAMER_FONT): the bench plot is "
             "drawn without text");

    // The plotted rows and their modes' colours, in order of appearance.
    std::vector<size_t> shown;
    std::vector<std::string> modes;
    std::map<std::string, Color> color;
    for (size_t i = 0; i < result.rows.size(); ++i) {
        const BenchRow& r = result.rows[i];
        std::string m = r.mode.name();
        if (!color.count(m)) {
            color[m] = kPalette[modes.size() % kPalette.size()];
            modes.push_back(m);
        }
        if (!r.skipped() && std::isfinite(r.renderMsMedian) && r.renderMsMedian > 0 && std::isfinite(r.de2000P95))
            shown.push_back(i);
    }
    auto errorOf = [&](size_t i) { return std::max(result.rows[i].de2000P95, kBenchPlotFloor); };

    const Rect plot{96, 78, W - 210, H - 72};
    LogAxis ax{0, 1, plot.x0, plot.x1}, ay{0, 1, plot.y1, plot.y0};
    if (!shown.empty()) {
        double t0 = 1e300, t1 = 0, e0 = 1e300, e1 = 0;
        for (size_t i : shown) {
            t0 = std::min(t0, result.rows[i].renderMsMedian);
            t1 = std::max(t1, result.rows[i].renderMsMedian);
            e0 = std::min(e0, errorOf(i));
            e1 = std::max(e1, errorOf(i));
        }
        // Labels sit beside and above their markers: more room on the right and at the top.
        fitLog(ax, t0, t1, 0.06, 0.18);
        fitLog(ay, e0, e1, 0.1, 0.3);
    }

    // Title and subtitle.
    cv.text(fmt::format("metamer bench: {} on {}", result.sceneName, result.device), 16, 28, 19, kBlack);
    std::string sub = fmt::format("{}x{} px, {} frames, {}; reference: full at 1 nm ({})", result.width,
                                  result.height, result.frames, result.date.substr(0, 10), result.referenceGrid.str());
    if (!result.overrides.empty()) sub += fmt::format("; --set {}", fmt::join(result.overrides, " "));
    cv.text(sub, 16, 50, 12, kAxisText);

    // Grid, ticks and their labels.
    for (const Tick& t : logTicks(ax)) {
        double x = ax.pixel(t.value);
        if (t.labelled) cv.line(x, plot.y0, x, plot.y1, kGrid);
        cv.line(x, plot.y1, x, plot.y1 + (t.labelled ? 6 : 3), kBlack);
        if (t.labelled) cv.text(tickLabel(t.value), int(x), plot.y1 + 9, 12, kBlack, AX::Center, AY::Top);
    }
    for (const Tick& t : logTicks(ay)) {
        double y = ay.pixel(t.value);
        if (t.labelled) cv.line(plot.x0, y, plot.x1, y, kGrid);
        cv.line(plot.x0 - (t.labelled ? 6 : 3), y, plot.x0, y, kBlack);
        if (t.labelled) cv.text(tickLabel(t.value), plot.x0 - 9, int(y), 12, kBlack, AX::Right, AY::Center);
    }
    cv.box(plot, kBlack, false);
    cv.text(fmt::format("time per frame, ms (log): spectral + tonemap pass, median of frames 2..{}", result.frames),
            (plot.x0 + plot.x1) / 2, H - 22, 13, kBlack, AX::Center, AY::Baseline);
    cv.text(fmt::format("dE2000 p95 against the reference (log; below {0} drawn at {0})",
                        tickLabel(kBenchPlotFloor)),
            plot.x0 - 80, plot.y0 - 10, 13, kBlack);

    // The Pareto front, under the markers.
    std::vector<size_t> front = paretoFront(result.rows);
    for (size_t k = 1; k < front.size(); ++k) {
        size_t a = front[k - 1], b = front[k];
        cv.line(ax.pixel(result.rows[a].renderMsMedian), ay.pixel(errorOf(a)), ax.pixel(result.rows[b].renderMsMedian),
                ay.pixel(errorOf(b)), kFront, 2);
    }

    // Markers: filled squares; on the front, ringed in black; at the floor, hollow.
    std::vector<Rect> occupied;
    std::vector<std::pair<int, int>> at(result.rows.size());
    for (size_t i : shown) {
        int x = int(std::lround(ax.pixel(result.rows[i].renderMsMedian))), y = int(std::lround(ay.pixel(errorOf(i))));
        at[i] = {x, y};
        const Color& c = color[result.rows[i].mode.name()];
        bool floor = !(result.rows[i].de2000P95 > kBenchPlotFloor);
        bool onFront = std::find(front.begin(), front.end(), i) != front.end();
        Rect m{x - 4, y - 4, x + 4, y + 4};
        if (floor) {
            cv.box(m, c, false);
            cv.box({m.x0 + 1, m.y0 + 1, m.x1 - 1, m.y1 - 1}, c, false);
        } else {
            cv.box(m, c, true);
        }
        if (onFront) cv.box({m.x0 - 2, m.y0 - 2, m.x1 + 2, m.y1 + 2}, kBlack, false);
        occupied.push_back({m.x0 - 2, m.y0 - 2, m.x1 + 2, m.y1 + 2});
    }

    // Labels: markers of one mode that (nearly) coincide share one ("rgb 1,2,5nm"); each label
    // goes to the first place around its marker that covers nothing else, or the least bad one.
    std::vector<bool> labelled(result.rows.size(), false);
    for (size_t i : shown) {
        if (labelled[i]) continue;
        std::vector<size_t> group{i};
        for (size_t j : shown)
            if (j != i && !labelled[j] && result.rows[j].mode.name() == result.rows[i].mode.name() &&
                std::abs(at[j].first - at[i].first) <= 14 && std::abs(at[j].second - at[i].second) <= 14)
                group.push_back(j);
        std::vector<std::string> steps;
        for (size_t j : group) {
            labelled[j] = true;
            steps.push_back(fmt::format("{:g}", result.rows[j].stepNm));
        }
        std::string label = fmt::format("{} {}nm", result.rows[i].mode.name(), fmt::join(steps, ","));
        auto [x, y] = at[i];
        int w = cv.textWidth(label, 11);
        const std::array<std::pair<int, int>, 14> offsets{{{9, 4}, {-9 - w, 4}, {-w / 2, -9}, {-w / 2, 17},
                                                           {9, -7}, {9, 15}, {-9 - w, -7}, {-9 - w, 15},
                                                           {-w / 2, -22}, {-w / 2, 30}, {9, -19}, {9, 27},
                                                           {-9 - w, -19}, {-9 - w, 27}}};
        Rect best{};
        long bestCost = -1;
        int bx = 0, by = 0;
        for (auto [dx, dy] : offsets) {
            Rect r = cv.textRect(label, x + dx, y + dy, 11);
            long cost = 0;
            for (const Rect& o : occupied) cost += r.overlap(o);
            // Outside the frame costs as much as covering something.
            Rect inside{plot.x0 + 1, plot.y0 + 1, plot.x1 - 1, plot.y1 - 1};
            cost += r.area() - r.overlap(inside);
            if (bestCost < 0 || cost < bestCost) {
                bestCost = cost;
                best = r;
                bx = x + dx;
                by = y + dy;
            }
            if (cost == 0) break;
        }
        cv.text(label, bx, by, 11, kAxisText);
        occupied.push_back(best);
    }

    // Legend, to the right of the frame.
    int lx = plot.x1 + 18, ly = plot.y0 + 8;
    cv.text("mode", lx, ly + 4, 13, kBlack);
    ly += 24;
    for (const auto& m : modes) {
        cv.box({lx, ly - 5, lx + 9, ly + 4}, color[m], true);
        cv.text(m, lx + 16, ly + 4, 12, kBlack);
        ly += 20;
    }
    ly += 6;
    cv.line(lx - 2, ly, lx + 12, ly, kFront, 2);
    cv.text("Pareto front", lx + 16, ly + 4, 12, kBlack);
    ly += 20;
    cv.box({lx - 2, ly - 7, lx + 12, ly + 6}, kBlack, false);
    cv.text("on the front", lx + 16, ly + 4, 12, kBlack);
    ly += 20;
    cv.box({lx, ly - 5, lx + 9, ly + 4}, kAxisText, false);
    cv.text(fmt::format("p95 <= {}", tickLabel(kBenchPlotFloor)), lx + 16, ly + 4, 12, kBlack);
    ly += 30;
    std::vector<std::string> skipped;
    for (const BenchRow& r : result.rows)
        if (r.skipped()) skipped.push_back(r.label());
    if (!skipped.empty()) {
        cv.text("skipped:", lx, ly, 12, kBlack);
        ly += 18;
        for (const auto& s : skipped) {
            if (ly > H - 30) {
                cv.text("...", lx, ly, 12, kAxisText);
                break;
            }
            cv.text(s, lx, ly, 11, kAxisText);
            ly += 16;
        }
    }
    ly += 12;
    cv.text(fmt::format("dE over {} px", result.comparedPixels), lx, std::min(ly, H - 40), 11, kAxisText);
    cv.text(fmt::format("with ref. Y > {:g}", kBenchMinY), lx, std::min(ly + 15, H - 25), 11, kAxisText);

    ImageFile f{W, H, {"R", "G", "B"}, {}};
    f.attributes.push_back({"ImageDescription", fmt::format("metamer bench {}: time per frame against ΔE2000 p95 on {}",
                                                            result.scene, result.device)});
    f.attributes.push_back({"oiio:ColorSpace", "sRGB"});  // its colours are sRGB counts
    writeImage(path, f, cv.counts(), 8);
    return cv.hasText();
}

}  // namespace metamer
