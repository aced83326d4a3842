// Shadows and hemisphere lights, with known answers through both renderers (docs/physics.md,
// "Shadows" and "Hemisphere lights"): a quad in the umbra of an opaque occluder receives exactly
// the ambient and environment terms, one outside it is what it is without shadows, the GPU's
// shadow boundary lies within a shadow-map texel of the exact one, shadowed lights excite no
// fluorescence, and the environment's diffuse and specular terms match their closed forms.
#include "interface.h"
#include "reference/cpu_renderer.h"
#include "reference/hemisphere_lobe.h"
#include "render/shadow_maps.h"
#include "render/spectral_pass.h"
#include "support/gpu.h"
#include "support/interior_comparison.h"
#include "support/scene_builders.h"

#include <cmath>
#include <numbers>

using namespace metamer;
using namespace metamer::test;

namespace {

constexpr double kPi = std::numbers::pi;

SpectralCube renderGpu(const Scene& s, const SceneOnGrid& g) {
    uint32_t before = test::gpu().validationErrors();
    SpectralPass pass(test::gpu(), s, g);
    SpectralCube c = pass.render();
    EXPECT_NO_VALIDATION_ERRORS(before);
    return c;
}

// A white floor (z = 0, facing +z) seen from straight above over [−0.8, 0.8]², a horizontal
// 0.3 m square occluder at height 0.5 over (−0.5, 0), lit by a directional light at 45° that puts
// the occluder's shadow on [−0.15, 0.15]², an ambient light, a sky and a ground.
struct UmbraScene {
    Scene scene;
    double rho = 0.8, E = 1.5, Ea = 0.2, Lsky = 0.05, Lground = 0.03;
    explicit UmbraScene(int px = 64) {
        scene = emptyScene(Grid{400, 700, 10}, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.6, px, px));
        scene.materials.push_back(lambertian(rho, "floor"));
        scene.materials.push_back(lambertian(0.5, "occluder"));
        scene.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 4, 4, 0));
        scene.meshes.push_back(quad({-0.5, 0, 0.5}, {0, 0, 1}, 0.3, 0.3, 1));
        scene.lights.push_back(directionalLight({1, 0, -1}, constantSpectrum(E), 1.0, "lights.0"));
        scene.lights.push_back(ambientLight(constantSpectrum(Ea), 1.0, "lights.1"));
        scene.lights.push_back(hemisphereLight({0, 0, 1}, constantSpectrum(Lsky), 1.0, "lights.2"));
        scene.lights.push_back(hemisphereLight({0, 0, -1}, constantSpectrum(Lground), 1.0, "lights.3"));
    }
    // The floor's radiance in the umbra (ambient and sky only: the ground is below it) and lit.
    double umbra() const { return rho * Ea / kPi + rho * Lsky; }
    double lit() const { return umbra() + rho * E * std::cos(kPi / 4) / kPi; }
};

double worldX(int x, int px, double height = 1.6, double centre = 0.0) { return centre + ((x + 0.5) / px - 0.5) * height; }
double worldY(int y, int px, double height = 1.6) { return (0.5 - (y + 0.5) / px) * height; }

}  // namespace

TEST(Shadows, UmbraReceivesExactlyTheAmbientAndEnvironmentTerms) {
    const UmbraScene u;
    const SceneOnGrid g = onGrid(u.scene);
    const SpectralCube gpuCube = renderGpu(u.scene, g);
    const ReferenceImage ref = renderReference(u.scene, g);
    int umbra = 0, lit = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const double wx = worldX(x, 64), wy = worldY(y, 64);
            const bool inUmbra = std::fabs(wx) < 0.12 && std::fabs(wy) < 0.12;
            const bool outside = (std::fabs(wx) > 0.18 || std::fabs(wy) > 0.18) && !(wx < -0.3 && wx > -0.7 && std::fabs(wy) < 0.2);
            if (!inUmbra && !outside) continue;
            const double expected = inUmbra ? u.umbra() : u.lit();
            (inUmbra ? umbra : lit)++;
            for (int b = 0; b < gpuCube.bands(); b += 10) {
                ASSERT_NEAR(ref.cube.at(x, y, b), expected, 1e-6 * expected) << "reference, pixel " << x << "," << y;
                ASSERT_NEAR(gpuCube.at(x, y, b), expected, 1e-6 * expected) << "GPU, pixel " << x << "," << y;
            }
        }
    EXPECT_GE(umbra, 100);
    EXPECT_GT(lit, 2000);
}

