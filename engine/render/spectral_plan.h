// What the spectral pass is asked for and what it decides for a scene, before any Vulkan object
// is made: shared by the pass (render/spectral_pass.h) and its resources
// (render/spectral_resources.h).
// Tests: through render/spectral_pass.h's.
#pragma once

#include <cstddef>
#include "scene/surface_quantity.h"

#include <cstdint>
#include <string>
#include <vector>

namespace metamer {

enum class Readback {
    Auto,  // map a LINEAR host-visible image where the device allows it, else copy
    Map,   // require mapping (error if unsupported)
    Copy,  // render to an OPTIMAL image and copy to a host buffer
};

struct SpectralPassOptions {
    int ssaa = 1;  // s×s samples per pixel, box-filtered (1, 2, 3 or 4)
    Readback readback = Readback::Auto;
    bool sampled = false;  // the target is also read by a later pass (the tonemap pass)
    // Render the image in horizontal strips of this many rows (0: the whole image at once), for
    // images larger than memory: setStrip() chooses the rows, readback() returns that strip.
    int stripRows = 0;
    // With stripRows, tiles of this many columns (0: the whole width): setTile() chooses the
    // tile (the preview's probe draws a 1×1 tile, the pixel under the cursor).
    int tileColumns = 0;
    // The response pass (non-empty): the outputs are the channels of a detector with these weights
    // [channel][band of the scene's grid], at most TONEMAP_MAX_CHANNELS, instead of the bands —
    // the display path that never writes the bands (docs/color.md, "The response pass"). The
    // target is then only sampled (needs `sampled`); it has no cube to read back.
    std::vector<std::vector<double>> responseWeights;
    // What the band passes compute: the radiance, or a ground-truth map (render/ground_truth.h),
    // drawn without the transparent objects (the map is of the opaque surface behind them).
    SurfaceQuantity quantity = SurfaceQuantity::Radiance;
};

// What this scene needs from the GPU: decided once, before any Vulkan object is made.
struct SpectralPassPlan {
    bool responses = false;  // the response pass: `bands` are a detector's channels
    SurfaceQuantity quantity = SurfaceQuantity::Radiance;  // the band passes' (SpectralPassOptions::quantity)
    int bands = 0;           // the grid's bands, or the response pass's channels
    int layers = 0;          // ceil(bands / 4)
    int passes = 0;          // ceil(layers / 8)
    int lightCount = 0;
    int shadowLayers = 0;  // shadow-map layers (render/shadow_maps.h), SHADOW_MAP_SIZE² each
    bool hasSpecular = false;
    bool hasFluorescence = false;
    bool fluorescenceSpectra = false;  // a Donaldson matrix: fluorescence as per-light spectra (interface.h)
    int ssaa = 1;
    uint32_t targetWidth = 0, targetHeight = 0;  // render-target size (× ssaa)
    bool mappedReadback = false;
    std::string frame;  // the frame's declared passes in order (SpectralResources::describeFrame)
    std::string interreflection;  // what solving the scene's interreflection took (empty without)
    std::string throughFilters;   // the response pass through sheets and media: its tables (empty without)
    size_t targetBytes = 0;  // the layered colour target
    std::string describe() const;
};

}  // namespace metamer
