// Known answers through the GPU spectral pass: radiances you can write down (docs/physics.md).
// Each is checked to float precision (relative 1e-5) without the CPU reference.
#include "render/spectral_pass.h"
#include "support/gpu.h"
#include "support/scene_builders.h"

#include <cmath>
#include <numbers>

using namespace metamer;
using namespace metamer::test;

namespace {

constexpr double kPi = std::numbers::pi;

// An orthographic camera looking down -z at the plane z = 0, 1 m tall, with `px` pixels a side:
// pixel (x, y) sees world point (xw(x), yw(y), 0).
Camera topDown(int px, double height_m = 1.0) {
    return orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, height_m, px, px);
}
double xw(int x, int px, double height_m = 1.0) { return ((x + 0.5) / px - 0.5) * height_m; }
double yw(int y, int px, double height_m = 1.0) { return (0.5 - (y + 0.5) / px) * height_m; }

SpectralCube render(const Scene& s, const SceneOnGrid& g) {
    uint32_t before = gpu().validationErrors();
    SpectralPass pass(gpu(), s, g);
    SpectralCube c = pass.render();
    EXPECT_NO_VALIDATION_ERRORS(before);
    return c;
}

Spectrum testLight() { return gaussianSpectrum(550, 80, 2.0, 300, 800, 1); }

}  // namespace

TEST(GpuKnownAnswer, WhiteLambertianQuadUnderDirectionalLightIsEOverPi) {
    Scene s = emptyScene(Grid{380, 780, 5}, topDown(16));
    s.materials.push_back(lambertian(1.0));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 10, 10));
    s.lights.push_back(directionalLight({0, 0, -1}, testLight(), 0.5));
    SceneOnGrid g = onGrid(s);
    SpectralCube cube = render(s, g);
    ASSERT_EQ(cube.bands(), 81);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x)
            for (int b = 0; b < cube.bands(); ++b) {
                double expected = g.lights[0][b] / kPi;
                ASSERT_NEAR(cube.at(x, y, b), expected, 1e-6 * expected) << x << "," << y << " band " << b;
            }
}

TEST(GpuKnownAnswer, AmbientIsRhoEOverPiWithoutCosine) {
    Scene s = emptyScene(Grid{400, 700, 10}, topDown(8));
    s.materials.push_back(lambertian(0.6));
    // Tilted 70° away from the camera and the light: ambient ignores orientation.
    s.meshes.push_back(quad({0, 0, 0}, {std::sin(70 * kPi / 180), 0, std::cos(70 * kPi / 180)}, 10, 10));
    s.lights.push_back(ambientLight(testLight(), 0.25));
    SceneOnGrid g = onGrid(s);
    SpectralCube cube = render(s, g);
    for (int b = 0; b < cube.bands(); ++b) EXPECT_NEAR(cube.at(4, 4, b), 0.6 * g.lights[0][b] / kPi, 1e-5 * g.lights[0][b]);
}

TEST(GpuKnownAnswer, PointLightFallsOffAsCosineOverDistanceSquared) {
    const int px = 33;
    const double h = 0.4, size = 2.0;
    Scene s = emptyScene(Grid{500, 600, 20}, topDown(px, size));
    s.materials.push_back(lambertian(0.8));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 10, 10));
    s.lights.push_back(pointLight({0, 0, h}, testLight(), 3.0));
    SceneOnGrid g = onGrid(s);
    SpectralCube cube = render(s, g);
    for (int y : {0, 7, 16, 25}) {
        for (int x : {3, 16, 30}) {
            double r2 = std::pow(xw(x, px, size), 2) + std::pow(yw(y, px, size), 2);
            double geometry = h / std::pow(h * h + r2, 1.5);  // cosθ/d² = h/d³
            for (int b = 0; b < cube.bands(); ++b) {
                double expected = 0.8 * g.lights[0][b] * geometry / kPi;
                EXPECT_NEAR(cube.at(x, y, b), expected, 1e-5 * expected) << x << "," << y;
            }
        }
    }
}

