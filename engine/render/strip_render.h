// Images larger than memory: the GPU path renders the image in horizontal strips and streams each
// strip's rows to the output files (spectral EXR, display PNG, XYZ and response EXRs), so peak
// memory is a strip's, not the image's. render/render_job.cpp decides when (the memory estimate
// against --memory-budget) and hands the prepared job over.
#pragma once

#include "color/tonemap.h"
#include "render/spectral_pass.h"
#include "represent/representation.h"
#include "scene/scene.h"
#include "spectral/library.h"
#include "vk/context.h"

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

// Memory a render holds at once, per image row: the cube's row, the GPU's layered target rows
// (ssaa² samples), the tonemap targets and the display outputs' rows.
size_t bytesPerRow(int width, int channels, int ssaa, bool display, int detectorChannels);

// The machine's default budget: a quarter of its physical memory.
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
    // Where to write (empty path: not written) and what the files say about themselves.
    std::filesystem::path cube, png, xyz, responses;
    bool half = false;
    std::string compression = "zip";
    std::vector<std::pair<std::string, std::string>> provenance;
};

struct StripResult {
    int strips = 0;
    size_t clampedToHalf = 0, clippedPixels = 0;
    double shading_ms = 0, tonemap_ms = 0, readback_ms = 0;
    std::string description;  // device and plan
};

StripResult renderInStrips(const StripJob& job);

}  // namespace metamer
