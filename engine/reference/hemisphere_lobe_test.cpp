#include "reference/hemisphere_lobe.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

using namespace metamer;

namespace {

// v = n = u: I = 2π·∫₀^{π/2} cos(θ/2)^N·cos θ·sin θ dθ; with c = cos(θ/2), sin θ dθ = −4c dc and
// cos θ = 2c² − 1: I = 8π·[2c^(N+4)/(N+4) − c^(N+2)/(N+2)] from 1/√2 to 1.
double normalView(double N) {
    const double c = 1.0 / std::sqrt(2.0);
    return 8.0 * M_PI * (2.0 / (N + 4.0) * (1.0 - std::pow(c, N + 4.0)) - 1.0 / (N + 2.0) * (1.0 - std::pow(c, N + 2.0)));
}

// The integral by brute force: a midpoint rule over cos θ and φ about n, M × 4M cells.
double bruteForce(glm::dvec3 n, glm::dvec3 v, glm::dvec3 u, double N, int M) {
    const glm::dvec3 a = std::fabs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 t = glm::normalize(glm::cross(a, n)), b = glm::cross(n, t);
    double sum = 0.0;
    for (int i = 0; i < M; ++i) {
        const double ct = (i + 0.5) / M, st = std::sqrt(1.0 - ct * ct);
        for (int j = 0; j < 4 * M; ++j) {
            const double phi = 2.0 * M_PI * (j + 0.5) / (4 * M);
            const glm::dvec3 w = ct * n + st * (std::cos(phi) * t + std::sin(phi) * b);
            if (glm::dot(u, w) <= 0.0) continue;
            const double nh = glm::dot(n, glm::normalize(w + v));
            if (nh > 0.0) sum += std::pow(nh, N) * ct;
        }
    }
    return sum / M * (2.0 * M_PI / (4 * M));
}

struct Geometry {
    glm::dvec3 n, v, u;
};

// Random normals, hemispheres and views (a tenth of them grazing, n·v < 0.02).
std::vector<Geometry> randomGeometry(int count) {
    std::mt19937 rng(7);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    auto direction = [&] { return glm::normalize(glm::dvec3(g(rng), g(rng), g(rng))); };
    std::vector<Geometry> out;
    for (int k = 0; k < count; ++k) {
        Geometry x{direction(), {}, direction()};
        glm::dvec3 p = direction();
        p = glm::normalize(p - glm::dot(p, x.n) * x.n);
        const double nv = k % 10 == 0 ? 0.001 + 0.019 * unit(rng) : unit(rng);
        x.v = nv * x.n + std::sqrt(1.0 - nv * nv) * p;
        out.push_back(x);
    }
    return out;
}

}  // namespace

TEST(HemisphereLobe, GlossZeroIsTheHemispheresIrradianceFactor) {
    const glm::dvec3 n(0, 0, 1), v = glm::normalize(glm::dvec3(0.3, 0, 1));
    for (double c : {-1.0, -0.5, 0.0, 0.3, 1.0}) {
        const glm::dvec3 u(std::sqrt(1 - c * c), 0, c);
        EXPECT_DOUBLE_EQ(hemisphereLobe(n, v, u, 0.0), M_PI * (1 + c) / 2) << "n·u = " << c;
    }
}

TEST(HemisphereLobe, NormalViewUnderTheSkyMatchesTheClosedForm) {
    const glm::dvec3 z(0, 0, 1);
    for (double N : {0.5, 1.0, 10.0, 60.0, 200.0, 1000.0}) {
        const double exact = normalView(N), rule = hemisphereLobe(z, z, z, N);
        std::printf("N = %g: closed form %.10g, rule %.10g, relative error %.2e\n", N, exact, rule, rule / exact - 1);
        EXPECT_NEAR(rule / exact, 1.0, 5e-5) << "N = " << N;
    }
}

