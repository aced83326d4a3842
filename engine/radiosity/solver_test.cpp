// The radiosity solve against closed forms: furnaces (a closed box of uniform reflectance), a
// fluorescent furnace, the bound against a direct solve, and its iterations against Jacobi's.
#include "radiosity/solver.h"

#include "core/error.h"
#include "radiosity/form_factor.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <random>

using namespace metamer::radiosity;
using glm::dvec3;

namespace {

struct Elements {
    std::vector<std::array<dvec3, 3>> triangles;
    std::vector<int> face;  // which of the cube's faces
    std::vector<double> area;
};

// The unit cube's inside, each face cut into k × k squares of two triangles, facing inwards.
Elements closedCube(int k) {
    Elements e;
    // Each face: an origin and two edge vectors whose cross product points inwards.
    const std::array<std::array<dvec3, 3>, 6> faces{{
        {dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(0, 1, 0)},  // z = 0
        {dvec3(0, 0, 1), dvec3(0, 1, 0), dvec3(1, 0, 0)},  // z = 1
        {dvec3(0, 0, 0), dvec3(0, 0, 1), dvec3(1, 0, 0)},  // y = 0
        {dvec3(0, 1, 0), dvec3(1, 0, 0), dvec3(0, 0, 1)},  // y = 1
        {dvec3(0, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, 1)},  // x = 0
        {dvec3(1, 0, 0), dvec3(0, 0, 1), dvec3(0, 1, 0)},  // x = 1
    }};
    for (int f = 0; f < 6; ++f) {
        const dvec3 o = faces[size_t(f)][0], u = faces[size_t(f)][1] / double(k), v = faces[size_t(f)][2] / double(k);
        for (int a = 0; a < k; ++a)
            for (int b = 0; b < k; ++b) {
                const dvec3 p = o + double(a) * u + double(b) * v;
                for (const std::array<dvec3, 3>& t : {std::array<dvec3, 3>{p, p + u, p + u + v}, std::array<dvec3, 3>{p, p + u + v, p + v}}) {
                    e.triangles.push_back(t);
                    e.face.push_back(f);
                    e.area.push_back(polygonArea(t));
                }
            }
    }
    return e;
}

// The box's form factors, computed once per subdivision for all the tests here.
const Eigen::MatrixXd& formFactors(const Elements& e) {
    static std::map<size_t, Eigen::MatrixXd> made;
    Eigen::MatrixXd& F = made[e.triangles.size()];
    if (F.size() != 0) return F;
    const size_t n = e.triangles.size();
    F = Eigen::MatrixXd::Zero(Eigen::Index(n), Eigen::Index(n));
    for (size_t i = 0; i < n; ++i)
        for (size_t j = 0; j < n; ++j)
            if (i != j && e.face[i] != e.face[j])
                F(Eigen::Index(i), Eigen::Index(j)) =
                    triangleToPolygon(e.triangles[i][0], e.triangles[i][1], e.triangles[i][2], e.triangles[j], 1e-10);
    return F;
}

Problem uniformProblem(const Elements& e, const Eigen::MatrixXd& F, const std::vector<double>& rho) {
    Problem p;
    p.area = e.area;
    p.formFactors = F;
    p.surface.assign(e.area.size(), 0);
    p.surfaces = {SurfaceResponse{rho, {}}};
    p.emission = Eigen::MatrixXd::Zero(Eigen::Index(e.area.size()), Eigen::Index(rho.size()));
    return p;
}

}  // namespace

