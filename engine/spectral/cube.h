// A spectral radiance cube: width × height pixels × grid.bands() bands, float32, stored
// pixel-interleaved ([y][x][band], row 0 at the top), values in W·sr⁻¹·m⁻²·nm⁻¹ (per band;
// docs/physics.md "Resampling"). The hand-over between the renderers and io/.
// Tests: engine/io/spectral_exr_test.cpp.
#pragma once

#include "spectral/grid.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace metamer {

struct SpectralCube {
    int width = 0;
    int height = 0;
    Grid grid;
    std::vector<float> data;

    SpectralCube() = default;
    SpectralCube(int w, int h, const Grid& g)
        : width(w), height(h), grid(g), data(static_cast<size_t>(w) * h * g.bands(), 0.0f) {}

    int bands() const { return grid.bands(); }
    size_t offset(int x, int y) const { return (static_cast<size_t>(y) * width + x) * bands(); }
    float* pixel(int x, int y) { return data.data() + offset(x, y); }
    const float* pixel(int x, int y) const { return data.data() + offset(x, y); }
    float& at(int x, int y, int band) { return data[offset(x, y) + band]; }
    float at(int x, int y, int band) const { return data[offset(x, y) + band]; }
};

}  // namespace metamer
