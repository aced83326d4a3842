// One offline render, start to finish: scene file → spectra on the grid → GPU spectral pass (or
// the CPU reference) → tonemap (display path) → spectral EXR, display PNG, XYZ and detector
// EXRs. The `metamer render` verb is a thin shell over this; tests call it directly.
#pragma once

#include "color/tonemap.h"
#include "render/spectral_pass.h"
#include "scene/scene_on_grid.h"
#include "spectral/cube.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace metamer {

enum class Backend { Gpu, Cpu };

// What a render writes (`--write`, or the scene's output.write).
struct OutputFiles {
    bool cube = true;        // <scene>.exr: the spectral radiance cube
    bool png = true;         // <scene>.png: the display image (counts)
    bool xyz = false;        // <scene>.xyz.exr: XYZ as the detector sees it
    bool responses = false;  // <scene>.<detector>.exr: raw detector responses
    bool edges = false;      // <scene>.edges.png: 255 where a pixel's 3×3 neighbourhood sees more
                             // than one surface (CPU backend only: the goldens' comparison mask)
};

struct RenderJob {
    std::filesystem::path scene;
    std::filesystem::path outDir = "out";
    std::optional<Grid> grid;             // --grid overrides the scene's grid
    std::vector<std::string> overrides;   // --set KEY=VALUE
    Backend backend = Backend::Gpu;
    int ssaa = 1;
    bool half = false;
    std::string compression = "zip";
    CoveragePolicy coverage = CoveragePolicy::ZeroWithWarning;
    Readback readback = Readback::Auto;
    bool validation = false;  // Vulkan validation layers (also METAMER_VALIDATION=1)
    std::string device;       // also METAMER_DEVICE
    bool verbose = false;
    int frames = 1;  // render this many times; timings report the first and the median of the rest

    // The display path: each unset field comes from the scene's "output" block, else the default.
    std::optional<std::string> detector, adaptation, display, integration, xyz;
    std::optional<int> bits;
    std::string mode = "full";  // representation mode: full, rgb, ac1c2[:N] (represent/representation.h)
    std::optional<std::vector<std::string>> write;
};

struct StageTimings {
    double load_ms = 0, upload_ms = 0, shading_ms = 0, readback_ms = 0, tonemap_ms = 0, write_ms = 0, total_ms = 0;
    // With frames > 1: the first frame's shading (includes the driver's shader compilation on
    // lavapipe) and the medians over the later frames.
    int frames = 1;
    double first_shading_ms = 0, median_shading_ms = 0, median_readback_ms = 0;
};

struct WrittenFile {
    std::filesystem::path path;
    std::string what;  // one line: the quantity and its units
};

struct RenderJobResult {
    std::vector<WrittenFile> written;
    Grid grid;
    int width = 0, height = 0;
    std::string backendDescription;  // device and plan
    std::string displayDescription;  // the tonemap plan, when there is one
    std::string xyzUnits;
    StageTimings timings;
    size_t clampedToHalf = 0;
    size_t clippedPixels = 0;
    std::optional<double> cameraFitRmsDeltaE;
    uint32_t validationErrors = 0;
    std::vector<std::string> notes;  // one line each, for the user
};

// Merges defaults < the scene's output block < the job's flags; names are checked here, with the
// scene file and key (or the flag) in the error.
TonemapSettings tonemapSettings(const RenderJob& job, const Scene& scene, OutputFiles* files);

RenderJobResult runRenderJob(const RenderJob& job);

}  // namespace metamer