// A closed box of uniform reflectance ρ whose every wall sends E of its own: every point receives
// what every point sends, B = E + ρB, so B = E/(1 − ρ) in every band — at any element count.
TEST(RadiositySolve, UniformFurnaceGivesEOverOneMinusRho) {
    const std::vector<double> rho{0.2, 0.5, 0.9, 0.99};
    for (int k : {1, 2}) {
        SCOPED_TRACE(k);
        const Elements e = closedCube(k);
        const Eigen::MatrixXd F = formFactors(e);
        for (Eigen::Index i = 0; i < F.rows(); ++i) EXPECT_NEAR(F.row(i).sum(), 1.0, 1e-8) << "row " << i;
        Problem p = uniformProblem(e, F, rho);
        for (Eigen::Index b = 0; b < 4; ++b) p.emission.col(b).setConstant(1.0 + double(b));
        const Solution s = solve(p, 1e-9);
        for (Eigen::Index b = 0; b < 4; ++b) {
            const double exact = (1.0 + double(b)) / (1.0 - rho[size_t(b)]);
            for (Eigen::Index i = 0; i < F.rows(); ++i)
                EXPECT_NEAR(s.radiosity(i, b) / exact, 1.0, 1e-6) << "element " << i << ", band " << b;
        }
        EXPECT_LE(s.relativeBound, 1e-9);
    }
}

// Emission on one wall only: the area-weighted mean of B is mean(E)/(1 − ρ) (sum the equation with
// the areas: reciprocity turns Σ_i A_i F_ij into A_j, the closed box's rows sum to 1).
TEST(RadiositySolve, OneEmittingWallKeepsTheAreaWeightedMean) {
    const Elements e = closedCube(2);
    const Eigen::MatrixXd F = formFactors(e);
    const std::vector<double> rho{0.3, 0.78, 0.95};
    Problem p = uniformProblem(e, F, rho);
    double meanE = 0.0, total = 0.0;
    for (size_t i = 0; i < e.area.size(); ++i) {
        if (e.face[i] == 1) p.emission.row(Eigen::Index(i)).setConstant(2.0);
        meanE += e.area[i] * p.emission(Eigen::Index(i), 0);
        total += e.area[i];
    }
    meanE /= total;
    const Solution s = solve(p, 1e-9);
    for (Eigen::Index b = 0; b < 3; ++b) {
        double meanB = 0.0;
        for (size_t i = 0; i < e.area.size(); ++i) meanB += e.area[i] * s.radiosity(Eigen::Index(i), b);
        meanB /= total;
        EXPECT_NEAR(meanB / (meanE / (1.0 - rho[size_t(b)])), 1.0, 1e-6) << "band " << b;
    }
    // The emitting wall is brightest, the opposite one darker than the sides.
    EXPECT_GT(s.radiosity(e.face[0] == 1 ? 0 : 8, 0), s.radiosity(0, 0));
}

// A fluorescent furnace: in a closed uniform box every element receives B, so
// B = E + (diag ρ + M)·B and B = (I − diag ρ − M)⁻¹E as a vector over the bands.
TEST(RadiositySolve, FluorescentFurnaceSolvesTheBandCoupling) {
    const Elements e = closedCube(1);
    const Eigen::MatrixXd F = formFactors(e);
    const int bands = 6;
    std::vector<double> rho{0.1, 0.2, 0.6, 0.7, 0.8, 0.8};
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(bands, bands);
    // Absorbed in bands 0–2, re-emitted in bands 3–5 (longer wavelengths), and a little anti-Stokes.
    for (int x = 0; x < 3; ++x)
        for (int m = 3; m < bands; ++m) M(m, x) = 0.08 * (1.0 - rho[size_t(x)]) * (m - 2);
    M(2, 3) = 0.01;
    Problem p = uniformProblem(e, F, rho);
    p.surfaces[0].reemission = M;
    Eigen::VectorXd E(bands);
    E << 1.0, 2.0, 0.5, 0.0, 0.3, 0.0;
    for (Eigen::Index i = 0; i < F.rows(); ++i) p.emission.row(i) = E.transpose();
    const Eigen::MatrixXd system = Eigen::MatrixXd::Identity(bands, bands) -
                                   Eigen::MatrixXd(Eigen::Map<const Eigen::VectorXd>(rho.data(), bands).asDiagonal()) - M;
    const Eigen::VectorXd exact = system.fullPivLu().solve(E);
    const Solution s = solve(p, 1e-10);
    for (Eigen::Index i = 0; i < F.rows(); ++i)
        for (Eigen::Index b = 0; b < bands; ++b) EXPECT_NEAR(s.radiosity(i, b), exact[b], 1e-8 * exact.maxCoeff());
    EXPECT_GT(s.radiosity(0, 5), 0.1);  // light that was never emitted in band 5 arrives there
    EXPECT_GT(s.sweeps, 1);
}

