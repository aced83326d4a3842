// Two independent quadratures of a hemisphere light's lobe integral, the oracles the lobe table is
// certified against (reference/lobe_table_test.cpp, tests/lobe_certification_test.cpp):
//
//     I(n, v, u, N) = ∫ (n·h)^N (n·ω) dω  over n·ω > 0 and u·ω > 0,   h = normalize(ω + v)
//
// - ringOracle: over half vectors, on rings n·h = c with s = c^(N+1) as the radial variable (the
//   lobe's weight is uniform in s, so the lobe has no peak to miss). On each ring the arc n·ω > 0 is
//   closed form, u·ω > 0 is bounded by the real roots of a trigonometric polynomial of degree 2
//   (a quartic in tan(φ/2), Ferrari's method, polished by Newton's method), and the integrand
//   4(v·h)(n·ω) has a closed-form antiderivative: each ring is exact. Along s, adaptive
//   Gauss–Kronrod, with breaks at every ring where the arcs change (rings tangent to either
//   horizon, rings through the horizons' crossings).
// - luneOracle: over directions, on the lune n·ω > 0, u·ω > 0 mapped to a rectangle (ω turned about
//   the axis n × u, then tilted towards it), nested adaptive Gauss–Kronrod with breaks graded about
//   the mirror direction. A different variable, a different domain and a different integrand form.
//
// They agree with each other to about 10⁻¹¹ of the unoccluded lobe (lobe_table_test.cpp checks it).
// Compiled with optimization (tests/CMakeLists.txt) although the tests are not.
#pragma once

#include <glm/glm.hpp>

#include <random>

namespace metamer::test {

// A configuration (n, v, u) for the lobe's tests: n and u uniform on the sphere, v with n·v
// uniform in [0, maxNv); `nearBoundary`: u turned so that its hemisphere's boundary passes within
// four lobe widths (4/√(N + 1)) of the mirror direction, where the lobe is cut.
struct LobeConfiguration {
    glm::dvec3 n, v, u;
};
class LobeConfigurations {
public:
    explicit LobeConfigurations(unsigned seed) : rng_(seed) {}
    LobeConfiguration next(double gloss, double maxNv, bool nearBoundary);

private:
    std::mt19937 rng_;
    std::normal_distribution<double> gaussian_;
    std::uniform_real_distribution<double> unit_{0.0, 1.0};
};

// `hemisphere` false: the unoccluded lobe (u unused).
double ringOracle(const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& u, double gloss, bool hemisphere = true,
                  double relTol = 1e-11);
double luneOracle(const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& u, double gloss, double relTol = 1e-10);

}  // namespace metamer::test