// Shadow maps are kept on the device for later renders of the same geometry and lights (a batch's
// next job; issue 31): a render that changes only a material gets the known answer with them, and
// one whose occluder moved gets new maps — its umbra where the new occluder puts it, not the old.
TEST(Shadows, MapsAreReusedOnlyForTheSameGeometryAndLights) {
    auto expectUmbraAt = [](const UmbraScene& u, double cy, const char* what) {
        const SpectralCube c = renderGpu(u.scene, onGrid(u.scene));
        int umbra = 0, lit = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                const double wx = worldX(x, 64), wy = worldY(y, 64) - cy;
                const bool inUmbra = std::fabs(wx) < 0.12 && std::fabs(wy) < 0.12;
                const bool outside = std::fabs(wx) > 0.18 && std::fabs(wx) < 0.3 && std::fabs(wy) < 0.1;
                if (!inUmbra && !outside) continue;
                const double expected = inUmbra ? u.umbra() : u.lit();
                (inUmbra ? umbra : lit)++;
                ASSERT_NEAR(c.at(x, y, 5), expected, 1e-5 * expected) << what << ", pixel " << x << "," << y;
            }
        EXPECT_GE(umbra, 100) << what;
        EXPECT_GE(lit, 50) << what;
    };
    UmbraScene u;
    expectUmbraAt(u, 0.0, "first");
    u.rho = 0.4;  // a material change: the same maps serve
    u.scene.materials[0] = lambertian(u.rho, "floor");
    expectUmbraAt(u, 0.0, "another floor");
    u.scene.meshes[1] = quad({-0.5, 0.3, 0.5}, {0, 0, 1}, 0.3, 0.3, 1);  // the occluder moved: new maps
    expectUmbraAt(u, 0.3, "the occluder moved");
    u.scene.meshes[1] = quad({-0.5, 0, 0.5}, {0, 0, 1}, 0.3, 0.3, 1);
    expectUmbraAt(u, 0.0, "moved back");
}

TEST(Shadows, WithoutOccludersNothingChangesAndShadowsFalseTurnsThemOff) {
    // Lit surfaces — the floor under a grazing light and a sphere's curved side — are what they
    // are with shadows off, to 1e-6: no surface shadows itself (no acne).
    Scene s = emptyScene(Grid{400, 700, 20}, perspectiveCamera({0, -3, 2}, {0, 0, 0.3}, {0, 0, 1}, 40, 96, 96));
    s.materials.push_back(lambertian(0.7, "floor"));
    s.materials.push_back(glossy(constantSpectrum(0.3), constantSpectrum(0.2), 40, "ball"));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 6, 6, 0));
    Mesh ball = sphere({0, 0, 0.5}, 0.5, 64, 32, 1);
    s.meshes.push_back(ball);
    s.lights.push_back(directionalLight({1, 0.3, -0.17}, constantSpectrum(1.0), 1.0, "lights.0"));  // 80° from the floor's normal
    s.lights.push_back(pointLight({-1.5, -1, 2}, constantSpectrum(3.0), 1.0, "lights.1"));
    const SceneOnGrid g = onGrid(s);
    Scene off = s;
    for (Light& l : off.lights) l.shadows = false;
    const SpectralCube on = renderGpu(s, g), without = renderGpu(off, g);
    const ReferenceImage ref = renderReference(s, g);
    int compared = 0;
    for (int y = 1; y + 1 < 96; ++y)
        for (int x = 1; x + 1 < 96; ++x) {
            bool clear = true;  // neither this pixel nor a neighbour has a light blocked
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) clear = clear && ref.shadows[size_t(y + dy) * 96 + x + dx] == 0;
            if (!clear || ref.objectId[size_t(y) * 96 + x] < 0) continue;
            ++compared;
            for (int b = 0; b < on.bands(); ++b)
                ASSERT_NEAR(on.at(x, y, b), without.at(x, y, b), 1e-6 * std::fabs(without.at(x, y, b)) + 1e-12)
                    << "pixel " << x << "," << y;
        }
    EXPECT_GT(compared, 4000);
    // The sphere shadows the floor in the reference, and the GPU agrees away from boundaries.
    const InteriorComparison c = compareInterior(on, ref);
    EXPECT_LE(c.maxRelative, 1e-4) << "pixel " << c.worstX << "," << c.worstY;
    size_t blocked = 0;
    for (uint64_t b : ref.shadows) blocked += b != 0 && b != kMixedShadows;
    EXPECT_GT(blocked, 200u);
}

