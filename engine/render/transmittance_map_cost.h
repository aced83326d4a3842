// What the coloured shadows' transmittance maps will cost to draw (render/shadow_transmittance.cpp),
// counted on the CPU before any of it is drawn: every transparent draw is rasterized once into each
// shadow-map layer's map, writing its optical-depth channels' layers (⌈channels / 4⌉: per
// transparent material, not per band), so the work is the transparent area each light sees, in
// texels, times those layers, plus a fixed cost per draw and channel group. A scene of 10⁵ stacked
// sheets is told what it will take; one beyond kMaxTransmittanceMapSeconds is refused, with the
// count and the time, before anything is drawn (issue 51, class 8; issue 50; docs/numerics.md).
// Tests: engine/render/transmittance_map_cost_test.cpp.
#pragma once

#include "render/spectral_packing.h"

#include <cstddef>
#include <string>

namespace metamer {

struct TransmittanceMapCost {
    size_t transparentDraws = 0;   // transparent objects (each drawn per layer and band pass)
    size_t layers = 0;             // shadow-map layers (a light's map each; a point light has 6)
    int groups = 0;                // the render passes each map is drawn in (≤ MAX_OUTPUTS layers each)
    int channelLayers = 0;         // RGBA32F layers each fragment writes, over all groups
    double texels = 0.0;           // transparent area the lights see, texels summed over layers and draws
    double seconds = 0.0;          // estimated, at the rates below
};

// The rates the estimate uses, measured with lavapipe on the development machine (2 cores;
// docs/numerics.md, "Scale of transparent scenes"): seconds per texel a transparent object covers
// (its fragment) and per texel and layer it writes, and seconds per draw and group. A hardware GPU
// is far faster: the estimate is an upper bound.
constexpr double kTransmittanceSecondsPerTexel = 0.7e-8;
constexpr double kTransmittanceSecondsPerTexelLayer = 1.4e-8;
constexpr double kTransmittanceSecondsPerDraw = 1.0e-5;
// Beyond this estimate the cost is said (a warning); beyond the second the scene is refused rather
// than left to run for an hour.
constexpr double kSlowTransmittanceMapSeconds = 10.0;
constexpr double kMaxTransmittanceMapSeconds = 600.0;

// The cost of `p`'s maps at `mapSize` texels a side (p.depthLayers layers each); zero when the
// scene has no coloured shadows. Triangles are clipped to each light's view (near plane, then the
// map's square), so a sheet a light does not see costs only its draw.
TransmittanceMapCost transmittanceMapCost(const PackedScene& p, int mapSize);

// One line for the user: the count, the area and the estimated time.
std::string describe(const TransmittanceMapCost& c);

}  // namespace metamer
