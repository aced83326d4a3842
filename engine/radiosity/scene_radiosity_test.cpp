// A scene's interreflection end to end (meshes → elements → form factors → direct light → solve →
// vertices), against the closed forms of a closed room.
#include "radiosity/scene_radiosity.h"

#include "radiosity/geometry_cache.h"
#include "support/scene_builders.h"

#include <gtest/gtest.h>

#include <numbers>

using namespace metamer;
using namespace metamer::radiosity;
using namespace metamer::test;

namespace {

constexpr double kPi = std::numbers::pi;

Scene roomScene(double rho, double irradiance) {
    Grid grid;
    grid.start_nm = 400;
    grid.end_nm = 700;
    grid.step_nm = 100;
    Scene scene = emptyScene(grid, perspectiveCamera(glm::dvec3(0.5, 0.5, 0.9), glm::dvec3(0.5), glm::dvec3(0, 1, 0), 60.0, 32, 32));
    scene.materials.push_back(lambertian(rho));
    scene.lights.push_back(ambientLight(constantSpectrum(irradiance)));
    scene.meshes = insideOfUnitCube(0);
    return scene;
}

}  // namespace

// A closed room of uniform reflectance ρ under an ambient light of irradiance E (which reaches
// every surface): every inside wall sends ρE directly and receives what every wall sends, so its
// radiosity is ρE/(1 − ρ) and so is the indirect irradiance at every inside vertex — corners and
// edges included; the walls' outsides see nothing of each other (0).
TEST(SceneRadiosity, AClosedRoomUnderAmbientLightIsAFurnace) {
    const double rho = 0.6, E = 2.0;
    const Scene scene = roomScene(rho, E);
    const SceneOnGrid g = onGrid(scene);
    EXPECT_NEAR(elementSize(scene), std::sqrt(3.0) / 24.0, 1e-12);  // the default: the room's diagonal / 24
    Scene lit = scene;
    lit.interreflection = Interreflection{0.3, 1e-8, 6000, Where{"room", "interreflection"}};
    const SceneInterreflection r = solveInterreflection(lit, g);
    std::printf("%s\n", r.describe().c_str());
    ASSERT_EQ(r.meshes.size(), 6u);
    const double exact = rho * E / (1.0 - rho);
    double worst = 0.0;
    for (const MeshInterreflection& m : r.meshes) {
        ASSERT_GT(m.front.rows(), 4);
        ASSERT_EQ(m.back.rows(), m.front.rows());  // quads are open: two sides
        for (Eigen::Index v = 0; v < m.front.rows(); ++v)
            for (Eigen::Index b = 0; b < m.front.cols(); ++b) {
                worst = std::max(worst, std::fabs(m.front(v, b) / exact - 1.0));
                EXPECT_EQ(m.back(v, b), 0.0);
            }
    }
    std::printf("worst relative deviation of the inside vertices' H: %.2e\n", worst);
    EXPECT_LT(worst, 1e-5);
}

// Emission on one wall only (a self-luminous floor, L_e from its inside): what every wall sends
// sums to what is emitted plus ρ × what arrives, and in a closed room what arrives is what is sent
// (rows of F sum to 1; A_i F_ij = A_j F_ji), so the area-weighted mean radiosity is mean(E)/(1 − ρ),
// E = πL_e on the floor's sixth of the area. The floor itself sends more than the mean; the ceiling less.
TEST(SceneRadiosity, OneEmittingWallMakesTheMeanRadiosityMeanEOverOneMinusRho) {
    const double rho = 0.7, Le = 2.0;
    Scene scene = roomScene(rho, 0.0);
    scene.lights.clear();
    scene.materials.push_back(emitting(lambertian(rho, "floor"), constantSpectrum(Le)));
    scene.meshes[2].material = 1;  // the floor (normal +y)
    scene.interreflection = Interreflection{0.25, 1e-10, 6000, Where{"room", "interreflection"}};
    const SceneOnGrid g = onGrid(scene);
    const SceneInterreflection r = solveInterreflection(scene, g);
    ASSERT_EQ(r.area.size(), size_t(r.solution.radiosity.rows()));
    double sent = 0.0, area = 0.0;
    for (size_t i = 0; i < r.area.size(); ++i) {
        sent += r.area[i] * r.solution.radiosity(Eigen::Index(i), 0);
        area += r.area[i];
    }
    const double expected = kPi * Le / 6.0 / (1.0 - rho);
    std::printf("mean radiosity %.10f, mean(E)/(1 - rho) %.10f: %.2e\n", sent / area, expected, sent / area / expected - 1.0);
    EXPECT_NEAR(area, 6.0, 1e-12);  // the walls' outsides take no part
    EXPECT_NEAR(sent / area / expected, 1.0, 1e-6);
}

