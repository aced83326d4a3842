// Interreflection through the GPU spectral pass (docs/physics.md, "Interreflection"): known
// answers a renderer of light that bounces must give, without the CPU reference.
#include "radiosity/form_factor.h"
#include "radiosity/scene_radiosity.h"
#include "reference/cpu_renderer.h"
#include "render/spectral_pass.h"
#include "support/gpu.h"
#include "support/scene_builders.h"

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace metamer;
using namespace metamer::test;

namespace {

constexpr double kPi = std::numbers::pi;

// The inside of a unit cube: six quads facing in, all of material 0, seen from inside.
Scene closedRoom(double rho, Spectrum light, double elementSize) {
    Scene s = emptyScene(Grid{400, 700, 10},
                         perspectiveCamera({0.5, 0.5, 0.95}, {0.5, 0.45, 0.0}, {0, 1, 0}, 100.0, 24, 24));
    s.materials.push_back(lambertian(rho));
    s.lights.push_back(ambientLight(std::move(light)));
    s.meshes = insideOfUnitCube(0);
    s.interreflection = Interreflection{elementSize, 1e-8, 6000, Where{"room", "interreflection"}};
    return s;
}

// A room the way people light one: a white floor, ceiling and back wall, a red left wall, the
// right wall green (or red too), a white box standing on the floor (its five visible faces as
// quads facing out), a point light under the ceiling; seen from the open front, 40 × 40.
Scene roomWithABox(const Grid& grid, bool greenRightWall) {
    Scene s = emptyScene(grid, perspectiveCamera({0.5, 0.5, 1.9}, {0.5, 0.5, 0.0}, {0, 1, 0}, 40.0, 40, 40));
    s.materials.push_back(lambertian(0.75, "white"));
    s.materials.push_back(lambertian(boxSpectrum(590, 700, 0.7), "red"));
    if (greenRightWall) s.materials.push_back(lambertian(boxSpectrum(490, 570, 0.6), "green"));
    s.meshes.push_back(quad({0.5, 0, 0.5}, {0, 1, 0}, 1, 1, 0));
    s.meshes.push_back(quad({0.5, 1, 0.5}, {0, -1, 0}, 1, 1, 0));
    s.meshes.push_back(quad({0.5, 0.5, 0}, {0, 0, 1}, 1, 1, 0));
    s.meshes.push_back(quad({0, 0.5, 0.5}, {1, 0, 0}, 1, 1, 1));
    s.meshes.push_back(quad({1, 0.5, 0.5}, {-1, 0, 0}, 1, 1, greenRightWall ? 2 : 1));
    const glm::dvec3 c(0.65, 0.15, 0.4);
    for (const glm::dvec3 n : {glm::dvec3(1, 0, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1),
                               glm::dvec3(0, 0, -1)})
        s.meshes.push_back(quad(c + 0.15 * n, n, 0.3, 0.3, 0));
    s.lights.push_back(pointLight({0.5, 0.9, 0.5}, constantSpectrum(1.0), 0.05));
    return s;
}

// |Σ_bands a / Σ_bands b − 1| at every pixel whose 3 × 3 neighbourhood is one object (`objectId`,
// the reference's), away from the image's border, sorted.
std::vector<double> interiorDifferences(const SpectralCube& a, const SpectralCube& b, const std::vector<int32_t>& objectId) {
    std::vector<double> relative;
    for (int y = 1; y + 1 < b.height; ++y)
        for (int x = 1; x + 1 < b.width; ++x) {
            const int32_t id = objectId[size_t(y * b.width + x)];
            bool interior = id >= 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) interior = interior && objectId[size_t((y + dy) * b.width + x + dx)] == id;
            if (!interior) continue;
            double sa = 0.0, sb = 0.0;
            for (int band = 0; band < a.bands(); ++band) {
                sa += a.at(x, y, band);
                sb += b.at(x, y, band);
            }
            if (sb > 0.0) relative.push_back(std::fabs(sa / sb - 1.0));
        }
    std::sort(relative.begin(), relative.end());
    return relative;
}

}  // namespace

