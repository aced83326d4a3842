// Known answers for the CPU reference renderer. Each expectation is written down from the
// physics (docs/physics.md), not from the renderer's own code; pixels are checked in double
// through ReferenceRenderer::pixel before the cube rounds them to float.
#include "reference/cpu_renderer.h"
#include "spectral/resampling.h"

#include "support/scene_builders.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

using namespace metamer;
using namespace metamer::test;

namespace {

constexpr double kPi = std::numbers::pi;
const Grid kGrid{300.0, 740.0, 5.0};  // 89 bands

// A made-up daylight-like SPD (relative, peak ≈ 1.2), covering the whole grid.
Spectrum testIlluminant() {
    return sampledSpectrum({300, 340, 380, 420, 460, 500, 540, 580, 620, 660, 700, 740, 780},
                           {0.05, 0.40, 0.55, 0.90, 1.20, 1.10, 1.05, 0.95, 0.90, 0.85, 0.72, 0.66, 0.60},
                           "test-illuminant");
}

// Silence the coverage warnings of tests whose spectra deliberately stop short of the grid.
struct QuietWarnings {
    WarningSink previous = setWarningSink([](const std::string&) {});
    ~QuietWarnings() { setWarningSink(previous); }
};

std::vector<double> pixelOf(const ReferenceRenderer& r, int x, int y, int32_t* id = nullptr) {
    std::vector<double> out(r.bands());
    int32_t i = r.pixel(x, y, out.data());
    if (id) *id = i;
    return out;
}

void expectRel(double actual, double expected, double tol, const std::string& what) {
    EXPECT_NEAR(actual, expected, tol * std::abs(expected)) << what;
}

// A camera looking down -z at the origin from z = 5, image up = +y.
Camera orthoAlongMinusZ(int w, int h, double height_m) {
    return orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, height_m, w, h);
}

// Every pixel hitting mesh 0 must equal `expected` (per band); returns how many did.
int expectHitsEqual(const ReferenceRenderer& r, const Camera& cam, const std::vector<double>& expected,
                    double tol) {
    int hits = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            int32_t id = 0;
            auto px = pixelOf(r, x, y, &id);
            if (id != 0) continue;
            ++hits;
            for (size_t b = 0; b < px.size(); ++b) {
                if (std::abs(px[b] - expected[b]) > tol * std::abs(expected[b])) {
                    ADD_FAILURE() << "pixel (" << x << "," << y << ") band " << b << ": " << px[b]
                                  << " vs " << expected[b];
                    return hits;
                }
            }
        }
    return hits;
}

}  // namespace

// --- 1. Lambertian quad under a directional light ---------------------------------------------

TEST(ReferenceRenderer, WhiteQuadFacingDirectionalLightIsEOverPi) {
    Camera cam = orthoAlongMinusZ(24, 16, 4.0);
    Scene s = emptyScene(kGrid, cam);
    s.materials.push_back(lambertian(1.0));
    s.lights.push_back(directionalLight({0, 0, -1}, testIlluminant(), 3.0));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 2.0, 2.0));
    SceneOnGrid g = onGrid(s);
    ReferenceRenderer r(s, g);

    std::vector<double> expected(g.lights[0]);
    for (double& v : expected) v /= kPi;
    int hits = expectHitsEqual(r, cam, expected, 1e-12);
    // The quad is 2 m of a 4 m-high, 6 m-wide view at 0.25 m per pixel: 8×8 pixels.
    EXPECT_EQ(hits, 8 * 8);

    // The cube holds the same values rounded to float, background 0.
    ReferenceImage img = r.render();
    EXPECT_FLOAT_EQ(img.cube.at(12, 8, 40), static_cast<float>(expected[40]));
    EXPECT_EQ(img.cube.at(0, 0, 40), 0.0f);
    EXPECT_EQ(img.objectId[0], kBackgroundId);
    EXPECT_EQ(img.objectId[8 * 24 + 12], 0);
}

