// The coloured shadows' cost estimate (issue 51, class 8): known areas of sheets in a light's map,
// clipped to its square and its near plane, and the refusal's arithmetic.
#include "render/transmittance_map_cost.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <tuple>

using namespace metamer;

namespace {

// A square sheet of side `side` in the plane z = `z`, centred on (x, y), as one transparent draw.
void addSheet(PackedScene& p, double x, double y, double z, double side, bool transparent = true) {
    const uint32_t first = uint32_t(p.vertices.size());
    const double h = side / 2;
    for (auto [dx, dy] : {std::pair{-h, -h}, {h, -h}, {h, h}, {-h, h}}) {
        gpu::SpectralVertex v{};
        v.position[0] = float(x + dx), v.position[1] = float(y + dy), v.position[2] = float(z);
        p.vertices.push_back(v);
    }
    PackedDraw d{};
    d.firstIndex = uint32_t(p.indices.size());
    d.indexCount = 6;
    d.vertexOffset = 0;
    d.transparent = transparent;
    for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) p.indices.push_back(first + i);
    p.draws.push_back(d);
}

// A scene with one shadow-map layer whose matrix is `viewProjection`, 21 band layers and 9
// optical-depth channels (3 layers: the maps' cost does not depend on the bands).
PackedScene oneLight(const glm::mat4& viewProjection) {
    PackedScene p;
    p.filteredShadows = true;
    p.bandLayers = 21;
    p.depthChannels = 9;
    p.depthLayers = 3;
    p.shadowMaps.layers.resize(1);
    p.shadowBlock.layers[0] = viewProjection;
    return p;
}

}  // namespace

TEST(TransmittanceMapCost, ASheetCoversItsShareOfTheMapClippedToItsSquare) {
    // An orthographic light whose map spans x, y ∈ [−1, 1]: the identity as its matrix.
    PackedScene p = oneLight(glm::mat4(1.0f));
    addSheet(p, 0, 0, 0.5, 1.0);      // a quarter of the map
    addSheet(p, 0, 0, 0.5, 4.0);      // larger than the map: the whole of it
    addSheet(p, 1, 0, 0.5, 1.0);      // half outside: an eighth
    addSheet(p, 5, 5, 0.5, 1.0);      // outside: nothing but its draw
    addSheet(p, 0, 0, 0.5, 1.0, false);  // opaque: not in the maps
    const TransmittanceMapCost c = transmittanceMapCost(p, 256);
    EXPECT_EQ(c.transparentDraws, 4u);
    EXPECT_EQ(c.layers, 1u);
    EXPECT_NEAR(c.texels, 256.0 * 256.0 * (0.25 + 1.0 + 0.125), 1e-6);
    EXPECT_EQ(c.channelLayers, 3);
    EXPECT_EQ(c.groups, 1);
    EXPECT_DOUBLE_EQ(c.seconds, c.texels * (kTransmittanceSecondsPerTexel + 3 * kTransmittanceSecondsPerTexelLayer) +
                                    4 * 1 * kTransmittanceSecondsPerDraw);
}

TEST(TransmittanceMapCost, WhatIsBehindAPointLightCostsNothingAndWhatCrossesItIsClipped) {
    // A point light at the origin looking down −z (a cube face): 90° field of view.
    const glm::mat4 face = glm::perspective(glm::radians(90.0f), 1.0f, 0.01f, 100.0f);
    PackedScene p = oneLight(face);
    addSheet(p, 0, 0, -1, 2.0);   // fills the face exactly (tan 45° × 1 on each side)
    addSheet(p, 0, 0, +1, 2.0);   // behind the light: nothing
    EXPECT_NEAR(transmittanceMapCost(p, 256).texels, 256.0 * 256.0, 1e-3);
    // A triangle through the light's plane (one corner behind it): only the part in front is
    // projected — a naive projection would divide by w ≈ 0 on the way.
    PackedScene q = oneLight(face);
    gpu::SpectralVertex v{};
    for (auto [x, y, z] : {std::tuple{-0.5f, -0.5f, -1.0f}, {0.5f, -0.5f, -1.0f}, {0.0f, 1.0f, 0.5f}}) {
        v.position[0] = x, v.position[1] = y, v.position[2] = z;
        q.vertices.push_back(v);
    }
    PackedDraw d{};
    d.indexCount = 3;
    d.transparent = true;
    q.indices = {0, 1, 2};
    q.draws.push_back(d);
    const double texels = transmittanceMapCost(q, 256).texels;
    EXPECT_GT(texels, 256.0 * 256.0 * 0.125);  // more than the front edge's own triangle...
    EXPECT_LT(texels, 256.0 * 256.0);          // ...and not the whole face
}

TEST(TransmittanceMapCost, ASceneWithoutColouredShadowsCostsNothing) {
    PackedScene p = oneLight(glm::mat4(1.0f));
    addSheet(p, 0, 0, 0.5, 1.0);
    p.filteredShadows = false;
    EXPECT_EQ(transmittanceMapCost(p, 256).seconds, 0.0);
}