// In an open scene of random elements the solution is within the reported bound of a direct solve
// of each band, and the bound within the tolerance; conjugate gradients need far fewer steps than
// Jacobi's ρ_max^k at ρ = 0.99.
TEST(RadiositySolve, TheBoundHoldsAgainstADirectSolveAndBrightScenesDoNotStall) {
    const Elements cube = closedCube(2);
    Eigen::MatrixXd F = formFactors(cube);
    // Open it: one face's elements leave, the rest keep their factors (rows now sum below 1).
    std::vector<Eigen::Index> keep;
    for (size_t i = 0; i < cube.area.size(); ++i)
        if (cube.face[i] != 1) keep.push_back(Eigen::Index(i));
    const Eigen::Index n = Eigen::Index(keep.size());
    Eigen::MatrixXd G(n, n);
    Elements open;
    for (Eigen::Index a = 0; a < n; ++a) {
        for (Eigen::Index b = 0; b < n; ++b) G(a, b) = F(keep[size_t(a)], keep[size_t(b)]);
        open.area.push_back(cube.area[size_t(keep[size_t(a)])]);
    }
    const std::vector<double> rho{0.5, 0.9, 0.99};
    Problem p;
    p.area = open.area;
    p.formFactors = G;
    p.surface.assign(size_t(n), 0);
    p.surfaces = {SurfaceResponse{rho, {}}};
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    p.emission = Eigen::MatrixXd(n, 3);
    for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index b = 0; b < 3; ++b) p.emission(i, b) = unit(random) < 0.3 ? unit(random) : 0.0;
    const double tolerance = 1e-6;
    const Solution s = solve(p, tolerance);
    double largest = 0.0;
    for (Eigen::Index b = 0; b < 3; ++b) {
        const Eigen::MatrixXd system = Eigen::MatrixXd::Identity(n, n) - rho[size_t(b)] * G;
        const Eigen::VectorXd exact = system.fullPivLu().solve(p.emission.col(b));
        const double error = (s.radiosity.col(b) - exact).cwiseAbs().maxCoeff();
        EXPECT_LE(error, s.bound) << "band " << b;
        largest = std::max(largest, exact.maxCoeff());
    }
    EXPECT_LE(s.bound, tolerance * largest * 1.01);
    // Jacobi's error after k steps falls as 0.99^k: 10⁻⁶ takes ln(10⁻⁶)/ln(0.99) ≈ 1375 steps.
    EXPECT_LT(s.iterations, 150) << s.describe();
}

// Sizes that disagree are refused by name.
TEST(RadiositySolve, ProblemsWhoseSizesDisagreeAreRefused) {
    Problem p;
    p.area = {1.0, 1.0};
    p.formFactors = Eigen::MatrixXd::Zero(2, 2);
    p.surface = {0, 0};
    p.surfaces = {SurfaceResponse{{0.5, 0.5}, {}}};
    p.emission = Eigen::MatrixXd::Zero(2, 3);
    EXPECT_THROW(solve(p, 1e-6), metamer::Error);
    p.emission = Eigen::MatrixXd::Zero(2, 2);
    p.surfaces[0].reflectance[1] = 1.5;
    EXPECT_THROW(solve(p, 1e-6), metamer::Error);
    p.surfaces[0].reflectance[1] = 0.5;
    EXPECT_NO_THROW(solve(p, 1e-6));
}