TEST(Shadows, BoundaryLiesWithinOneShadowMapTexel) {
    // The umbra's edge x = 0.15 seen at 0.25 mm per pixel: the GPU's edge (where the radiance
    // crosses halfway) lies within one texel of the exact one; the reference's within a pixel.
    for (bool point : {false, true}) {
        UmbraScene u(200);
        Scene& s = u.scene;
        s.camera = orthographicCamera({0.15, 0, 5}, {0.15, 0, 0}, {0, 1, 0}, 0.05, 200, 200);
        if (point) {
            // From (−1.5, 0, 1.5) the occluder's shadow is scaled by 1.5 about the light: also centred
            // at 0, 0.45 wide, edge at x = 0.225.
            s.lights[0] = pointLight({-1.5, 0, 1.5}, constantSpectrum(2.0), 1.0, "lights.0");
            s.camera = orthographicCamera({0.225, 0, 5}, {0.225, 0, 0}, {0, 1, 0}, 0.05, 200, 200);
        }
        const double edge = point ? 0.225 : 0.15, centre = edge;
        const SceneOnGrid g = onGrid(s);
        const SpectralCube gpuCube = renderGpu(s, g);
        const ReferenceImage ref = renderReference(s, g);
        const ShadowMaps maps = planShadowMaps(s, SHADOW_MAP_SIZE);
        // A texel on the floor: directional, its size over cos 45° (the light's slant stretches
        // it along x); point, at the distance and slant of the edge.
        double texel = maps.lights[0].texel / std::cos(kPi / 4);
        if (point) {
            const glm::dvec3 d = glm::dvec3(edge, 0, 0) - s.lights[0].position;
            const double slant = std::fabs(d.z) / glm::length(d);
            texel = maps.lights[0].texel * std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)}) / slant;
        }
        auto edgeAt = [&](const SpectralCube& c, int y) {
            const double lo = c.at(0, y, 0), hi = c.at(199, y, 0), half = 0.5 * (lo + hi);
            for (int x = 1; x < 200; ++x)
                if ((c.at(x - 1, y, 0) - half) * (c.at(x, y, 0) - half) <= 0.0) return worldX(x, 200, 0.05, centre) - 0.5 * 0.05 / 200;
            return double(NAN);
        };
        double worst = 0.0;
        for (int y = 20; y < 180; y += 20) {
            const double exact = edgeAt(ref.cube, y), gpuEdge = edgeAt(gpuCube, y);
            EXPECT_NEAR(exact, edge, 0.05 / 200) << (point ? "point" : "directional") << ", row " << y;
            worst = std::max(worst, std::fabs(gpuEdge - exact));
        }
        std::printf("%s light: GPU shadow boundary at most %.3g mm from the exact one (a texel is %.3g mm on the floor)\n",
                    point ? "point" : "directional", worst * 1e3, texel * 1e3);
        EXPECT_LE(worst, texel) << (point ? "point" : "directional");
    }
}

TEST(Shadows, ShadowedLightsExciteNoFluorescenceAndTheEnvironmentDoes) {
    UmbraScene u;
    u.scene.materials[0] = fluorescent(constantSpectrum(0.5), boxSpectrum(400, 480, 0.8), gaussianSpectrum(580, 25), 0.7, "floor");
    Scene noDirectional = u.scene;
    noDirectional.lights.erase(noDirectional.lights.begin());
    Scene noEnvironment = u.scene;
    noEnvironment.lights.resize(2);
    const SceneOnGrid g = onGrid(u.scene), g1 = onGrid(noDirectional), g2 = onGrid(noEnvironment);
    const SpectralCube all = renderGpu(u.scene, g), without = renderGpu(noDirectional, g1), noEnv = renderGpu(noEnvironment, g2);
    const ReferenceImage ref = renderReference(u.scene, g), refWithout = renderReference(noDirectional, g1);
    const int x = 32, y = 32;  // the umbra's middle
    double emitted = 0.0;
    for (int b = 0; b < all.bands(); ++b) {
        EXPECT_NEAR(all.at(x, y, b), without.at(x, y, b), 1e-6 * without.at(x, y, b)) << "band " << b;
        EXPECT_NEAR(ref.cube.at(x, y, b), refWithout.cube.at(x, y, b), 1e-9 * refWithout.cube.at(x, y, b)) << "band " << b;
        emitted = std::max(emitted, double(all.at(x, y, b) - noEnv.at(x, y, b) - 0.5 * u.Lsky));
    }
    EXPECT_GT(emitted, 1e-3);  // the sky excites the paint: more than its reflection alone
}