TEST(ReferenceRenderer, QuadTiltedBy60DegreesIsECos60OverPi) {
    Camera cam = orthoAlongMinusZ(24, 24, 4.0);
    Scene s = emptyScene(kGrid, cam);
    s.materials.push_back(lambertian(1.0));
    s.lights.push_back(directionalLight({0, 0, -1}, testIlluminant(), 2.0));
    const double t = 60.0 * kPi / 180.0;
    s.meshes.push_back(quad({0, 0, 0}, {std::sin(t), 0, std::cos(t)}, 2.0, 2.0));
    SceneOnGrid g = onGrid(s);
    ReferenceRenderer r(s, g);

    std::vector<double> expected(g.lights[0]);
    for (double& v : expected) v *= 0.5 / kPi;
    EXPECT_GT(expectHitsEqual(r, cam, expected, 1e-12), 20);
}

TEST(ReferenceRenderer, DirectionalLightFromBehindTheSurfaceGivesNothing) {
    Camera cam = orthoAlongMinusZ(8, 8, 4.0);
    Scene s = emptyScene(kGrid, cam);
    s.materials.push_back(lambertian(1.0));
    s.lights.push_back(directionalLight({0.3, 0, 1}, testIlluminant()));  // travels towards +z
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 2.0, 2.0));
    SceneOnGrid g = onGrid(s);
    ReferenceRenderer r(s, g);
    int32_t id = -5;
    auto px = pixelOf(r, 4, 4, &id);
    EXPECT_EQ(id, 0);
    for (double v : px) EXPECT_EQ(v, 0.0);
}

TEST(ReferenceRenderer, ShadingNormalIsTheInterpolatedVertexNormal) {
    // One triangle in z = 0 with tilted vertex normals; the ray hits (0.5, 0.25), where the
    // barycentrics are b0 = 0.25, b1 = 0.5, b2 = 0.25.
    Scene s = emptyScene(kGrid, orthoAlongMinusZ(4, 4, 4.0));
    s.materials.push_back(lambertian(1.0));
    s.lights.push_back(directionalLight({0, 0, -1}, testIlluminant()));
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const glm::dvec3 n0(0, 0, 1), n1 = glm::normalize(glm::dvec3(1, 0, 1)),
                     n2 = glm::normalize(glm::dvec3(0, -2, 1));
    m.normals = {n0, n1, n2};
    m.indices = {0, 1, 2};
    s.meshes.push_back(m);
    SceneOnGrid g = onGrid(s);
    std::vector<double> L(g.grid.bands());
    const double cosine = glm::normalize(0.25 * n0 + 0.5 * n1 + 0.25 * n2).z;
    const ReferenceRenderer smooth(s, g);
    const Ray ray{smooth.frame().position({0.5, 0.25, 5.0}), {0, 0, -1}};  // rays live in the renderer's frame
    ASSERT_EQ(smooth.trace(ray, L.data()), 0);
    for (int b = 0; b < g.grid.bands(); ++b) expectRel(L[b], g.lights[0][b] * cosine / kPi, 1e-12, "smooth");

    // Without vertex normals the face normal shades: E/π.
    s.meshes[0].normals.clear();
    ASSERT_EQ(ReferenceRenderer(s, g).trace(ray, L.data()), 0);
    for (int b = 0; b < g.grid.bands(); ++b) expectRel(L[b], g.lights[0][b] / kPi, 1e-12, "flat");
}

// --- 2. Ambient --------------------------------------------------------------------------------

TEST(ReferenceRenderer, AmbientIsRhoEOverPiWhateverTheOrientation) {
    Camera cam = orthoAlongMinusZ(16, 16, 4.0);
    const glm::dvec3 normals[] = {{0, 0, 1}, {1, 0, 1}, {0, -2, 1}, {1, 1, 0.2}, {0, 0, -1}};
    for (const glm::dvec3& n : normals) {
        Scene s = emptyScene(kGrid, cam);
        s.materials.push_back(lambertian(gaussianSpectrum(550, 60, 0.8)));
        s.lights.push_back(ambientLight(testIlluminant(), 5.0));
        s.meshes.push_back(quad({0, 0, 0}, n, 2.0, 2.0));
        SceneOnGrid g = onGrid(s);
        ReferenceRenderer r(s, g);
        std::vector<double> expected(g.grid.bands());
        for (int b = 0; b < g.grid.bands(); ++b)
            expected[b] = g.materials[0].diffuse[b] * g.lights[0][b] / kPi;
        EXPECT_GT(expectHitsEqual(r, cam, expected, 1e-12), 4)
            << "normal " << n.x << "," << n.y << "," << n.z;
    }
}

