// Images larger than memory: the GPU path renders the image in horizontal strips and streams each
// strip's rows to the outputs (render/outputs: spectral EXR, display PNG, XYZ and response EXRs),
// so peak memory is a strip's, not the image's. Without a cube to write, the strips are drawn by
// the display path that never writes the bands (render/display_frame.h). render/render_job.cpp decides when (the memory
// estimate against --memory-budget) and hands the prepared job over. Tests: tests/strips_test.cpp.
#pragma once

#include "color/tonemap.h"
#include "render/outputs.h"
#include "render/spectral_pass.h"
#include "represent/representation.h"
#include "scene/scene.h"
#include "spectral/library.h"
#include "vk/context.h"

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

// The machine's default budget: a quarter of its memory (core/memory_limits.h machineMemoryBytes:
// physical memory, or the cgroup's limit when lower).
size_t defaultMemoryBudget();

struct StripJob {
    const Scene* scene = nullptr;
    const SceneOnGrid* rendered = nullptr;        // in the mode's channels
    const Representation* representation = nullptr;
    const TonemapPlan* plan = nullptr;            // null: no display outputs
    vk::Context* context = nullptr;
    int stripRows = 0;
    int ssaa = 1;
    Readback readback = Readback::Auto;
    RenderOutputs* outputs = nullptr;             // where every strip's rows go
    // After every strip, with the strips done and their total (and once with 0 before the
    // first); may throw to stop (render/render_progress.h). Empty: none.
    std::function<void(int done, int total)> afterStrip;
};

struct StripResult {
    int strips = 0;
    size_t clippedPixels = 0;
    double shading_ms = 0, tonemap_ms = 0, readback_ms = 0;
    bool responsePass = false;  // display outputs only, and the bands were never drawn
    bool displayOnly = false;   // display outputs only (the response pass, or bands with transparent objects)
    std::string description;  // device and plan
};

StripResult renderInStrips(const StripJob& job);

}  // namespace metamer
