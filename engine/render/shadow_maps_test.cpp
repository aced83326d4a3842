#include "render/shadow_maps.h"

#include "interface.h"
#include "support/cubes.h"

#include <gtest/gtest.h>

using namespace metamer;
using namespace metamer::test;

namespace {

Scene twoLights() {
    Scene s;
    Mesh m;
    m.positions = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 2, 1}};
    m.indices = {0, 1, 2, 0, 2, 3};
    s.meshes.push_back(m);
    s.materials.push_back({});
    Light d;
    d.type = Light::Type::Directional;
    d.direction = glm::normalize(glm::dvec3(0.3, -1, 0.2));
    d.name = "lights.0";
    Light p;
    p.type = Light::Type::Point;
    p.position = {0, 3, 0};
    p.name = "lights.1";
    Light a;
    a.type = Light::Type::Ambient;
    s.lights = {d, p, a};
    return s;
}

glm::dvec3 clip(const glm::dmat4& m, const glm::dvec3& p) {
    const glm::dvec4 c = m * glm::dvec4(p, 1.0);
    return glm::dvec3(c) / c.w;
}

}  // namespace

TEST(ShadowMaps, EveryVertexLandsInsideItsLayers) {
    const Scene s = twoLights();
    const ShadowMaps maps = planShadowMaps(s, 1024);
    ASSERT_EQ(maps.layers.size(), 7u);
    EXPECT_EQ(maps.lights[0].firstLayer, 0);
    EXPECT_EQ(maps.lights[1].firstLayer, 1);
    EXPECT_EQ(maps.lights[2].firstLayer, -1);
    for (const glm::dvec3& p : s.meshes[0].positions) {
        const glm::dvec3 q = clip(maps.layers[0].viewProjection, p);
        EXPECT_LE(std::fabs(q.x), 1.0);
        EXPECT_LE(std::fabs(q.y), 1.0);
        EXPECT_GT(q.z, 0.0);
        EXPECT_LT(q.z, 1.0);
    }
    // A point below the point light lands in its −y face, in the middle, in front of the far plane.
    const glm::dvec3 below = clip(maps.layers[1 + 3].viewProjection, {0, 0, 0});
    EXPECT_NEAR(below.x, 0.0, 1e-12);
    EXPECT_NEAR(below.y, 0.0, 1e-12);
    EXPECT_GT(below.z, 0.0);
    EXPECT_LT(below.z, 1.0);
}

TEST(ShadowMaps, NearerAlongTheLightIsSmallerDepth) {
    const Scene s = twoLights();
    const ShadowMaps maps = planShadowMaps(s, 1024);
    const glm::dvec3 d = s.lights[0].direction;
    const glm::dvec3 a = clip(maps.layers[0].viewProjection, glm::dvec3(0, 0.5, 0));
    const glm::dvec3 b = clip(maps.layers[0].viewProjection, glm::dvec3(0, 0.5, 0) + 0.1 * d);
    EXPECT_LT(a.z, b.z);
    EXPECT_NEAR(a.x, b.x, 1e-12);  // along the light: the same texel
    const glm::dvec3 n1 = clip(maps.layers[1 + 3].viewProjection, {0, 1, 0}), n2 = clip(maps.layers[1 + 3].viewProjection, {0, 0, 0});
    EXPECT_LT(n1.z, n2.z);
}

TEST(ShadowMaps, ShadowsFalseAndTooManyLayers) {
    Scene s = twoLights();
    s.lights[1].shadows = false;
    EXPECT_EQ(planShadowMaps(s, 512).layers.size(), 1u);
    s.lights.clear();
    for (int i = 0; i < MAX_SHADOW_LAYERS / 6 + 1; ++i) {
        Light p;
        p.type = Light::Type::Point;
        p.position = {0, 3, 0};
        p.name = "lights." + std::to_string(i);
        s.lights.push_back(p);
    }
    expectInputError([&] { planShadowMaps(s, 512); }, "", "lights.16.shadows", "set \"shadows\": false");
}