TEST(HemisphereLobe, AHemisphereOppositeTheNormalReflectsNothing) {
    const glm::dvec3 n(0, 0, 1), v = glm::normalize(glm::dvec3(0.5, 0.2, 1));
    EXPECT_NEAR(hemisphereLobe(n, v, -n, 60.0), 0.0, 1e-9 * hemisphereLobe(n, v, n, 60.0));
}

TEST(HemisphereLobe, AgreesWithBruteForce) {
    for (const Geometry& x : randomGeometry(4)) {
        for (double N : {1.0, 10.0}) {
            const double brute = bruteForce(x.n, x.v, x.u, N, 500), full = hemisphereLobe(x.n, x.v, x.n, N, 8, 128);
            EXPECT_NEAR(hemisphereLobe(x.n, x.v, x.u, N), brute, 2e-3 * full) << "N = " << N;
        }
    }
}

// The rule's error over many geometries, against the same rule refined until it no longer changes
// (8 radial panels, 128 ring samples), relative to the lobe's unoccluded integral. Prints the
// figures docs/physics.md quotes.
TEST(HemisphereLobe, RuleErrorIsSmallAgainstTheRefinedRule) {
    const std::vector<Geometry> geometry = randomGeometry(200);
    for (double N : {1.0, 10.0, 60.0, 200.0, 1000.0, 10000.0}) {
        std::vector<double> errors;
        for (const Geometry& x : geometry) {
            const double full = hemisphereLobe(x.n, x.v, x.n, N, 8, 128);
            errors.push_back(std::fabs(hemisphereLobe(x.n, x.v, x.u, N) - hemisphereLobe(x.n, x.v, x.u, N, 8, 128)) / full);
            // Sky and ground together are the whole lobe (to the refined rule's own error).
            EXPECT_NEAR(hemisphereLobe(x.n, x.v, x.u, N, 8, 128) + hemisphereLobe(x.n, x.v, -x.u, N, 8, 128), full,
                        1e-5 * full);
        }
        std::sort(errors.begin(), errors.end());
        std::printf("N = %g: error / unoccluded lobe: median %.2e, 90th percentile %.2e, max %.2e\n", N,
                    errors[errors.size() / 2], errors[errors.size() * 9 / 10], errors.back());
        EXPECT_LT(errors[errors.size() / 2], 5e-5) << "N = " << N;
        EXPECT_LT(errors.back(), N < 10 ? 5e-3 : 1e-3) << "N = " << N;
    }
}

TEST(HemisphereLobe, TheUnoccludedLobeAndTheGroundAfterItsSky) {
    // The whole lobe: at v = n the closed form; elsewhere the refined rule with u = n (the same
    // domain). A ground after its sky: the rest of the whole lobe, as accurate as the sky's.
    const glm::dvec3 z(0, 0, 1);
    for (double N : {1.0, 60.0, 200.0}) EXPECT_NEAR(unoccludedLobe(z, z, N) / normalView(N), 1.0, 5e-5) << "N = " << N;
    EXPECT_DOUBLE_EQ(unoccludedLobe(z, glm::normalize(glm::dvec3(1, 0, 1)), 0.0), M_PI);
    double worstWhole = 0.0, worstGround = 0.0;
    for (const Geometry& x : randomGeometry(100))
        for (double N : {10.0, 200.0}) {
            const double full = hemisphereLobe(x.n, x.v, x.n, N, 8, 128);
            worstWhole = std::max(worstWhole, std::fabs(unoccludedLobe(x.n, x.v, N) - full) / full);
            const double ground = oppositeHemisphereLobe(x.n, x.v, N, hemisphereLobe(x.n, x.v, x.u, N));
            worstGround = std::max(worstGround, std::fabs(ground - hemisphereLobe(x.n, x.v, -x.u, N, 8, 128)) / full);
        }
    std::printf("unoccluded lobe: max error %.2e; a ground after its sky: max error %.2e (of the unoccluded lobe)\n",
                worstWhole, worstGround);
    EXPECT_LT(worstWhole, 1e-3);
    EXPECT_LT(worstGround, 1e-3);
}
