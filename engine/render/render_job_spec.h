// What one offline render is asked to do: the scene, the flags of `metamer render` and where
// the result goes — plain data, read by render/render_setup (loading the scene, the display plan)
// and render/render_job (running it). Tests: tests/cli_test.cpp.
#pragma once

#include "render/render_progress.h"
#include "render/spectral_plan.h"
#include "scene/scene_on_grid.h"
#include "spectral/grid.h"

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace metamer {

namespace vk {
class Context;
}

enum class Backend { Gpu, Cpu };

struct CapturedRender;  // render/render_job.h
class AtomicOutput;     // io/atomic_file.h
class StagingFolder;

// Runs once every file of a render is complete, before any is renamed into place: `files` are the
// render's files (each one's finalPath, and its tempPath where it is whole now). The folders it
// returns, with what it staged in them, are committed with the render's files, all or none (a
// sensor's capture of the cube: app/main.cpp, batch/batch.cpp). It may throw: nothing is then put
// in place.
using BeforeCommitHook = std::function<std::vector<StagingFolder*>(const std::vector<AtomicOutput*>& files)>;

struct RenderJob {
    std::filesystem::path scene;
    // The scene's text when it is not read from `scene` (the Python module's dict); `scene` still
    // names it in messages, resolves its relative paths and gives the output files their stem.
    std::optional<std::string> sceneText;
    std::filesystem::path outDir = "out";
    // The outputs' stem, <outStem>.exr, <outStem>.png, ... (-o NAME.exr); empty: the scene file's.
    std::string outStem;
    // The file -o named, by its extension (".exr", ".h5", ".hdr", ".png"; render/output_path.h):
    // the run must write it (an error naming --out otherwise), and a cube extension chooses the
    // cube's format when neither --format nor the scene's output.format does. Empty: a folder.
    std::string outExtension;
    std::optional<Grid> grid;             // --grid overrides the scene's grid (not its resampling rule)
    std::optional<Resampling> resampling; // --resample overrides the scene's grid.resample
    std::vector<std::string> overrides;   // --set KEY=VALUE
    Backend backend = Backend::Gpu;
    int ssaa = 1;
    bool half = false;
    std::string compression = "piz";  // docs/io.md, "Write speed": faster and mostly smaller than zip on renders
    CoveragePolicy coverage = CoveragePolicy::ZeroWithWarning;
    Readback readback = Readback::Auto;
    bool validation = false;  // Vulkan validation layers (also METAMER_VALIDATION=1)
    std::string device;       // also METAMER_DEVICE
    bool verbose = false;
    int frames = 1;  // render this many times; timings report the first and the median of the rest
    bool allowOutsidePaths = false;  // --allow-outside-paths: the scene may read files anywhere

    // The display path: each unset field comes from the scene's "output" block, else the default.
    std::optional<std::string> detector, adaptation, display, integration, xyz;
    std::optional<int> bits;
    // Memory the render may hold at once, bytes (0: a quarter of the machine's memory). A larger
    // image is rendered in strips and streamed to the files (GPU backend).
    size_t memoryBudget = 0;
    std::string mode = "full";  // representation mode: full, rgb, ac1c2[:N] (represent/representation.h)
    std::optional<std::vector<std::string>> write;
    // The cube is written whatever `write` (or the scene's output.write) says: a sensor's capture
    // reads it (app/main.cpp, batch/sweep.cpp). The other outputs stay as the list chooses them.
    bool writeCube = false;
    std::optional<std::vector<std::string>> format;  // --format: the cube's containers (render/outputs.h)
    // A Vulkan context to render with, owned by the caller and kept between jobs (metamer batch);
    // null: the job makes its own (validation and device then come from the fields above).
    vk::Context* context = nullptr;
    // Keep the outputs that `write` names in memory instead of writing files (outDir is not used);
    // saveCapturedRender() writes them later. Null: write the files.
    CapturedRender* capture = nullptr;
    // Called between strips and frames (render/render_progress.h: when, on which thread, and what
    // throwing from it does). Empty: none.
    RenderProgressHook progress;
    // Files written with the render's (render/render_job_spec.h, BeforeCommitHook). Empty: none.
    BeforeCommitHook beforeCommit;
    // With a hook: a GPU image of more samples (pixels × ssaa²) than this is rendered in strips of
    // about this many (whole 16-row blocks), so the hook runs at least once per strip's worth of work and a
    // stop it asks for waits for one strip, not the image (the Python binding's Ctrl-C). Strips
    // give the same values as one frame (tests/strips_test.cpp). 0: strips only over the budget.
    size_t stripPixels = 0;
};

}  // namespace metamer