// --- 3. Point light ----------------------------------------------------------------------------

TEST(ReferenceRenderer, PointLightFallsOffAsCosineOverDistanceSquared) {
    // Floor y = 0 seen from above; image right = +x, image up = -z.
    const int W = 33, H = 33;
    const double heightM = 4.0, h = 1.0, rho = 0.7;
    Camera cam = orthographicCamera({0, 3, 0}, {0, 0, 0}, {0, 0, -1}, heightM, W, H);
    Scene s = emptyScene(kGrid, cam);
    s.materials.push_back(lambertian(rho));
    s.lights.push_back(pointLight({0, h, 0}, testIlluminant(), 10.0));
    s.meshes.push_back(quad({0, 0, 0}, {0, 1, 0}, 10.0, 10.0));
    SceneOnGrid g = onGrid(s);
    ReferenceRenderer r(s, g);
    const std::vector<double>& I = g.lights[0];

    // World position of a pixel centre from the camera convention: r = +x, u = -z, aspect 1.
    auto world = [&](int x, int y) {
        const double ndcX = 2.0 * (x + 0.5) / W - 1.0, ndcY = 1.0 - 2.0 * (y + 0.5) / H;
        return glm::dvec3(ndcX * heightM / 2, 0.0, -ndcY * heightM / 2);
    };
    // The pixel right under the light: ρ·I/(π h²).
    EXPECT_EQ(world(16, 16), glm::dvec3(0.0));
    auto centre = pixelOf(r, 16, 16);
    for (int b = 0; b < r.bands(); ++b) expectRel(centre[b], rho * I[b] / (kPi * h * h), 1e-12, "centre");

    const int probes[][2] = {{20, 16}, {16, 3}, {0, 0}, {32, 10}, {7, 29}, {25, 25}};
    for (const auto& pr : probes) {
        const glm::dvec3 p = world(pr[0], pr[1]);
        const double x2 = p.x * p.x + p.z * p.z;
        const double geometry = h / (kPi * std::pow(h * h + x2, 1.5));
        auto px = pixelOf(r, pr[0], pr[1]);
        for (int b = 0; b < r.bands(); ++b)
            expectRel(px[b], rho * I[b] * geometry, 1e-12,
                      "pixel " + std::to_string(pr[0]) + "," + std::to_string(pr[1]));
    }
    // Off-centre pixels must be dimmer: guards against a missing cosine or distance term.
    EXPECT_LT(pixelOf(r, 0, 0)[40], 0.2 * centre[40]);
}

// --- 4. Specular -------------------------------------------------------------------------------

TEST(ReferenceRenderer, SpecularLobeIsNormalizedBlinnPhong) {
    Camera cam = orthoAlongMinusZ(8, 8, 4.0);
    for (double N : {0.0, 1.0, 10.0, 100.0}) {
        for (double deg : {0.0, 20.0, 45.0, 70.0}) {
            const double th = deg * kPi / 180.0;
            Scene s = emptyScene(kGrid, cam);
            s.materials.push_back(glossy(constantSpectrum(0.0), constantSpectrum(1.0), N));
            // Arriving from direction (sin θ, 0, cos θ): it travels the opposite way.
            s.lights.push_back(directionalLight({-std::sin(th), 0, -std::cos(th)}, testIlluminant(), 2.0));
            s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 2.0, 2.0));
            SceneOnGrid g = onGrid(s);
            ReferenceRenderer r(s, g);
            const double lobe =
                std::cos(th) * (N + 8) / (8 * kPi) * (N == 0 ? 1.0 : std::pow(std::cos(th / 2), N));
            auto px = pixelOf(r, 4, 4);
            for (int b = 0; b < r.bands(); ++b)
                expectRel(px[b], g.lights[0][b] * lobe, 1e-12,
                          "N=" + std::to_string(N) + " θ=" + std::to_string(deg));
        }
    }
}