// A closed room of uniform reflectance ρ under an ambient light of irradiance E: a furnace. Every
// wall sends ρE of its own and receives what all send, B = ρE/(1 − ρ); what a pixel sees is
// B/π = ρE/(π(1 − ρ)) — the direct ρE/π plus the indirect ρ·H/π, H = B — wherever it looks,
// corners and edges included, at any element size.
TEST(Interreflection, AClosedRoomIsAFurnaceOnTheGpu) {
    for (double size : {0.5, 0.2}) {
        SCOPED_TRACE(size);
        const double rho = 0.7;
        const Scene s = closedRoom(rho, gaussianSpectrum(550, 80, 2.0, 300, 800, 1), size);
        const SceneOnGrid g = onGrid(s);
        const uint32_t before = gpu().validationErrors();
        SpectralPass pass(gpu(), s, g);
        const SpectralCube cube = pass.render();
        EXPECT_NO_VALIDATION_ERRORS(before);
        EXPECT_NE(pass.plan().describe().find("interreflection:"), std::string::npos);
        double worst = 0.0;
        for (int y = 0; y < cube.height; ++y)
            for (int x = 0; x < cube.width; ++x)
                for (int b = 0; b < cube.bands(); ++b) {
                    const double expected = rho * g.lights[0][size_t(b)] / (kPi * (1.0 - rho));
                    worst = std::max(worst, std::fabs(cube.at(x, y, b) / expected - 1.0));
                }
        EXPECT_LT(worst, 2e-5);
    }
}

// The furnace itself: a closed room whose every wall emits L_e from its inside and reflects
// ρ. Each wall sends B = πL_e + ρB, so B = πL_e/(1 − ρ), and every pixel sees B/π = L_e/(1 − ρ) — the
// emitted L_e, per pixel, plus the indirect ρH/π — on both renderers, each its own way.
TEST(Interreflection, AClosedRoomOfEmittingWallsIsAFurnaceOnBothRenderers) {
    const double rho = 0.6;
    Scene s = closedRoom(rho, constantSpectrum(0.0), 0.25);
    s.lights.clear();
    s.materials[0] = emitting(s.materials[0], gaussianSpectrum(520, 60, 3.0, 300, 800, 1));
    const SceneOnGrid g = onGrid(s);
    const uint32_t before = gpu().validationErrors();
    SpectralPass pass(gpu(), s, g);
    const SpectralCube cube = pass.render();
    EXPECT_NO_VALIDATION_ERRORS(before);
    s.camera.width = s.camera.height = 8;
    const ReferenceImage image = renderReference(s, g);
    for (const SpectralCube* c : {&cube, &image.cube}) {
        double worst = 0.0;
        for (int y = 0; y < c->height; ++y)
            for (int x = 0; x < c->width; ++x)
                for (int b = 0; b < c->bands(); ++b) {
                    const double expected = g.materials[0].emitted[size_t(b)] / (1.0 - rho);
                    worst = std::max(worst, std::fabs(c->at(x, y, b) / expected - 1.0));
                }
        EXPECT_LT(worst, c == &cube ? 2e-5 : 1e-6) << (c == &cube ? "GPU" : "reference");
    }
}

// A black wall emitting L_e stands at the edge of a grey floor, which nothing else lights: every
// floor pixel is ρ·L_e·F, F the closed-form factor from its centre to the wall — the emitter's
// direct light drawn per pixel, not interpolated between the element vertices (whose spacing,
// 0.25 m, is far coarser than F's curvature at the wall's foot).
TEST(Interreflection, AnEmittingWallLightsTheFloorByItsClosedFormPerPixel) {
    const double rho = 0.5;
    const int size = 32;
    Scene s = emptyScene(Grid{400, 700, 10}, orthographicCamera({0.5, 2.0, 0.5}, {0.5, 0.0, 0.5}, {0, 0, -1}, 1.0, size, size));
    s.materials.push_back(lambertian(rho, "floor"));
    s.materials.push_back(emitting(lambertian(0.0, "wall"), gaussianSpectrum(560, 70, 2.0, 300, 800, 1)));
    s.meshes.push_back(quad({0.5, 0.0, 0.5}, {0, 1, 0}, 1.0, 1.0, 0));
    const Mesh wall = quad({1.0, 0.25, 0.5}, {-1, 0, 0}, 1.0, 0.5, 1);
    s.meshes.push_back(wall);
    s.interreflection = Interreflection{0.25, 1e-10, 6000, Where{"wall", "interreflection"}};
    s.interreflection->refine = 0;
    const SceneOnGrid g = onGrid(s);
    const uint32_t before = gpu().validationErrors();
    SpectralPass pass(gpu(), s, g);
    const SpectralCube cube = pass.render();
    EXPECT_NO_VALIDATION_ERRORS(before);
    const ReferenceImage image = renderReference(s, g);
    for (const SpectralCube* c : {&cube, &image.cube}) {
        double worst = 0.0;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size - 1; ++x) {  // the last column touches the wall's foot
                const glm::dvec3 at((x + 0.5) / size, 0.0, (y + 0.5) / size);
                double F = 0.0;
                for (size_t t = 0; t < 2; ++t) {
                    const std::array<glm::dvec3, 3> tri{wall.positions[wall.indices[3 * t]], wall.positions[wall.indices[3 * t + 1]],
                                                        wall.positions[wall.indices[3 * t + 2]]};
                    F += radiosity::pointToTriangle(at, {0, 1, 0}, tri, radiosity::polygonNormal(tri));
                }
                for (int b = 0; b < c->bands(); b += 5) {
                    const double expected = rho * g.materials[1].emitted[size_t(b)] * F;
                    worst = std::max(worst, std::fabs(c->at(x, y, b) / expected - 1.0));
                }
            }
        // The reference integrates the wall's patches by a 6 × 6 midpoint rule (indirect_light.h):
        // 0.3 % at most here; the GPU's closed form in float, 1e-5.
        EXPECT_LT(worst, c == &cube ? 2e-4 : 5e-3) << (c == &cube ? "GPU" : "reference");
    }
}