TEST(HemisphereLight, DiffuseIsRhoLTimesOnePlusCosOverTwoInBothRenderers) {
    for (double tilt : {0.0, 60.0, 120.0}) {
        const double t = tilt * kPi / 180;
        Scene s = emptyScene(Grid{400, 700, 10}, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0, 8, 8));
        s.materials.push_back(lambertian(0.6));
        s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 4, 4));
        s.lights.push_back(hemisphereLight({std::sin(t), 0, std::cos(t)}, gaussianSpectrum(550, 60, 0.3)));
        const SceneOnGrid g = onGrid(s);
        const SpectralCube gpuCube = renderGpu(s, g);
        const ReferenceImage ref = renderReference(s, g);
        for (int b = 0; b < gpuCube.bands(); ++b) {
            const double expected = 0.6 * g.lights[0][b] * (1 + std::cos(t)) / 2;
            EXPECT_NEAR(ref.cube.at(4, 4, b), expected, 1e-7 * g.lights[0][b]) << "tilt " << tilt;
            EXPECT_NEAR(gpuCube.at(4, 4, b), expected, 1e-6 * g.lights[0][b]) << "tilt " << tilt;
        }
    }
}

TEST(HemisphereLight, SpecularMatchesTheClosedFormsInBothRenderers) {
    // A mirror-like metal (ρd = 0, ρs = 1) facing the sky, seen along its normal: for N = 0 the
    // lobe's integral is π(1 + n·u)/2; for N > 0 with v = n = u, 8π·[2c^(N+4)/(N+4) − c^(N+2)/(N+2)]
    // from 1/√2 to 1 (lobe_table_test.cpp); the radiance is L·(N+8)/(8π) times it.
    for (double N : {0.0, 10.0, 60.0, 200.0}) {
        Scene s = emptyScene(Grid{400, 700, 50}, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0, 4, 4));
        s.materials.push_back(glossy(constantSpectrum(0.0), constantSpectrum(1.0), N, "metal"));
        s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 4, 4));
        s.lights.push_back(hemisphereLight({0, 0, 1}, constantSpectrum(0.4)));
        const SceneOnGrid g = onGrid(s);
        const double c = 1 / std::sqrt(2.0);
        const double integral = N == 0 ? kPi
                                       : 8 * kPi * (2 / (N + 4) * (1 - std::pow(c, N + 4)) - 1 / (N + 2) * (1 - std::pow(c, N + 2)));
        const double expected = 0.4 * (N + 8) / (8 * kPi) * integral;
        const SpectralCube gpuCube = renderGpu(s, g);
        const ReferenceImage ref = renderReference(s, g);
        // The table's error at v = n = u is below 10⁻⁶ (lobe_table_test.cpp); float adds ~10⁻⁶.
        EXPECT_NEAR(ref.cube.at(2, 2, 0), expected, 1e-6 * expected) << "N = " << N;
        EXPECT_NEAR(gpuCube.at(2, 2, 0), ref.cube.at(2, 2, 0), 1e-5 * expected) << "N = " << N;
    }
}

TEST(HemisphereLight, GpuAgreesWithTheReferenceOnSpheres) {
    // Metals and plastic under a sky and a ground of different spectra, viewed so that every
    // angle of incidence up to grazing appears: the shared table lookup in float against it in double.
    Scene s = emptyScene(Grid{400, 700, 10}, perspectiveCamera({0, -4, 1.2}, {0, 0, 0.5}, {0, 0, 1}, 30, 96, 64));
    s.materials.push_back(glossy(constantSpectrum(0.0), gaussianSpectrum(600, 80, 0.9), 200, "gold"));
    s.materials.push_back(glossy(constantSpectrum(0.3), constantSpectrum(0.04), 10, "plastic"));
    s.materials.push_back(glossy(constantSpectrum(0.0), constantSpectrum(0.9), 1000, "mirror"));
    s.meshes.push_back(sphere({-1.1, 0, 0.5}, 0.5, 96, 48, 0));
    s.meshes.push_back(sphere({0, 0, 0.5}, 0.5, 96, 48, 1));
    s.meshes.push_back(sphere({1.1, 0, 0.5}, 0.5, 96, 48, 2));
    s.lights.push_back(hemisphereLight({0, 0, 1}, gaussianSpectrum(470, 80, 0.08)));
    s.lights.push_back(hemisphereLight({0, 0, -1}, gaussianSpectrum(620, 90, 0.03)));
    const SceneOnGrid g = onGrid(s);
    const SpectralCube gpuCube = renderGpu(s, g);
    const ReferenceImage ref = renderReference(s, g);
    const InteriorComparison c = compareInterior(gpuCube, ref);
    std::printf("hemisphere lights on spheres: %d interior pixels, max relative error %.3g\n", c.pixels, c.maxRelative);
    EXPECT_GT(c.pixels, 1000);
    EXPECT_LE(c.maxRelative, 1e-4) << "pixel " << c.worstX << "," << c.worstY << " band " << c.worstBand;
}