TEST(ReferenceRenderer, SpecularFromBehindTheSurfaceIsZero) {
    Camera cam = orthoAlongMinusZ(8, 8, 4.0);
    for (double N : {0.0, 1.0, 10.0, 100.0}) {
        Scene s = emptyScene(kGrid, cam);
        s.materials.push_back(glossy(constantSpectrum(0.0), constantSpectrum(1.0), N));
        s.lights.push_back(directionalLight({-0.5, 0, 1}, testIlluminant()));  // hits the back
        s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 2.0, 2.0));
        SceneOnGrid g = onGrid(s);
        ReferenceRenderer r(s, g);
        int32_t id = -5;
        auto px = pixelOf(r, 4, 4, &id);
        EXPECT_EQ(id, 0);
        for (double v : px) EXPECT_EQ(v, 0.0) << "N=" << N;
    }
}

TEST(ReferenceRenderer, BackFaceIsShadedAsSeenFromItsFront) {
    // The quad's normal points to +z but camera and light are both on the -z side: the back face
    // must look exactly as the front does in the mirrored setup.
    const double th = 30.0 * kPi / 180.0;
    auto render = [&](double side) {
        Camera cam = orthographicCamera({0, 0, 5 * side}, {0, 0, 0}, {0, 1, 0}, 4.0, 8, 8);
        Scene s = emptyScene(kGrid, cam);
        s.materials.push_back(glossy(constantSpectrum(0.5), constantSpectrum(0.3), 20));
        s.lights.push_back(directionalLight({-std::sin(th), 0, -std::cos(th) * side}, testIlluminant()));
        s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 2.0, 2.0));
        SceneOnGrid g = onGrid(s);
        return pixelOf(ReferenceRenderer(s, g), 4, 4);
    };
    auto front = render(1.0), back = render(-1.0);
    EXPECT_GT(front[40], 0.0);
    for (size_t b = 0; b < front.size(); ++b) expectRel(back[b], front[b], 1e-12, "band");
}

// --- 5. Fluorescence ---------------------------------------------------------------------------

namespace {

struct FluorescentSetup {
    Scene scene;
    SceneOnGrid g;
};

// ρd = 0, a = 0.5 over 300–400 nm (0 up to 450 nm), emission a Gaussian at 450 nm, Φ = 0.8.
FluorescentSetup fluorescentQuad(const Grid& grid, Light light) {
    QuietWarnings quiet;
    FluorescentSetup f;
    f.scene = emptyScene(grid, orthoAlongMinusZ(8, 8, 4.0));
    Spectrum excitation = sampledSpectrum({300, 400, 400.001, 450}, {0.5, 0.5, 0.0, 0.0}, "uv-box");
    f.scene.materials.push_back(
        fluorescent(constantSpectrum(0.0), excitation, gaussianSpectrum(450, 15, 2.0, 350, 550), 0.8));
    f.scene.lights.push_back(std::move(light));
    f.scene.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 2.0, 2.0));
    f.g = onGrid(f.scene);
    return f;
}

// π·Σ L(λ)·λ·Δλ: the emitted photon exitance, up to the factor 1/(hc) common to both sides.
double photonExitance(const std::vector<double>& L, const SceneOnGrid& g) {
    double sum = 0.0;
    for (size_t b = 0; b < L.size(); ++b) sum += L[b] * g.wavelengths_nm[b] * g.grid.step_nm;
    return kPi * sum;
}

// Σ a·E·λ·Δλ over the grid: the absorbed photon irradiance, same units.
double absorbedPhotons(const SceneOnGrid& g, double geometry) {
    double sum = 0.0;
    const auto& m = g.materials[0];
    for (int b = 0; b < g.grid.bands(); ++b)
        sum += m.excitation[b] * g.lights[0][b] * geometry * g.wavelengths_nm[b] * g.grid.step_nm;
    return sum;
}

}  // namespace