TEST(GpuKnownAnswer, SpecularLobeIsNormalizedBlinnPhong) {
    for (double gloss : {0.0, 1.0, 10.0, 100.0}) {
        for (double thetaDeg : {0.0, 30.0, 60.0}) {
            double theta = thetaDeg * kPi / 180;
            Scene s = emptyScene(Grid{400, 700, 50}, topDown(4));
            s.materials.push_back(glossy(constantSpectrum(0.0), constantSpectrum(1.0), gloss));
            s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 10, 10));
            // Light arrives at θ from the normal; the orthographic view is along the normal,
            // so n·h = cos(θ/2).
            s.lights.push_back(directionalLight({-std::sin(theta), 0, -std::cos(theta)}, testLight(), 1.0));
            SceneOnGrid g = onGrid(s);
            SpectralCube cube = render(s, g);
            double lobe = std::cos(theta) * (gloss + 8) / (8 * kPi) * std::pow(std::cos(theta / 2), gloss);
            for (int b = 0; b < cube.bands(); ++b) {
                double expected = g.lights[0][b] * lobe;
                EXPECT_NEAR(cube.at(1, 2, b), expected, 1e-5 * expected) << "gloss " << gloss << " θ " << thetaDeg;
            }
        }
    }
}

TEST(GpuKnownAnswer, FluorescenceConservesPhotons) {
    // ρd = 0, excitation 0.5 over 300–400 nm, emission a Gaussian at 450 nm, yield Φ, ambient
    // light: π·Σ L(λ)·λ·Δλ (emitted photons, up to hc) = Φ·Σ a·E·λ·Δλ (absorbed photons).
    const double phi = 0.8;
    Scene s = emptyScene(Grid{300, 740, 5}, topDown(4));
    s.materials.push_back(fluorescent(constantSpectrum(0.0), boxSpectrum(300, 400, 0.5, 5),
                                      gaussianSpectrum(450, 15), phi));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 10, 10));
    s.lights.push_back(ambientLight(testLight(), 1.0));
    SceneOnGrid g = onGrid(s);
    SpectralCube cube = render(s, g);
    const auto& E = g.lights[0];
    const auto& a = g.materials[0].excitation;
    double absorbed = 0, emitted = 0;
    for (int b = 0; b < cube.bands(); ++b) {
        double lambda = g.wavelengths_nm[b];
        absorbed += a[b] * E[b] * lambda * 5.0;
        emitted += kPi * cube.at(2, 2, b) * lambda * 5.0;
    }
    EXPECT_NEAR(emitted, phi * absorbed, 1e-5 * absorbed);
    // Emission only where ê is: at 300 nm the Gaussian is 10 σ from its peak.
    EXPECT_LT(cube.at(2, 2, 0), 1e-12 * cube.at(2, 2, (450 - 300) / 5));
}

TEST(GpuKnownAnswer, NoFluorescenceWithoutExcitationOverlap) {
    Scene s = emptyScene(Grid{300, 740, 5}, topDown(4));
    s.materials.push_back(fluorescent(constantSpectrum(0.0), boxSpectrum(300, 350, 0.9, 5),
                                      gaussianSpectrum(450, 15), 1.0));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 10, 10));
    s.lights.push_back(directionalLight({0, 0, -1}, gaussianSpectrum(600, 10, 1.0, 500, 700, 1), 1.0));
    SceneOnGrid g = onGrid(s);
    SpectralCube cube = render(s, g);
    for (int b = 0; b < cube.bands(); ++b) EXPECT_EQ(cube.at(2, 2, b), 0.0f) << "band " << b;
}

TEST(GpuKnownAnswer, EmptySceneAndNoLightsAreBlack) {
    Scene s = emptyScene(Grid{400, 700, 10}, topDown(8));
    SpectralCube empty = render(s, onGrid(s));
    for (float v : empty.data) ASSERT_EQ(v, 0.0f);
    s.materials.push_back(lambertian(1.0));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 10, 10));
    SpectralCube dark = render(s, onGrid(s));
    for (float v : dark.data) ASSERT_EQ(v, 0.0f);
}
