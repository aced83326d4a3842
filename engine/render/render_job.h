// One offline render, start to finish: scene file → spectra on the grid → GPU spectral pass (or
// the CPU reference) → tonemap (display path) → spectral EXR, display PNG, XYZ and detector
// EXRs. The `metamer render` verb is a thin shell over this; tests call it directly.
// Tests: tests/cli_test.cpp, tests/bad_inputs_test.cpp, tests/strips_test.cpp,
// tests/interrupted_run_test.cpp, the goldens (tests/golden/check.sh).
#pragma once

#include "color/tonemap.h"
#include "render/outputs.h"
#include "render/render_job_spec.h"
#include "render/spectral_pass.h"
#include "scene/scene_on_grid.h"
#include "spectral/cube.h"
#include "vk/context.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

struct LoadedScene;  // render/render_setup.h

struct StageTimings {
    double load_ms = 0, upload_ms = 0, shading_ms = 0, readback_ms = 0, tonemap_ms = 0, write_ms = 0, total_ms = 0;
    double shadow_ms = 0;  // of upload_ms: the shadow maps' depth passes (once per scene)
    double ground_truth_ms = 0;  // the ground-truth maps (render/ground_truth.h), 0 without
    // With frames > 1: the first frame's shading (includes the driver's shader compilation on
    // lavapipe) and the medians over the later frames.
    int frames = 1;
    double first_shading_ms = 0, median_shading_ms = 0, median_readback_ms = 0, median_tonemap_ms = 0;

    // The stages and their times, ms, in order — load, upload, shading, readback, tonemap,
    // ground_truth, write, total: what `metamer render --timings` prints, the Python module's timings_ms and a batch
    // job's record hold, written in this one place.
    std::vector<std::pair<const char*, double>> stages() const {
        return {{"load", load_ms},       {"upload", upload_ms}, {"shading", shading_ms}, {"readback", readback_ms},
                {"tonemap", tonemap_ms}, {"ground_truth", ground_truth_ms}, {"write", write_ms},
                {"total", total_ms}};
    }
};

// The Metamer version ("0.1.0"), as `metamer --version` and the files' metadata say it.
const char* metamerVersion();

struct RenderJobResult {
    std::vector<WrittenFile> written;
    Grid grid;
    int width = 0, height = 0;
    std::string backendDescription;  // device and plan
    // The display path without the bands (render/display_frame.h): no cube was asked for, so the
    // GPU drew the detector's channels instead of the bands.
    bool responsePass = false;
    // The display path only (no cube asked for): the response pass, or, for a scene with
    // transparent objects, the band passes and the tonemap pass.
    bool displayOnly = false;
    std::string displayDescription;  // the tonemap plan, when there is one
    std::string xyzUnits;
    StageTimings timings;
    size_t clampedToHalf = 0;
    size_t clippedPixels = 0;
    std::optional<double> cameraFitRmsDeltaE;
    uint32_t validationErrors = 0;
    std::vector<std::string> notes;  // one line each, for the user
    // The CPU threads the process was given and why (core/cpu_count.h): what the pools, OpenEXR and
    // lavapipe were sized by.
    int threads = 0;
    std::string threadsSource;
};

// The memory a render allocates that grows with the image, in bytes: what is checked against
// kMaxRenderMemory before anything is allocated, so that an absurd size (a 16384² camera on a
// 0.5 nm grid) is refused with the estimate rather than failing in the allocator or swapping the
// machine to a halt, and — for one row — what decides the strip height of an image over the
// memory budget. Deliberately simple and on the high side: it counts what the render path
// allocates per pixel and ignores what does not grow with the image (meshes, spectra, shaders).
struct RenderMemory {
    uint64_t cube = 0;     // the spectral cube on the host: W·H·bands floats
    uint64_t target = 0;   // GPU: the layered RGBA32F spectral target at the ssaa size, its depth
                           // buffer and (when it cannot be mapped) a readback buffer of the same size
    uint64_t display = 0;  // the display path: tonemap attachments and readback (GPU) and the
                           // display image (responses up to 8 channels, XYZ, counts, clip mask)
    uint64_t total() const { return cube + target + display; }
    std::string describe() const;  // "41.2 GiB (cube 31.0 GiB, GPU target 10.1 GiB, display 0.1 GiB)"
};

// 64 GiB: more than a workstation can give one render (a 4096 × 4096 image on the default
// 89-band grid needs about 12 GiB on the GPU path; 16384 × 16384 would need about 130 GiB).
constexpr uint64_t kMaxRenderMemory = uint64_t(64) << 30;
// The GPU path streams images over the memory budget in strips; what it refuses is a cube file
// beyond 64 GiB (8192² on the default grid is 22 GiB; 16384² would be 89 GiB).
constexpr uint64_t kMaxStreamedCube = uint64_t(64) << 30;

// `cube`: whether the render holds the bands; a GPU render without (display outputs only: the
// response pass) has a target of at most TONEMAP_MAX_CHANNELS channels and no cube.
RenderMemory estimateRenderMemory(int width, int height, int bands, int ssaa, Backend backend, bool display,
                                  bool cube = true);

// Merges defaults < the scene's output block < the job's flags; names are checked here, with the
// scene file and key (or the flag) in the error.
TonemapSettings tonemapSettings(const RenderJob& job, const Scene& scene, OutputFiles* files);

RenderJobResult runRenderJob(const RenderJob& job);

// A render held in memory (RenderJob::capture): the arrays, and what writing them as the files of
// `metamer render` needs — the scene on its grid (the representation and, for a custom detector's
// quick look, the library), the display plan and each file's provenance.
struct CapturedRender {
    CapturedOutputs outputs;
    Grid grid;
    std::string stem;  // the scene file's stem: <stem>.exr, <stem>.png, ...
    std::shared_ptr<const LoadedScene> loaded;
    std::optional<TonemapPlan> plan;
    Attributes provenance;
    OutputOptions options;
};

// Writes a captured render's outputs into `dir` under the names, and with the contents and
// attributes, that `metamer render --write` gives them (atomically, every file or none renamed
// into place at the end).
std::vector<WrittenFile> saveCapturedRender(const CapturedRender& render, const std::filesystem::path& dir);

}  // namespace metamer