TEST(ReferenceRenderer, FluorescenceConservesPhotons) {
    auto f = fluorescentQuad(kGrid, ambientLight(testIlluminant(), 4.0));
    ReferenceRenderer r(f.scene, f.g);
    auto L = pixelOf(r, 4, 4);
    const double absorbed = absorbedPhotons(f.g, 1.0);
    ASSERT_GT(absorbed, 0.0);
    expectRel(photonExitance(L, f.g), 0.8 * absorbed, 1e-9, "photon balance");
    // The light shows up around 450 nm only: nothing where the emission is 0.
    EXPECT_GT(L[30], 0.0);  // 450 nm
    EXPECT_EQ(L[80], 0.0);  // 700 nm
    EXPECT_EQ(L[0], 0.0);   // 300 nm: absorbed, not reflected (ρd = 0)
}

TEST(ReferenceRenderer, FluorescenceUnderDirectionalLightScalesWithCosine) {
    const double th = 50.0 * kPi / 180.0;
    auto f = fluorescentQuad(kGrid, directionalLight({std::sin(th), 0, -std::cos(th)}, testIlluminant()));
    auto L = pixelOf(ReferenceRenderer(f.scene, f.g), 4, 4);
    expectRel(photonExitance(L, f.g), 0.8 * absorbedPhotons(f.g, std::cos(th)), 1e-9, "photon balance");
}

TEST(ReferenceRenderer, FluorescenceWithoutExcitationOverlapIsExactlyZero) {
    // The light has no power below 500 nm, where all the excitation is.
    Spectrum red = sampledSpectrum({500, 780}, {1.0, 1.0}, "red");
    auto f = fluorescentQuad(kGrid, ambientLight(red, 10.0));
    auto L = pixelOf(ReferenceRenderer(f.scene, f.g), 4, 4);
    for (double v : L) EXPECT_EQ(v, 0.0);
}

TEST(ReferenceRenderer, ExcitationOutsideTheGridCausesNoEmission) {
    // The same material on a grid starting at 405 nm: its UV excitation is not on the grid, so
    // the Riemann sum, and with it the emission, is exactly 0; on a UV grid it is not.
    auto onVisible = fluorescentQuad(Grid{405, 740, 5}, ambientLight(testIlluminant(), 4.0));
    for (double v : pixelOf(ReferenceRenderer(onVisible.scene, onVisible.g), 4, 4)) EXPECT_EQ(v, 0.0);
    auto onUv = fluorescentQuad(kGrid, ambientLight(testIlluminant(), 4.0));
    EXPECT_GT(pixelOf(ReferenceRenderer(onUv.scene, onUv.g), 4, 4)[30], 0.0);
}

TEST(ReferenceRenderer, EmissionOutsideTheGridIsLostNotRescaled) {
    // Grid 300–460 nm cuts the 450 nm emission: only the part of ê on the grid's bands (Σ ê·Δλ,
    // about its integral up to 462.5 nm) is emitted into the cube; ê stays normalized by the
    // integral of its own data.
    const Grid grid{300, 460, 5};
    auto f = fluorescentQuad(grid, ambientLight(testIlluminant(), 4.0));
    auto L = pixelOf(ReferenceRenderer(f.scene, f.g), 4, 4);
    const Spectrum& em = f.scene.materials[0].fluorescence->emission.spectrum;
    double inside = 0;
    for (double v : resample(em, grid)) inside += v * grid.step_nm / em.integral();
    EXPECT_NEAR(inside, em.integrate(297.5, 462.5) / em.integral(), 2e-3);
    ASSERT_LT(inside, 0.85);
    expectRel(photonExitance(L, f.g), 0.8 * absorbedPhotons(f.g, 1.0) * inside, 1e-9, "balance");
}

// --- 6. Camera conventions ---------------------------------------------------------------------

namespace {

// Renders a 0.1 m quad facing the camera at world (xw, yw, 0) and checks that exactly pixel
// (px, py) sees it.
void expectOnlyPixel(const Camera& cam, double xw, double yw, int px, int py) {
    Scene s = emptyScene(kGrid, cam);
    s.materials.push_back(lambertian(1.0));
    s.lights.push_back(ambientLight(testIlluminant()));
    s.meshes.push_back(quad({xw, yw, 0}, {0, 0, 1}, 0.1, 0.1));
    SceneOnGrid g = onGrid(s);
    ReferenceImage img = renderReference(s, g);
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            const bool expectHit = x == px && y == py;
            EXPECT_EQ(img.objectId[y * cam.width + x], expectHit ? 0 : kBackgroundId)
                << "pixel " << x << "," << y;
            EXPECT_EQ(img.cube.at(x, y, 40) > 0.0f, expectHit) << "pixel " << x << "," << y;
        }
}

}  // namespace

