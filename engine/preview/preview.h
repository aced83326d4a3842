// `metamer preview`: the interactive spectral preview (docs/preview.md). A GLFW window shows the
// display image made by the same spectral pass and tonemap pass as `metamer render`, with live
// controls (lights, detector, adaptation, display, mode, grid step, camera), a pixel probe with a
// pinned second probe, a split view of the scene under two settings, saving, and reloading of the
// scene file when it changes. With frames > 0 it runs a fixed number of frames without waiting
// for input and reports frame times: the scripted path the tests use under Xvfb.
// Tests: engine/preview/preview_settings_test.cpp, tests/preview_test.sh.
#pragma once

#include "render/render_job.h"

#include <glm/glm.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace metamer::preview {

struct PreviewOptions {
    RenderJob job;  // the (left) view: scene, --set, --grid, --mode, --detector, --adapt, --display, ...
    // --split SETTING=VALUE: a second view, right of the first, with these changes on top of the
    // first's: detector=, adapt=, display=, mode=, grid= set those; any other KEY=VALUE is a --set.
    std::vector<std::string> split;
    int frames = 0;  // > 0: render this many frames (each one re-rendered), report, close
    std::filesystem::path screenshot;        // the view region(s) of the last frame, as shown (PNG)
    std::filesystem::path windowScreenshot;  // the whole window of the last frame, UI included (PNG)
    std::filesystem::path outDir = "out";    // where Save writes
    bool saveAtEnd = false;                  // --save: save the views' cubes and PNGs when closing
    std::optional<glm::ivec2> probe;         // --probe X,Y: the probe as if the cursor were there
    std::optional<glm::ivec2> pin;           // --pin X,Y: the pinned probe
    bool watch = true;                       // reload the scene file when it changes on disk
};

struct PreviewReport {
    std::string device, presentMode, views;  // one line each
    int width = 0, height = 0, bands = 0;    // of the (left) view
    int frames = 0;
    // Wall-clock milliseconds. The first frame includes the driver's shader compilation; the
    // medians are over the later frames (frames > 1). "frame" is one whole loop iteration: UI,
    // shading and tonemap of every view, the probe's cube read-back (when a probe is shown),
    // copying into the swapchain, drawing the UI and presenting.
    double first_ms = 0, median_ms = 0, medianShading_ms = 0, medianTonemap_ms = 0, medianProbe_ms = 0,
           medianPresent_ms = 0;
    double build_ms = 0;  // making the views at the start: what a light, mode or grid change costs
    std::vector<std::string> probes;  // describeProbe() lines, at the end
    std::vector<std::pair<std::filesystem::path, std::string>> written;
    std::vector<std::string> notes;
    uint32_t validationErrors = 0;
};

PreviewReport runPreview(const PreviewOptions& options);

// The right view's job: `left` with the --split settings applied (input errors name --split).
RenderJob splitJob(const RenderJob& left, const std::vector<std::string>& split);

// Parses "X,Y" (a pixel) for --probe and --pin.
glm::ivec2 parsePixel(const std::string& text, const std::string& flag);

}  // namespace metamer::preview
