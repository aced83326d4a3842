// Reading the spectral pass's layered target back into a cube: the layers' rows (4 bands a texel)
// strided into pixel-interleaved spectra, box-filtering ssaa × ssaa samples per pixel, rows in
// parallel. Plain C++ over a view of the target's memory (a mapped LINEAR image or a readback
// buffer), so it is tested without a GPU. Tests: render/target_readback_test.cpp.
#pragma once

#include "spectral/cube.h"

#include <cstddef>
#include <cstdint>

namespace metamer {

// Where layer l, row y of the target lies: 4 floats per texel.
struct LayeredView {
    const char* base = nullptr;
    size_t rowPitch = 0, layerPitch = 0;  // bytes
    const float* row(uint32_t layer, uint32_t y) const {
        return reinterpret_cast<const float*>(base + layer * layerPitch + y * rowPitch);
    }
};

// `cube` (W × H × bands, allocated by the caller) from a target of ssaa·W × ssaa·H texels and
// ⌈bands/4⌉ layers: each pixel the mean of its ssaa² samples (the samples themselves at ssaa 1).
void readLayered(const LayeredView& target, int ssaa, SpectralCube& cube);

}  // namespace metamer