// Too many elements are refused before the form factors, naming the key and the memory.
TEST(SceneRadiosity, TooManyElementsAreRefusedWithTheirMemory) {
    Scene scene = roomScene(0.5, 1.0);
    scene.interreflection = Interreflection{0.01, 1e-4, 2000, Where{"room", "interreflection"}};
    try {
        solveInterreflection(scene, onGrid(scene));
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(e.text().find("interreflection.max_elements"), std::string::npos) << e.text();
        EXPECT_NE(e.text().find("GiB"), std::string::npos) << e.text();
    }
}

// A sweep over spectra pays the solve, not the geometry: the same room with another light spectrum
// takes its form factors and gather factors from the geometry cache (geometry_cache.h) and, the
// one light's spectrum being what changed (every element's emission scaled band by band), is the
// last solve rescaled, without an iteration; another reflectance is solved again, from the last
// solve. Each gives what a solve from nothing gives, within the solves' bounds; the room with a wall
// moved computes its own form factors.
TEST(SceneRadiosity, ASpectrumChangeKeepsTheFormFactorsAndAGeometryChangeDoesNot) {
    Scene scene = roomScene(0.6, 2.0);
    scene.interreflection = Interreflection{0.3, 1e-8, 6000, Where{"room", "interreflection"}};
    clearGeometryCache();
    const SceneInterreflection first = solveInterreflection(scene, onGrid(scene));
    EXPECT_FALSE(first.formFactorsKept);
    EXPECT_FALSE(first.solution.rescaled);
    EXPECT_GT(first.formFactorSeconds, 0.0);
    // Solved from nothing, on form factors of its own; H = W·B, W's rows summing to ≤ 1.
    auto expectAsFresh = [&](const Scene& changed, const SceneInterreflection& swapped) {
        clearGeometryCache();
        const SceneInterreflection fresh = solveInterreflection(changed, onGrid(changed));
        EXPECT_FALSE(fresh.formFactorsKept);
        const double within = swapped.solution.bound + fresh.solution.bound;
        EXPECT_LE((swapped.solution.radiosity - fresh.solution.radiosity).cwiseAbs().maxCoeff(), within);
        for (size_t m = 0; m < changed.meshes.size(); ++m)
            EXPECT_LE((swapped.meshes[m].front - fresh.meshes[m].front).cwiseAbs().maxCoeff(), within);
        return fresh;
    };
    scene.lights[0].spectrum = sceneSpectrum(gaussianSpectrum(550, 60, 3.0, 300, 800, 1), SpectrumKind::Light);
    const SceneInterreflection swapped = solveInterreflection(scene, onGrid(scene));
    EXPECT_TRUE(swapped.formFactorsKept);
    EXPECT_EQ(swapped.formFactorSeconds, 0.0);
    EXPECT_NE(swapped.describe().find("form factors kept"), std::string::npos) << swapped.describe();
    EXPECT_TRUE(swapped.solution.rescaled);
    EXPECT_EQ(swapped.solution.iterations, 0);
    EXPECT_NE(swapped.describe().find("scaled band by band"), std::string::npos) << swapped.describe();
    EXPECT_LE(swapped.solution.relativeBound, 1e-8);
    expectAsFresh(scene, swapped);
    // A tighter tolerance than the last solve met is solved again (from it), not rescaled.
    solveInterreflection(scene, onGrid(scene));
    scene.interreflection->tolerance = 1e-12;
    const SceneInterreflection tighter = solveInterreflection(scene, onGrid(scene));
    EXPECT_FALSE(tighter.solution.rescaled);
    EXPECT_LE(tighter.solution.relativeBound, 1e-12);
    scene.interreflection->tolerance = 1e-8;
    // Another reflectance: not a scaling of the last problem, so solved, from the last solve.
    solveInterreflection(scene, onGrid(scene));  // the cache as a sweep leaves it
    scene.materials[0] = lambertian(0.5);
    const SceneInterreflection repainted = solveInterreflection(scene, onGrid(scene));
    EXPECT_TRUE(repainted.formFactorsKept);
    EXPECT_FALSE(repainted.solution.rescaled);
    EXPECT_TRUE(repainted.warmStart);
    EXPECT_GT(repainted.solution.iterations, 0);
    const SceneInterreflection fresh = expectAsFresh(scene, repainted);
    EXPECT_LE(repainted.solution.iterations, fresh.solution.iterations);
    scene.meshes[0].positions[0].y += 0.01;
    EXPECT_FALSE(solveInterreflection(scene, onGrid(scene)).formFactorsKept);
}
