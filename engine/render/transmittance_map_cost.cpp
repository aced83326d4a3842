#include "render/transmittance_map_cost.h"

#include <fmt/format.h>
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace metamer {

namespace {

// The area, in the map's NDC units ([-1, 1]², area 4), of a triangle's part in front of the
// light (w > 0) and inside the map's square: Sutherland–Hodgman against w = ε, then x, y = ±1.
double visibleArea(const glm::dvec4 (&clip)[3]) {
    constexpr double kNear = 1e-9;
    std::vector<glm::dvec4> poly(std::begin(clip), std::end(clip)), next;
    auto clipBy = [&](auto distance) {  // keeps distance ≥ 0
        next.clear();
        for (size_t i = 0; i < poly.size(); ++i) {
            const glm::dvec4 &a = poly[i], &b = poly[(i + 1) % poly.size()];
            const double da = distance(a), db = distance(b);
            if (da >= 0) next.push_back(a);
            if ((da >= 0) != (db >= 0)) next.push_back(a + (b - a) * (da / (da - db)));
        }
        poly.swap(next);
    };
    clipBy([](const glm::dvec4& v) { return v.w - kNear; });
    clipBy([](const glm::dvec4& v) { return v.w - v.x; });
    clipBy([](const glm::dvec4& v) { return v.w + v.x; });
    clipBy([](const glm::dvec4& v) { return v.w - v.y; });
    clipBy([](const glm::dvec4& v) { return v.w + v.y; });
    if (poly.size() < 3) return 0.0;
    double twice = 0.0;
    for (size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec4 &a = poly[i], &b = poly[(i + 1) % poly.size()];
        twice += a.x / a.w * (b.y / b.w) - b.x / b.w * (a.y / a.w);
    }
    return 0.5 * std::abs(twice);
}

}  // namespace

TransmittanceMapCost transmittanceMapCost(const PackedScene& p, int mapSize) {
    TransmittanceMapCost c;
    if (!p.filteredShadows) return c;
    c.layers = p.shadowMaps.layers.size();
    c.channelLayers = p.depthLayers;
    c.groups = (p.depthLayers + MAX_OUTPUTS - 1) / MAX_OUTPUTS;
    const double texelsPerUnit = double(mapSize) * double(mapSize) / 4.0;  // NDC area 4 is the whole map
    for (const PackedDraw& d : p.draws) {
        if (!d.transparent) continue;
        ++c.transparentDraws;
        for (size_t layer = 0; layer < c.layers; ++layer) {
            const glm::dmat4 vp(p.shadowBlock.layers[layer]);
            for (uint32_t i = 0; i + 2 < d.indexCount; i += 3) {
                glm::dvec4 clip[3];
                for (int k = 0; k < 3; ++k) {
                    const float* q = p.vertices[size_t(int64_t(p.indices[d.firstIndex + i + uint32_t(k)]) + d.vertexOffset)].position;
                    clip[k] = vp * glm::dvec4(q[0], q[1], q[2], 1.0);
                }
                c.texels += visibleArea(clip) * texelsPerUnit;
            }
        }
    }
    c.seconds = c.texels * (kTransmittanceSecondsPerTexel + double(c.channelLayers) * kTransmittanceSecondsPerTexelLayer) +
                double(c.transparentDraws) * double(c.layers) * double(c.groups) * kTransmittanceSecondsPerDraw;
    return c;
}

std::string describe(const TransmittanceMapCost& c) {
    return fmt::format("{} transparent objects drawn into {} light map layer(s) of {} optical-depth layer(s) in {} "
                       "pass(es): {:.3g} texels of transparent area × {} layer(s), about {:.3g} s with lavapipe",
                       c.transparentDraws, c.layers, c.channelLayers, c.groups, c.texels, c.channelLayers, c.seconds);
}

}  // namespace metamer
