// `metamer bench`: the measured speed/accuracy trade of the representation modes and spectral
// steps on one scene (docs/speed-vs-accuracy.md). Every configuration (mode × step) is rendered
// on the GPU exactly as `metamer render` would: its display image as `--write png` makes it (the
// response pass + tonemap pass, render/display_frame.h) and its cube as `--write cube` does (every
// band, then the tonemap pass over them), each timed over several frames, and compared with the
// reference — full spectral at 1 nm over the scene's grid range — in ΔE2000 and, for spectral
// modes, in spectral RMSE.
#pragma once

#include "represent/representation.h"
#include "spectral/grid.h"
#include "vk/context.h"

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

// The sweep's defaults: the four modes the paper's argument needs and steps from the reference's
// 1 nm to a coarse 20 nm.
std::vector<Mode> defaultBenchModes();
std::vector<double> defaultBenchSteps();

struct BenchConfig {
    std::vector<Mode> modes = defaultBenchModes();
    std::vector<double> steps = defaultBenchSteps();
    int frames = 5;  // per configuration; the first pays shader compilation and is reported apart
    std::optional<std::pair<int, int>> size;  // width, height; default the scene's camera
    std::vector<std::string> overrides;        // --set KEY=VALUE, applied to every configuration
};

// One configuration. Numbers a configuration does not have are NaN (skipped rows: all of them;
// non-spectral modes: spectralRmseRelative).
struct BenchRow {
    Mode mode;
    double stepNm = 0;
    std::string grid;   // "380:780:5": the grid the configuration's spectra were sampled on
    int channels = 0;   // what the renderer carries per pixel: bands, or the mode's channels
    double renderMsMedian = 0;  // a display frame: response pass + tonemap pass, median over frames 2..N
    double renderMsFirst = 0;   // the same for frame 1 (includes the driver's shader compilation)
    double cubeMsMedian = 0;    // a cube frame: every band + the tonemap pass over them, median over 2..N
    double runMs = 0;           // resample, represent, plan, upload, every frame of both
    double de2000Mean = 0, de2000P95 = 0, de2000Max = 0;  // against the reference, lit pixels
    double spectralRmseRelative = 0;  // RMSE of the cube against the 1 nm reference on its bands / mean
    std::string skippedReason;        // non-empty: the configuration could not run (input error)

    bool skipped() const { return !skippedReason.empty(); }
    std::string label() const;  // "ac1c2:4 5nm"
};

struct BenchResult {
    std::string scene;       // as given
    std::string sceneName;   // the file's stem, used in output names
    std::string device;      // the Vulkan device's name
    std::string machine;     // OS, kernel, CPU count
    std::string date;        // UTC, ISO 8601
    int frames = 0;
    int width = 0, height = 0;
    Grid referenceGrid;      // full at 1 nm
    std::vector<std::string> overrides;
    size_t comparedPixels = 0;  // pixels where the reference has Y > kBenchMinY
    std::vector<std::string> notes;  // one line each, for the user (grids shortened, …)
    std::vector<BenchRow> rows;
};

// ΔE2000 and spectral RMSE are taken over pixels whose reference Y (white = 100) exceeds this:
// the background is black in every mode and would only dilute the statistics.
constexpr double kBenchMinY = 0.01;

// Runs the sweep: the reference first, then every mode × step (mode-major), reporting each on
// `progress` ("[4/20] ac1c2:4 at 5 nm: 123 ms, ΔE00 p95 0.8"). A configuration that fails with an
// input error (e.g. an AC1C2 sample outside a coarse grid) becomes a skipped row; errors of the
// scene itself, of the reference or of the device are thrown.
BenchResult runBench(const std::filesystem::path& scene, const BenchConfig& config, vk::Context& ctx,
                     std::function<void(const std::string&)> progress = {});

// Indices of the rows no other row beats in both median time and ΔE2000 p95 (beating = no worse
// in both and better in one; equal rows do not beat each other), in order of increasing time.
// Skipped rows and rows without finite numbers are never on the front.
std::vector<size_t> paretoFront(const std::vector<BenchRow>& rows);

// DIR/<scene>.bench.csv: '#' lines with the machine, device, date, frames and size, then the
// header mode,step_nm,grid,channels,render_ms_median,render_ms_first,cube_ms_median,run_ms,
// de2000_mean,de2000_p95,de2000_max,spectral_rmse_relative,skipped_reason and one row per
// configuration.
void writeBenchCsv(const std::filesystem::path& path, const BenchResult& result);
// The same as JSON (missing numbers are null), with the Pareto front's rows marked.
void writeBenchJson(const std::filesystem::path& path, const BenchResult& result);

}  // namespace metamer