TEST(ReferenceRenderer, PerspectiveCameraPutsAPointAtTheExpectedPixel) {
    // 64×32 (aspect 2), fov 90° (tan = 1), 5 m away. Pixel (40, 8): its centre (40.5, 8.5) has
    // ndc (0.265625, 0.46875), i.e. world x = 0.265625·1·2·5, y = 0.46875·1·5: right of and above
    // the centre, so a column > 32 and a row < 16 (row 0 at the top).
    Camera cam = perspectiveCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 90.0, 64, 32);
    expectOnlyPixel(cam, 2.65625, 2.34375, 40, 8);
    expectOnlyPixel(cam, -2.65625, -2.34375, 23, 23);
}

TEST(ReferenceRenderer, OrthographicCameraPutsAPointAtTheExpectedPixel) {
    // 64×32, 4 m high (8 m wide): world x = ndc_x·2·2, y = ndc_y·2.
    Camera cam = orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 4.0, 64, 32);
    expectOnlyPixel(cam, 0.265625 * 4, 0.46875 * 2, 40, 8);
    expectOnlyPixel(cam, -0.265625 * 4, -0.46875 * 2, 23, 23);
}

TEST(ReferenceRenderer, ObjectIdsNameTheMeshAndTheBackground) {
    Camera cam = orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 8.0, 8, 8);  // 1 m per pixel
    Scene s = emptyScene(kGrid, cam);
    s.materials.push_back(lambertian(1.0));
    s.materials.push_back(lambertian(0.5));
    s.lights.push_back(ambientLight(testIlluminant()));
    s.meshes.push_back(quad({-2, 0, 0}, {0, 0, 1}, 2.0, 2.0, 1));  // columns 1–2, rows 3–4
    s.meshes.push_back(quad({2, 0, 0}, {0, 0, 1}, 2.0, 2.0, 0));   // columns 5–6
    SceneOnGrid g = onGrid(s);
    ReferenceImage img = renderReference(s, g);
    auto id = [&](int x, int y) { return img.objectId[y * 8 + x]; };
    EXPECT_EQ(id(1, 3), 0);
    EXPECT_EQ(id(2, 4), 0);
    EXPECT_EQ(id(5, 3), 1);
    EXPECT_EQ(id(6, 4), 1);
    EXPECT_EQ(id(0, 0), kBackgroundId);
    EXPECT_EQ(id(3, 3), kBackgroundId);
    EXPECT_EQ(id(1, 2), kBackgroundId);
    // Mesh 0 uses material 1 (ρ = 0.5), mesh 1 material 0 (ρ = 1).
    EXPECT_FLOAT_EQ(img.cube.at(1, 3, 40), static_cast<float>(0.5 * g.lights[0][40] / kPi));
    EXPECT_FLOAT_EQ(img.cube.at(5, 3, 40), static_cast<float>(g.lights[0][40] / kPi));
}