// Past what the GPU draws per pixel (kMaxPixelEmitterTriangles), the emitters' direct light comes
// from the vertices with the rest of H: the room of emitting walls, each wall 8 × 8 quads (768
// triangles), is still the furnace L_e/(1 − ρ) at every pixel.
TEST(Interreflection, ManyEmittingTrianglesFallBackToTheVertices) {
    const double rho = 0.6;
    Scene s = closedRoom(rho, constantSpectrum(0.0), 0.25);
    s.lights.clear();
    s.materials[0] = emitting(s.materials[0], gaussianSpectrum(520, 60, 3.0, 300, 800, 1));
    for (Mesh& wall : s.meshes) {  // each quad cut into 8 × 8, wound as it was
        const glm::dvec3 o = wall.positions[0], u = wall.positions[1] - o, v = wall.positions[3] - o;
        Mesh grid;
        grid.material = wall.material;
        grid.name = wall.name;
        for (int i = 0; i <= 8; ++i)
            for (int j = 0; j <= 8; ++j) grid.positions.push_back(o + u * (j / 8.0) + v * (i / 8.0));
        for (uint32_t i = 0; i < 8; ++i)
            for (uint32_t j = 0; j < 8; ++j) {
                const uint32_t a = i * 9 + j, b = a + 1, c = a + 10, d = a + 9;
                grid.indices.insert(grid.indices.end(), {a, b, c, a, c, d});
            }
        wall = grid;
    }
    const SceneOnGrid g = onGrid(s);
    const radiosity::SceneInterreflection r = radiosity::solveInterreflection(s, g);
    EXPECT_TRUE(r.emitters.empty());
    SpectralPass pass(gpu(), s, g);
    const SpectralCube cube = pass.render();
    double worst = 0.0;
    for (int y = 0; y < cube.height; ++y)
        for (int x = 0; x < cube.width; ++x)
            for (int b = 0; b < cube.bands(); ++b)
                worst = std::max(worst, std::fabs(cube.at(x, y, b) / (g.materials[0].emitted[size_t(b)] / (1.0 - rho)) - 1.0));
    EXPECT_LT(worst, 2e-5);
}

// The emitters' spectra take the light spectra's slots after the lights: a scene whose 128 lights
// fill them all and that has an emitter is refused, naming the interreflection key.
TEST(Interreflection, LightsAndEmittersPastTheSpectraSlotsAreRefused) {
    Scene s = closedRoom(0.5, constantSpectrum(0.0), 0.5);
    s.lights.clear();
    for (int i = 0; i < 128; ++i) s.lights.push_back(ambientLight(constantSpectrum(0.01)));
    s.materials[0] = emitting(s.materials[0], constantSpectrum(1.0));
    const SceneOnGrid g = onGrid(s);
    try {
        SpectralPass pass(gpu(), s, g);
        FAIL() << "expected a refusal";
    } catch (const Error& e) {
        EXPECT_NE(e.text().find("interreflection"), std::string::npos) << e.text();
        EXPECT_NE(e.text().find("128 lights and 1 emitting materials"), std::string::npos) << e.text();
    }
}

// Without the key nothing changes (the same scene without it renders the direct light only: ρE/π).
TEST(Interreflection, WithoutTheKeyOnlyTheDirectLight) {
    Scene s = closedRoom(0.7, constantSpectrum(1.0), 0.5);
    s.interreflection.reset();
    const SceneOnGrid g = onGrid(s);
    SpectralPass pass(gpu(), s, g);
    const SpectralCube cube = pass.render();
    EXPECT_EQ(pass.plan().describe().find("interreflection"), std::string::npos);
    for (int b = 0; b < cube.bands(); ++b) EXPECT_NEAR(cube.at(12, 12, b), 0.7 / kPi, 1e-6);
}

