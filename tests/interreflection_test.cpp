// Interreflection through the GPU spectral pass (docs/physics.md, "Interreflection"): known
// answers a renderer of light that bounces must give, without the CPU reference.
#include "render/spectral_pass.h"
#include "support/gpu.h"
#include "support/scene_builders.h"

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
    for (const glm::dvec3 n : {glm::dvec3(1, 0, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0),
                               glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1)})
        s.meshes.push_back(quad(glm::dvec3(0.5) - 0.5 * n, n, 1.0, 1.0, 0));
    s.interreflection = Interreflection{elementSize, 1e-8, 6000, Where{"room", "interreflection"}};
    return s;
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
