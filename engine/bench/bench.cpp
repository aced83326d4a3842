#include "bench/bench.h"

#include "core/cpu_count.h"

#include "color/delta_e.h"
#include "color/lab.h"
#include "color/tonemap.h"
#include "core/csv_text.h"
#include "core/json.h"
#include "core/statistics.h"
#include "core/timing.h"
#include "io/atomic_file.h"
#include "render/render_setup.h"
#include "render/spectral_pass.h"
#include "render/display_frame.h"
#include "render/tonemap_pass.h"
#include "scene/scene_json.h"
#include "scene/scene_on_grid.h"
#include "spectral/library.h"
#include "spectral/resampling.h"

#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <sys/utsname.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <limits>
#include <set>
#include <thread>

namespace metamer {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Every configuration resamples the same scene, so its coverage warnings would repeat once per
// configuration; each distinct line is passed on once per sweep.
WarningSink gOuterSink = nullptr;
std::set<std::string>* gSeenWarnings = nullptr;
void onceSink(const std::string& line) {
    if (!gSeenWarnings->insert(line).second) return;
    if (gOuterSink) gOuterSink(line);
    else std::fprintf(stderr, "%s\n", line.c_str());
}
struct WarnOnce {
    std::set<std::string> seen;
    WarnOnce() {
        gSeenWarnings = &seen;
        gOuterSink = setWarningSink(onceSink);
    }
    ~WarnOnce() {
        setWarningSink(gOuterSink);
        gSeenWarnings = nullptr;
    }
};

// The grid of one step over the scene's range: the scene's start, and the last whole step that
// does not pass the scene's end.
Grid stepGrid(const Grid& range, double step) {
    double k = std::floor((range.end_nm - range.start_nm) / step + 1e-9);
    Grid g = range;
    g.end_nm = range.start_nm + std::max(0.0, k) * step;
    g.step_nm = step;
    g.validate(Where{"", "--steps"});
    return g;
}

std::string machineDescription() {
    std::string os;
    std::ifstream release("/etc/os-release");
    for (std::string line; std::getline(release, line);)
        if (line.rfind("PRETTY_NAME=", 0) == 0) {
            os = line.substr(12);
            os.erase(std::remove(os.begin(), os.end(), '"'), os.end());
        }
    utsname u{};
    std::string kernel = uname(&u) == 0 ? fmt::format("{} {}, {}", u.sysname, u.release, u.machine) : "";
    std::vector<std::string> parts;
    for (const auto& p : {os, kernel})
        if (!p.empty()) parts.push_back(p);
    parts.push_back(fmt::format("{} CPUs, {} threads", std::thread::hardware_concurrency(), usableCpuCount()));
    return fmt::format("{}", fmt::join(parts, ", "));
}

std::string utcNow() {
    std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

// One configuration rendered and timed; what the accuracy measures need is kept.
struct Run {
    BenchRow row;
    DisplayImage image;
    SpectralCube cube;       // spectral modes only
    glm::dvec3 white{0.0};   // the plan's reference white, relative XYZ (Y = 1)
};

Run runConfiguration(vk::Context& ctx, const Scene& scene, const SpectrumLibrary& library, const Mode& mode,
                     const Grid& grid, int frames) {
    Run run;
    run.row.mode = mode;
    run.row.stepNm = grid.step_nm;
    run.row.grid = grid.str();
    auto start = Clock::now();
    SceneOnGrid spectra = resampleScene(scene, grid);
    // linear:K analyses the scene's own spectra; the other modes ignore them.
    Representation representation = makeRepresentation(mode, grid, library, &spectra);
    SceneOnGrid rendered = represent(spectra, representation, scene);
    run.row.channels = representation.channels();
    // The defaults of `metamer render`: CIE 1931, Bradford, sRGB. The XYZ compared is taken
    // before adaptation, so only the detector matters for accuracy; the rest is real work timed.
    TonemapPlan plan = makeScenePlan(TonemapSettings{}, scene, spectra, library, &representation);
    run.white = plan.sourceWhiteXyz;
    // With one frame there is nothing after the first: its time stands for the median.
    auto laterMedian = [](const std::vector<double>& ms) { return ms.size() > 1 ? median({ms.begin() + 1, ms.end()}) : ms[0]; };
    std::vector<double> ms;
    {
        // The display image as `metamer render --write png,xyz` makes it.
        DisplayFrame frame(ctx, scene, rendered, plan, {}, TonemapOutputs{true, true, false});
        for (int f = 0; f < std::max(1, frames); ++f) {
            run.image = frame.render();
            ms.push_back(frame.timings().shading_ms + frame.timings().tonemap_ms);
        }
    }
    run.row.renderMsFirst = ms[0];
    run.row.renderMsMedian = laterMedian(ms);
    // The cube path: every band, and the display path over them (`--write cube,png`).
    SpectralPassOptions options;
    options.sampled = true;
    SpectralPass pass(ctx, scene, rendered, options);
    TonemapPass tonemap(ctx, pass, plan, TonemapOutputs{true, true, false});
    std::vector<double> cubeMs;
    for (int f = 0; f < std::max(1, frames); ++f) {
        pass.draw();
        const double shading = pass.timings().shading_ms;
        tonemap.render();
        cubeMs.push_back(shading + tonemap.lastMs());
    }
    run.row.cubeMsMedian = laterMedian(cubeMs);
    run.row.runMs = msSince(start);
    if (mode.spectral()) {
        // Outside the timing: only the RMSE needs the cube. linear:K's pixels are their projections
        // onto the basis (Peercy's result; the display path gets the same through projected
        // detector weights, so the timed frames need no projection).
        pass.readback(run.cube);
        projectCube(representation, run.cube.data, run.cube.bands());
    }
    return run;
}

glm::dvec3 xyzAt(const DisplayImage& d, size_t i) { return {d.xyz[3 * i], d.xyz[3 * i + 1], d.xyz[3 * i + 2]}; }

// The reference, prepared once: its lit pixels, their CIELAB, and its white.
struct Reference {
    std::vector<size_t> pixels;   // reference Y > kBenchMinY
    std::vector<glm::dvec3> lab;  // per entry of `pixels`
    glm::dvec3 white;             // Y = 100
    const SpectralCube* cube = nullptr;
};

void measureDeltaE(BenchRow& row, const DisplayImage& image, const Reference& ref) {
    if (ref.pixels.empty()) {
        row.de2000Mean = row.de2000P95 = row.de2000Max = kNaN;
        return;
    }
    std::vector<double> de(ref.pixels.size());
    double sum = 0;
    for (size_t k = 0; k < ref.pixels.size(); ++k) {
        de[k] = deltaE2000(xyzToLab(xyzAt(image, ref.pixels[k]), ref.white), ref.lab[k]);
        sum += de[k];
    }
    row.de2000Mean = sum / double(de.size());
    row.de2000Max = *std::max_element(de.begin(), de.end());
    row.de2000P95 = percentile(std::move(de), 0.95);
}

// The 1 nm reference is compared with a coarser cube on the coarse cube's bands: the reference's
// band values taken as data and put on the coarse grid by the grid's own rule (spectral/resampling.h),
// as the coarse render put every input spectrum there. At 1 nm this is the identity.
double spectralRmseRelative(const SpectralCube& cube, const Reference& ref) {
    if (ref.pixels.empty()) return kNaN;
    const BandWeights avg = bandWeights(ref.cube->grid.wavelengths(), cube.grid);
    double sq = 0, sum = 0;
    for (size_t p : ref.pixels) {
        const float* c = cube.data.data() + p * size_t(cube.bands());
        const float* r = ref.cube->data.data() + p * size_t(ref.cube->bands());
        for (int b = 0; b < cube.bands(); ++b) {
            double v = 0;
            const auto& w = avg.weights[size_t(b)];
            for (size_t k = 0; k < w.size(); ++k) v += w[k] * r[size_t(avg.first[size_t(b)]) + k];
            double d = c[b] - v;
            sq += d * d;
            sum += v;
        }
    }
    double n = double(ref.pixels.size()) * cube.bands();
    return sum > 0 ? std::sqrt(sq / n) / (sum / n) : kNaN;
}

std::string fmtNumber(double v) { return std::isfinite(v) ? fmt::format("{:.6g}", v) : ""; }



}  // namespace

std::vector<Mode> defaultBenchModes() {
    return {Mode{ModeKind::Full, 0}, Mode{ModeKind::Rgb, 0}, Mode{ModeKind::Ac1c2, 4}, Mode{ModeKind::Ac1c2, 8}};
}

std::vector<double> defaultBenchSteps() { return {1, 2, 5, 10, 20}; }

std::string BenchRow::label() const { return fmt::format("{} {:g}nm", mode.name(), stepNm); }

BenchResult runBench(const std::filesystem::path& scenePath, const BenchConfig& config, vk::Context& ctx,
                     std::function<void(const std::string&)> progress) {
    auto say = [&](const std::string& line) {
        if (progress) progress(line);
    };
    if (config.modes.empty()) failInput(Where{"", "--modes"}, "no representation mode to measure");
    if (config.steps.empty()) failInput(Where{"", "--steps"}, "no spectral step to measure");
    if (config.frames < 1) failInput(Where{"", "--frames"}, "{} frames; at least 1 is needed", config.frames);
    for (double s : config.steps)
        if (!(s >= Grid::kMinStep && s <= Grid::kMaxStep))
            failInput(Where{"", "--steps"}, "step {:g} nm is outside {:g}..{:g} nm", s, Grid::kMinStep,
                      Grid::kMaxStep);

    WarnOnce warnOnce;
    BenchResult result;
    result.scene = scenePath.string();
    result.sceneName = scenePath.stem().string();
    result.device = ctx.deviceInfo().name;
    result.machine = machineDescription();
    result.date = utcNow();
    result.frames = config.frames;
    result.overrides = config.overrides;

    SpectrumLibrary library;
    std::vector<std::string> overrides = config.overrides;
    if (config.size) {
        overrides.push_back(fmt::format("camera.width={}", config.size->first));
        overrides.push_back(fmt::format("camera.height={}", config.size->second));
    }
    Scene scene = loadScene(scenePath, library, overrides);
    result.width = scene.camera.width;
    result.height = scene.camera.height;
    const Grid range = scene.grid;

    // The reference: full spectral at 1 nm over the scene's range.
    result.referenceGrid = stepGrid(range, 1.0);
    std::set<double> noted;
    auto noteShortened = [&](const Grid& g) {
        if (std::fabs(g.end_nm - range.end_nm) < 1e-9 || !noted.insert(g.step_nm).second) return;
        std::string note = fmt::format("step {:g} nm does not divide the scene's range {:g}..{:g} nm: its grid is {} "
                                       "(end = start + a whole number of steps)",
                                       g.step_nm, range.start_nm, range.end_nm, g.str());
        result.notes.push_back(note);
        say("note: " + note);
    };
    noteShortened(result.referenceGrid);
    Run refRun = runConfiguration(ctx, scene, library, Mode{}, result.referenceGrid, config.frames);
    Reference ref;
    ref.white = refRun.white * 100.0;
    ref.cube = &refRun.cube;
    for (size_t i = 0; i < size_t(refRun.image.width) * refRun.image.height; ++i)
        if (refRun.image.xyz[3 * i + 1] > kBenchMinY) {
            ref.pixels.push_back(i);
            ref.lab.push_back(xyzToLab(xyzAt(refRun.image, i), ref.white));
        }
    result.comparedPixels = ref.pixels.size();
    if (ref.pixels.empty())
        result.notes.push_back(fmt::format("no pixel of the reference has Y > {:g}: nothing to compare", kBenchMinY));
    say(fmt::format("[ref] full at 1 nm ({}, {} bands, {}×{}): {:.1f} ms per frame, {:.0f} ms in all; {} lit pixels "
                    "compared",
                    result.referenceGrid.str(), refRun.row.channels, result.width, result.height,
                    refRun.row.renderMsMedian, refRun.row.runMs, ref.pixels.size()));

    const size_t total = config.modes.size() * config.steps.size();
    size_t n = 0;
    for (const Mode& mode : config.modes) {
        for (double step : config.steps) {
            ++n;
            BenchRow row;
            row.mode = mode;
            row.stepNm = step;
            try {
                Grid grid = stepGrid(range, step);
                row.grid = grid.str();
                noteShortened(grid);
                if (mode.spectral() && grid == result.referenceGrid) {
                    // The reference itself: measured already, and exact by definition.
                    row = refRun.row;
                    row.de2000Mean = row.de2000P95 = row.de2000Max = ref.pixels.empty() ? kNaN : 0.0;
                    row.spectralRmseRelative = ref.pixels.empty() ? kNaN : 0.0;
                } else {
                    Run run = runConfiguration(ctx, scene, library, mode, grid, config.frames);
                    row = run.row;
                    measureDeltaE(row, run.image, ref);
                    row.spectralRmseRelative = mode.spectral() ? spectralRmseRelative(run.cube, ref) : kNaN;
                }
            } catch (const Error& e) {
                if (e.code() != ExitCode::BadInput) throw;
                row.skippedReason = e.text();
                row.channels = 0;
                row.renderMsMedian = row.renderMsFirst = row.cubeMsMedian = row.runMs = kNaN;
                row.de2000Mean = row.de2000P95 = row.de2000Max = row.spectralRmseRelative = kNaN;
            }
            std::string head = fmt::format("[{}/{}] {} at {:g} nm", n, total, mode.name(), step);
            if (row.skipped()) say(fmt::format("{}: skipped: {}", head, row.skippedReason));
            else
                say(fmt::format("{}: {:.1f} ms, ΔE00 p95 {:.3g}{}", head, row.renderMsMedian, row.de2000P95,
                                std::isfinite(row.spectralRmseRelative)
                                    ? fmt::format(", spectral RMSE {:.3g}", row.spectralRmseRelative)
                                    : ""));
            result.rows.push_back(std::move(row));
        }
    }
    return result;
}

std::vector<size_t> paretoFront(const std::vector<BenchRow>& rows) {
    auto usable = [](const BenchRow& r) {
        return !r.skipped() && std::isfinite(r.renderMsMedian) && std::isfinite(r.de2000P95);
    };
    std::vector<size_t> front;
    for (size_t i = 0; i < rows.size(); ++i) {
        if (!usable(rows[i])) continue;
        const BenchRow& a = rows[i];
        bool beaten = false;
        for (size_t j = 0; j < rows.size() && !beaten; ++j) {
            if (j == i || !usable(rows[j])) continue;
            const BenchRow& b = rows[j];
            beaten = b.renderMsMedian <= a.renderMsMedian && b.de2000P95 <= a.de2000P95 &&
                     (b.renderMsMedian < a.renderMsMedian || b.de2000P95 < a.de2000P95);
        }
        if (!beaten) front.push_back(i);
    }
    std::stable_sort(front.begin(), front.end(), [&](size_t x, size_t y) {
        if (rows[x].renderMsMedian != rows[y].renderMsMedian) return rows[x].renderMsMedian < rows[y].renderMsMedian;
        return rows[x].de2000P95 > rows[y].de2000P95;
    });
    return front;
}

void writeBenchCsv(const std::filesystem::path& path, const BenchResult& r) {
    std::string s;
    s += fmt::format("# metamer bench {}{}\n", r.scene,
                     r.overrides.empty() ? "" : fmt::format(" --set {}", fmt::join(r.overrides, " --set ")));
    s += fmt::format("# device: {}; machine: {}; date: {}\n", r.device, r.machine, r.date);
    s += fmt::format("# frames: {}; size: {}x{}; reference: full at 1 nm on {}; ΔE2000 and RMSE over {} pixels "
                     "with reference Y > {:g}; times in ms\n",
                     r.frames, r.width, r.height, r.referenceGrid.str(), r.comparedPixels, kBenchMinY);
    for (const auto& note : r.notes) s += "# note: " + note + "\n";
    s += "mode,step_nm,grid,channels,render_ms_median,render_ms_first,cube_ms_median,run_ms,de2000_mean,de2000_p95,"
         "de2000_max,spectral_rmse_relative,skipped_reason\n";
    for (const BenchRow& row : r.rows) {
        s += fmt::format("{},{:g},{},{},{},{},{},{},{},{},{},{},{}\n", row.mode.name(), row.stepNm, row.grid,
                         row.skipped() ? "" : std::to_string(row.channels), fmtNumber(row.renderMsMedian),
                         fmtNumber(row.renderMsFirst), fmtNumber(row.cubeMsMedian), fmtNumber(row.runMs),
                         fmtNumber(row.de2000Mean),
                         fmtNumber(row.de2000P95), fmtNumber(row.de2000Max), fmtNumber(row.spectralRmseRelative),
                         csvQuoted(row.skippedReason));
    }
    writeFileAtomically(path, s);
}

void writeBenchJson(const std::filesystem::path& path, const BenchResult& r) {
    std::vector<size_t> front = paretoFront(r.rows);
    nlohmann::ordered_json j;
    j["scene"] = r.scene;
    j["overrides"] = r.overrides;
    j["device"] = r.device;
    j["machine"] = r.machine;
    j["date"] = r.date;
    j["frames"] = r.frames;
    j["width"] = r.width;
    j["height"] = r.height;
    j["reference"] = {{"mode", "full"}, {"grid", r.referenceGrid.str()}};
    j["display"] = "cie1931, bradford, srgb; XYZ before adaptation, CIELAB relative to the reference white (Y = 100)";
    j["compared_pixels"] = r.comparedPixels;
    j["compared_where"] = fmt::format("reference Y > {:g}", kBenchMinY);
    j["timing"] = "render_ms: a display frame, the response pass (the detector's channels, no bands) + the tonemap "
                  "pass (submit to fence, with counts and XYZ read back), median over frames 2..N; cube_ms: a cube "
                  "frame, every band + the tonemap pass over them, median over frames 2..N; run_ms: resample, "
                  "represent, plan, upload and all frames of both";
    j["notes"] = r.notes;
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (size_t i = 0; i < r.rows.size(); ++i) {
        const BenchRow& row = r.rows[i];
        nlohmann::ordered_json o;
        o["mode"] = row.mode.name();
        o["step_nm"] = row.stepNm;
        o["grid"] = row.grid;
        o["channels"] = row.skipped() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(row.channels);
        o["render_ms_median"] = jsonNumber(row.renderMsMedian);
        o["render_ms_first"] = jsonNumber(row.renderMsFirst);
        o["cube_ms_median"] = jsonNumber(row.cubeMsMedian);
        o["run_ms"] = jsonNumber(row.runMs);
        o["de2000_mean"] = jsonNumber(row.de2000Mean);
        o["de2000_p95"] = jsonNumber(row.de2000P95);
        o["de2000_max"] = jsonNumber(row.de2000Max);
        o["spectral_rmse_relative"] = jsonNumber(row.spectralRmseRelative);
        o["skipped_reason"] = row.skipped() ? nlohmann::ordered_json(row.skippedReason) : nlohmann::ordered_json(nullptr);
        o["pareto"] = std::find(front.begin(), front.end(), i) != front.end();
        rows.push_back(std::move(o));
    }
    j["rows"] = std::move(rows);
    j["pareto_front"] = front;
    writeFileAtomically(path, j.dump(2) + "\n");
}

}  // namespace metamer