// The same furnace on the CPU reference, its own way (patches, ray-cast form factors whose rows
// sum to exactly 1 in a closed room, Gauss–Seidel, a final gather): ρE/(π(1 − ρ)) everywhere.
TEST(Interreflection, AClosedRoomIsAFurnaceOnTheReference) {
    const double rho = 0.7;
    Scene s = closedRoom(rho, gaussianSpectrum(550, 80, 2.0, 300, 800, 1), 0.5);
    s.camera.width = s.camera.height = 8;
    const SceneOnGrid g = onGrid(s);
    const ReferenceImage image = renderReference(s, g);
    double worst = 0.0;
    for (int y = 0; y < image.cube.height; ++y)
        for (int x = 0; x < image.cube.width; ++x)
            for (int b = 0; b < image.cube.bands(); ++b) {
                const double expected = rho * g.lights[0][size_t(b)] / (kPi * (1.0 - rho));
                worst = std::max(worst, std::fabs(image.cube.at(x, y, b) / expected - 1.0));
            }
    EXPECT_LT(worst, 1e-6);
}

// A room the way people light one — coloured walls, a box casting a shadow, a point light under
// the ceiling — on both renderers, each solved its own way (radiosity/ on the GPU: conforming
// elements, closed-form factors, conjugate gradients, vertices; the reference: patches, ray-cast
// factors, Gauss–Seidel, a final gather): away from the edges between objects, their radiance
// agrees to 1.5 % in the median pixel and 5 % in the 95th percentile (the reference's quadrature,
// measured: docs/physics.md, "Interreflection").
TEST(Interreflection, TheGpuAgreesWithTheReferenceInAColouredRoom) {
    Scene s = roomWithABox(Grid{400, 700, 20}, true);
    s.interreflection = Interreflection{0.15, 1e-6, 6000, Where{"room", "interreflection"}};
    const SceneOnGrid g = onGrid(s);
    const uint32_t before = gpu().validationErrors();
    SpectralPass pass(gpu(), s, g);
    const SpectralCube gpuCube = pass.render();
    EXPECT_NO_VALIDATION_ERRORS(before);
    const ReferenceImage cpu = renderReference(s, g);
    const std::vector<double> relative = interiorDifferences(gpuCube, cpu.cube, cpu.objectId);
    ASSERT_GT(relative.size(), 800u);
    const double median = relative[relative.size() / 2], p95 = relative[relative.size() * 95 / 100];
    std::printf("GPU against the reference, %zu interior pixels: median %.4f, p95 %.4f, max %.4f\n", relative.size(), median,
                p95, relative.back());
    EXPECT_LT(median, 0.015);
    EXPECT_LT(p95, 0.05);
}

// Convergence with refinement: the coloured room's box and light at element sizes 0.4, 0.2 and
// 0.1 m. The pixels' radiance (band sum, interior pixels of the reference's object ids) changes
// less from each level to the next — the indirect light converges as its elements shrink. Measured:
// median 1.2 % then 0.38 % (about h^1.6), p95 6.3 % then 3.9 % (shadows' and contacts' edges).
TEST(Interreflection, ThePixelsConvergeAsTheElementsShrink) {
    Scene s = roomWithABox(Grid{400, 700, 50}, false);
    std::vector<SpectralCube> cubes;
    for (double size : {0.4, 0.2, 0.1}) {
        s.interreflection = Interreflection{size, 1e-7, 6000, Where{"room", "interreflection"}};
        const SceneOnGrid g = onGrid(s);
        SpectralPass pass(gpu(), s, g);
        cubes.push_back(pass.render());
    }
    const ReferenceImage ids = renderReference(s, onGrid(s));
    auto change = [&](const SpectralCube& a, const SpectralCube& b) {
        const std::vector<double> relative = interiorDifferences(a, b, ids.objectId);
        return std::pair{relative[relative.size() / 2], relative[relative.size() * 95 / 100]};
    };
    const auto [coarse, coarse95] = change(cubes[0], cubes[1]);
    const auto [fine, fine95] = change(cubes[1], cubes[2]);
    std::printf("element size 0.4 → 0.2: median %.4f, p95 %.4f; 0.2 → 0.1: median %.4f, p95 %.4f\n", coarse, coarse95,
                fine, fine95);
    EXPECT_LT(fine, 0.5 * coarse);
    EXPECT_LT(fine, 0.01);
    EXPECT_LT(fine95, coarse95);
}
