// The GPU cube against the CPU reference on interior pixels: the pixel and its 8 neighbours see
// the same mesh and the same blocked lights in the reference (no surface edge, no shadow boundary
// within a pixel), so the rasterizer and the ray caster agree on which surface is
// seen and the GPU differs only by float rounding (docs/physics.md, "GPU path specifics"). Shared
// by the GPU-vs-reference, numerics, texture and Donaldson tests.
#pragma once

#include "reference/cpu_renderer.h"
#include "spectral/cube.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace metamer::test {

// Which pixels and values a comparison counts.
struct CompareRule {
    // Relative error is taken against max(|reference|, floor × the band's largest reference
    // value), so bands that are almost black do not turn float rounding into large ratios.
    double floor = 1e-4;
    // Values whose reference is below this fraction of the band's largest are skipped (for
    // needle lobes, whose tails are all rounding).
    double skipBelow = 0.0;
};

struct InteriorComparison {
    double maxRelative = 0.0;  // as CompareRule says; a NaN on either side counts as +Inf
    double maxAbsolute = 0.0;  // largest |gpu − reference|, W·sr⁻¹·m⁻²·nm⁻¹
    int pixels = 0;            // interior pixels compared
    int worstX = -1, worstY = -1, worstBand = -1;  // where maxRelative is
};

inline InteriorComparison compareInterior(const SpectralCube& gpuCube, const ReferenceImage& ref,
                                          CompareRule rule = {}) {
    InteriorComparison m;
    const SpectralCube& cpu = ref.cube;
    const int W = cpu.width, H = cpu.height, B = cpu.bands();
    std::vector<double> bandMax(size_t(B), 0.0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int b = 0; b < B; ++b) bandMax[b] = std::max(bandMax[b], double(std::fabs(cpu.at(x, y, b))));
    for (int y = 1; y + 1 < H; ++y)
        for (int x = 1; x + 1 < W; ++x) {
            const int32_t id = ref.objectId[size_t(y) * W + x];
            if (id < 0) continue;
            const bool shadows = ref.shadows.size() == ref.objectId.size();
            const uint64_t blocked = shadows ? ref.shadows[size_t(y) * W + x] : 0;
            bool interior = blocked != kMixedShadows;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const size_t at = size_t(y + dy) * W + x + dx;
                    interior = interior && ref.objectId[at] == id && (!shadows || ref.shadows[at] == blocked) &&
                               (ref.crossings.size() != ref.objectId.size() ||
                                (ref.crossings[at] == ref.crossings[size_t(y) * W + x] &&
                                 ref.crossings[at] != kMixedCrossings));
                }
            if (!interior) continue;
            ++m.pixels;
            for (int b = 0; b < B; ++b) {
                const double r = cpu.at(x, y, b), g = gpuCube.at(x, y, b);
                const double diff = std::fabs(g - r);
                if (!(diff <= m.maxAbsolute)) m.maxAbsolute = std::isnan(diff) ? INFINITY : diff;
                if (std::fabs(r) < rule.skipBelow * bandMax[b]) continue;
                const double rel = diff / std::max(std::fabs(r), rule.floor * bandMax[b] + 1e-300);
                // A NaN on either side must count as the worst error, not be skipped by `>`.
                if (!(rel <= m.maxRelative)) {
                    m.maxRelative = std::isnan(rel) ? INFINITY : rel;
                    m.worstX = x;
                    m.worstY = y;
                    m.worstBand = b;
                }
            }
        }
    return m;
}

}  // namespace metamer::test