// A first guess: its own solution stops at once (no step, the same bound met); one 0.1 % off takes
// fewer steps than nothing to reach the same bound; a guess of the wrong size is refused.
TEST(RadiositySolve, AFirstGuessStartsTheIteration) {
    const Elements e = closedCube(2);
    const Eigen::MatrixXd F = formFactors(e);
    Problem p = uniformProblem(e, F, {0.3, 0.78, 0.95});
    for (size_t i = 0; i < e.area.size(); ++i)
        if (e.face[i] == 1) p.emission.row(Eigen::Index(i)).setConstant(2.0);
    const Solution cold = solve(p, 1e-9);
    const Solution again = solve(p, 1e-9, 2000, &cold.radiosity);
    EXPECT_EQ(again.iterations, 0);
    EXPECT_EQ(again.radiosity, cold.radiosity);
    const Eigen::MatrixXd near = 0.999 * cold.radiosity;
    const Solution warm = solve(p, 1e-9, 2000, &near);
    EXPECT_LT(warm.iterations, cold.iterations);
    EXPECT_LE(warm.relativeBound, 1e-9);
    EXPECT_LE((warm.radiosity - cold.radiosity).cwiseAbs().maxCoeff(), warm.bound + cold.bound);
    const Eigen::MatrixXd wrong = Eigen::MatrixXd::Zero(3, 3);
    EXPECT_THROW(solve(p, 1e-9, 2000, &wrong), metamer::Error);
}

// An emission scaled band by band (one light's spectrum changed) needs no solve: the last solution
// scaled so is within both bounds of a solve of the new problem, its own bound the old one's
// scaled. Anything else — the emission changed otherwise, or a reflectance — is not rescaled.
TEST(RadiositySolve, AnEmissionScaledBandByBandRescalesTheLastSolution) {
    const Elements e = closedCube(2);
    const Eigen::MatrixXd F = formFactors(e);
    Problem p = uniformProblem(e, F, {0.3, 0.78, 0.95});
    for (size_t i = 0; i < e.area.size(); ++i)
        if (e.face[i] == 1) p.emission.row(Eigen::Index(i)) << 2.0, 1.0, 0.5;
    const Solution before = solve(p, 1e-9);
    Problem q = p;
    q.emission = p.emission * Eigen::Vector3d(0.5, 3.0, 0.0).asDiagonal();
    const std::optional<Solution> rescaled = rescaledSolution(p, before, q);
    ASSERT_TRUE(rescaled.has_value());
    EXPECT_TRUE(rescaled->rescaled);
    EXPECT_EQ(rescaled->iterations, 0);
    const Solution fresh = solve(q, 1e-9);
    EXPECT_LE((rescaled->radiosity - fresh.radiosity).cwiseAbs().maxCoeff(), rescaled->bound + fresh.bound);
    EXPECT_LE((rescaled->irradiance - fresh.irradiance).cwiseAbs().maxCoeff(), 1e-9 * fresh.irradiance.maxCoeff());
    EXPECT_LE(rescaled->relativeBound, 1e-9);
    EXPECT_EQ(rescaled->radiosity.col(2).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_NE(rescaled->describe().find("scaled band by band"), std::string::npos) << rescaled->describe();
    Problem moved = q;  // one element's emission not in proportion
    moved.emission(0, 0) += 0.1;
    EXPECT_FALSE(rescaledSolution(p, before, moved).has_value());
    Problem repainted = q;
    repainted.surfaces[0].reflectance[1] = 0.7;
    EXPECT_FALSE(rescaledSolution(p, before, repainted).has_value());
    Problem lit = p;  // a band that was dark and is not
    lit.emission.col(2).setZero();
    const Solution dark = solve(lit, 1e-9);
    EXPECT_FALSE(rescaledSolution(lit, dark, p).has_value());
}
