// One offline render, start to finish: scene file → spectra on the grid → GPU spectral pass (or
// the CPU reference) → spectral EXR + quick-look PNG. The `metamer render` verb is a thin shell
// over this; tests call it directly.
#pragma once

#include "render/spectral_pass.h"
#include "scene/scene_on_grid.h"
#include "spectral/cube.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace metamer {

enum class Backend { Gpu, Cpu };

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
    bool quickLook = true;
    bool validation = false;  // Vulkan validation layers (also METAMER_VALIDATION=1)
    std::string device;       // also METAMER_DEVICE
    bool verbose = false;
    int frames = 1;  // render this many times; timings report the first and the median of the rest
};

struct StageTimings {
    double load_ms = 0, upload_ms = 0, shading_ms = 0, readback_ms = 0, write_ms = 0, total_ms = 0;
    // With frames > 1: the first frame's shading (includes the driver's shader compilation on
    // lavapipe) and the medians over the later frames.
    int frames = 1;
    double first_shading_ms = 0, median_shading_ms = 0, median_readback_ms = 0;
};

struct RenderJobResult {
    std::filesystem::path cubePath, pngPath;
    Grid grid;
    int width = 0, height = 0;
    std::string backendDescription;  // device and plan
    StageTimings timings;
    size_t clampedToHalf = 0;
    uint32_t validationErrors = 0;
};

RenderJobResult runRenderJob(const RenderJob& job);

}  // namespace metamer