TEST(ReferenceRenderer, SupersamplingAveragesSubSamplesAtAnEdge) {
    // 1 m per pixel: world x = px - 4. The quad ends at x = 0.5, the middle of column 4; with
    // ssaa 2 or 4, half of that column's sub-samples hit it.
    Camera cam = orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 8.0, 8, 8);
    Scene s = emptyScene(kGrid, cam);
    s.materials.push_back(lambertian(1.0));
    s.lights.push_back(ambientLight(testIlluminant()));
    s.meshes.push_back(quad({-2, 0, 0}, {0, 0, 1}, 5.0, 20.0));
    SceneOnGrid g = onGrid(s);
    for (int ssaa : {2, 4}) {
        ReferenceOptions opt;
        opt.ssaa = ssaa;
        ReferenceRenderer r(s, g, opt);
        int32_t id3 = 0, id4 = 0, id5 = 0;
        auto inside = pixelOf(r, 3, 2, &id3), edge = pixelOf(r, 4, 2, &id4), outside = pixelOf(r, 5, 2, &id5);
        EXPECT_EQ(id3, 0);
        EXPECT_EQ(id4, kMixedId);
        EXPECT_EQ(id5, kBackgroundId);
        for (int b = 0; b < r.bands(); ++b) {
            expectRel(inside[b], g.lights[0][b] / kPi, 1e-12, "inside");
            expectRel(edge[b], 0.5 * g.lights[0][b] / kPi, 1e-12, "edge");
            EXPECT_EQ(outside[b], 0.0);
        }
        ReferenceImage img = r.render();
        EXPECT_EQ(img.objectId[2 * 8 + 4], kMixedId);
        EXPECT_FLOAT_EQ(img.cube.at(4, 2, 40), static_cast<float>(edge[40]));
    }
}

// --- 7. Linearity in the lights ----------------------------------------------------------------

TEST(ReferenceRenderer, SixteenLightsSumLinearly) {
    QuietWarnings quiet;  // the excitation and emission data stop short of the grid
    Camera cam = perspectiveCamera({0.5, 1.0, 4.0}, {0, 0, 0}, {0, 1, 0}, 40.0, 20, 16);
    Scene s = emptyScene(kGrid, cam);
    s.materials.push_back(fluorescent(gaussianSpectrum(600, 50, 0.6),
                                      sampledSpectrum({300, 420, 440}, {0.3, 0.3, 0.0}),
                                      gaussianSpectrum(500, 20, 1.0, 400, 600), 0.7));
    s.materials.back().specular = sceneSpectrum(constantSpectrum(0.04), SpectrumKind::Reflectance);
    s.materials.back().gloss = 30;
    s.meshes.push_back(sphere({0, 0, 0}, 1.0, 32, 16));
    s.meshes.push_back(quad({0, -1, 0}, {0, 1, 0}, 6.0, 6.0));
    for (int l = 0; l < 16; ++l) {
        Spectrum spd = gaussianSpectrum(320 + 25 * l, 40, 1.0, 300, 780);
        const double a = 0.4 * l;
        if (l % 3 == 0)
            s.lights.push_back(ambientLight(spd, 0.1 * (l + 1)));
        else if (l % 3 == 1)
            s.lights.push_back(directionalLight({std::cos(a), -1.0, std::sin(a)}, spd, 0.5 + 0.1 * l));
        else
            s.lights.push_back(pointLight({2 * std::cos(a), 1.5, 2 * std::sin(a)}, spd, 2.0 + l));
    }
    SceneOnGrid g = onGrid(s);
    ReferenceRenderer all(s, g);

    std::vector<std::vector<double>> sum(cam.width * cam.height, std::vector<double>(g.grid.bands(), 0.0));
    for (int l = 0; l < 16; ++l) {
        Scene one = s;
        one.lights = {s.lights[l]};
        SceneOnGrid gOne = g;
        gOne.lights = {g.lights[l]};
        ReferenceRenderer r(one, gOne);
        for (int y = 0; y < cam.height; ++y)
            for (int x = 0; x < cam.width; ++x) {
                auto px = pixelOf(r, x, y);
                for (int b = 0; b < r.bands(); ++b) sum[y * cam.width + x][b] += px[b];
            }
    }
    int lit = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            auto px = pixelOf(all, x, y);
            const auto& expected = sum[y * cam.width + x];
            double peak = 0.0;
            for (double v : expected) peak = std::max(peak, std::abs(v));
            lit += peak > 0.0;
            for (int b = 0; b < all.bands(); ++b)
                ASSERT_NEAR(px[b], expected[b], 1e-12 * peak) << x << "," << y << " band " << b;
        }
    EXPECT_GT(lit, cam.width * cam.height / 2);
}

// --- Threads, options ---------------------------------------------------------------------------

