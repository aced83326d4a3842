// core/quadrature.h by known answers.
#include "core/quadrature.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

using namespace metamer;

TEST(Quadrature, GaussLegendreIntegratesPolynomialsOfDegree2nMinus1Exactly) {
    for (int n : {1, 4, 8, 16}) {
        const GaussRule g = gaussLegendre(n);
        for (int degree = 0; degree <= 2 * n - 1; ++degree) {
            double sum = 0.0;
            for (int i = 0; i < n; ++i) sum += g.w[i] * std::pow(g.x[i], degree);
            const double exact = degree % 2 ? 0.0 : 2.0 / (degree + 1);
            EXPECT_NEAR(sum, exact, 1e-14) << n << " nodes, degree " << degree;
        }
        for (int i = 1; i < n; ++i) EXPECT_LT(g.x[i - 1], g.x[i]);
    }
}

TEST(Quadrature, AdaptiveMeetsItsToleranceOnAPeakAndASquareRoot) {
    // A narrow peak (σ = 10⁻³) is found when a break marks it; √x's end singularity by halving.
    const double sigma = 1e-3, centre = 0.3;
    auto peak = [&](double x) { return std::exp(-0.5 * std::pow((x - centre) / sigma, 2)); };
    const double breaks[] = {0.0, centre, 1.0};
    EXPECT_NEAR(integrateAdaptively(peak, breaks, 1e-12), sigma * std::sqrt(2.0 * std::numbers::pi), 1e-14);
    const double unit[] = {0.0, 1.0};
    EXPECT_NEAR(integrateAdaptively([](double x) { return std::sqrt(x); }, unit, 1e-12), 2.0 / 3.0, 1e-12);
}

TEST(Quadrature, CumulativeIntegralAtAnyUpperLimit) {
    // ∫₀ˣ cos t dt = sin x, between and at the breaks, before the first and after the last.
    const double breaks[] = {0.0, 1.0, 2.5, 4.0};
    const CumulativeIntegral c([](double t) { return std::cos(t); }, breaks, 1e-13);
    EXPECT_NEAR(c.total(), std::sin(4.0), 1e-13);
    for (double x = 0.0; x <= 4.0; x += 0.0625) EXPECT_NEAR(c(x), std::sin(x), 1e-12) << x;
    EXPECT_EQ(c(-1.0), 0.0);
    EXPECT_EQ(c(5.0), c.total());
}
