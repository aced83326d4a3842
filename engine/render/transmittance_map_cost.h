// What the coloured shadows' transmittance maps will cost to draw (render/shadow_transmittance.cpp),
// counted on the CPU before any of it is drawn: every transparent draw is rasterized into every band
// layer of every shadow-map layer's map, so the work is the transparent area each light sees, in
// texels, times the band layers, plus a fixed cost per draw and band pass. A scene of 10⁴ stacked
// sheets is told what it will take; one beyond kMaxTransmittanceMapSeconds is refused, with the
// count and the time, before anything is drawn (issue 51, class 8; docs/numerics.md).
// Tests: engine/render/transmittance_map_cost_test.cpp.
#pragma once

#include "render/spectral_packing.h"

#include <cstddef>
#include <string>

namespace metamer {

struct TransmittanceMapCost {
    size_t transparentDraws = 0;   // transparent objects (each drawn per layer and band pass)
    size_t layers = 0;             // shadow-map layers (a light's map each; a point light has 6)
    int bandPasses = 0;            // the band passes each map is drawn in
    int bandLayers = 0;            // RGBA32F layers each fragment writes, over all band passes
    double texels = 0.0;           // transparent area the lights see, texels summed over layers and draws
    double seconds = 0.0;          // estimated, at the rates below
};

// The rates the estimate uses, measured with lavapipe on the development machine (2 cores;
// docs/numerics.md, "Scale of transparent scenes"): texel × band-layer writes per second, and
// seconds per draw and band pass. A hardware GPU is far faster: the estimate is an upper bound.
constexpr double kTransmittanceWritesPerSecond = 7.0e7;
constexpr double kTransmittanceSecondsPerDraw = 1.0e-5;
// Beyond this estimate the cost is said (a warning); beyond the second the scene is refused rather
// than left to run for an hour.
constexpr double kSlowTransmittanceMapSeconds = 10.0;
constexpr double kMaxTransmittanceMapSeconds = 600.0;

// The cost of `p`'s maps at `mapSize` texels a side drawn in `bandPasses` passes; zero when the
// scene has no coloured shadows. Triangles are clipped to each light's view (near plane, then the
// map's square), so a sheet a light does not see costs only its draw.
TransmittanceMapCost transmittanceMapCost(const PackedScene& p, int mapSize, int bandPasses);

// One line for the user: the count, the area and the estimated time.
std::string describe(const TransmittanceMapCost& c);

}  // namespace metamer