TEST(ReferenceRenderer, ThreadCountDoesNotChangeTheImage) {
    Camera cam = perspectiveCamera({0, 0.5, 4.0}, {0, 0, 0}, {0, 1, 0}, 35.0, 24, 20);
    Scene s = emptyScene(kGrid, cam);
    s.materials.push_back(glossy(gaussianSpectrum(600, 50, 0.6), constantSpectrum(0.1), 40));
    s.lights.push_back(directionalLight({-1, -1, -1}, testIlluminant()));
    s.lights.push_back(pointLight({1, 2, 2}, testIlluminant(), 5));
    s.meshes.push_back(sphere({0, 0, 0}, 1.0, 24, 12));
    SceneOnGrid g = onGrid(s);
    ReferenceImage one = renderReference(s, g, {2, 1});
    ReferenceImage many = renderReference(s, g, {2, 5});
    EXPECT_EQ(one.cube.data, many.cube.data);
    EXPECT_EQ(one.objectId, many.objectId);
    EXPECT_EQ(one.cube.width, 24);
    EXPECT_EQ(one.cube.height, 20);
    EXPECT_EQ(one.cube.bands(), 89);
}

TEST(ReferenceRenderer, RejectsBadOptionsAndCameras) {
    Scene s = emptyScene(kGrid, orthoAlongMinusZ(8, 8, 4.0));
    s.materials.push_back(lambertian(1.0));
    SceneOnGrid g = onGrid(s);
    auto code = [&](const Scene& sc, ReferenceOptions o) {
        try {
            ReferenceRenderer r(sc, g, o);
        } catch (const Error& e) {
            return e.code();
        }
        return ExitCode::Ok;
    };
    EXPECT_EQ(code(s, {0, 0}), ExitCode::BadInput);
    EXPECT_EQ(code(s, {1, -1}), ExitCode::BadInput);
    EXPECT_EQ(code(s, {1, 0}), ExitCode::Ok);
    Scene bad = s;
    bad.camera.up = {0, 0, 1};  // parallel to the view direction
    EXPECT_EQ(code(bad, {}), ExitCode::BadInput);
    bad = s;
    bad.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 1.0, 1.0, 3));  // no material 3
    EXPECT_EQ(code(bad, {}), ExitCode::BadInput);
    bad = s;
    bad.lights.push_back(ambientLight(testIlluminant()));  // not in g
    EXPECT_EQ(code(bad, {}), ExitCode::Failure);
}

TEST(ReferenceRenderer, EmptySceneIsBlack) {
    Scene s = emptyScene(kGrid, orthoAlongMinusZ(4, 3, 4.0));
    s.lights.push_back(ambientLight(testIlluminant()));
    SceneOnGrid g = onGrid(s);
    ReferenceImage img = renderReference(s, g);
    EXPECT_EQ(img.cube.data, std::vector<float>(4 * 3 * 89, 0.0f));
    EXPECT_EQ(img.objectId, std::vector<int32_t>(12, kBackgroundId));
}

// Timing of the brief's benchmark (run with --gtest_also_run_disabled_tests): 256×256, 89 bands,
// a 16 128-triangle sphere, 3 lights.
TEST(ReferenceRenderer, DISABLED_TimingSphere256) {
    Camera cam = perspectiveCamera({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 35.0, 256, 256);
    Scene s = emptyScene(kGrid, cam);
    s.materials.push_back(glossy(gaussianSpectrum(600, 50, 0.6), constantSpectrum(0.1), 40));
    s.meshes.push_back(sphere({0, 0, 0}, 1.0, 128, 64));
    ASSERT_EQ(s.triangleCount(), 16128u);
    s.lights.push_back(ambientLight(testIlluminant(), 0.1));
    s.lights.push_back(directionalLight({-1, -1, -1}, testIlluminant()));
    s.lights.push_back(pointLight({1, 2, 2}, testIlluminant(), 5));
    SceneOnGrid g = onGrid(s);
    for (int ssaa : {1, 2}) {
        auto t0 = std::chrono::steady_clock::now();
        ReferenceImage img = renderReference(s, g, {ssaa, 0});
        double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        std::printf("reference 256x256x89, 16128 triangles, 3 lights, ssaa %d: %.1f ms\n", ssaa, ms);
        EXPECT_EQ(img.objectId[128 * 256 + 128], 0);
    }
}
