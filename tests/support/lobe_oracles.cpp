#include "support/lobe_oracles.h"

#include "core/quadrature.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

namespace metamer::testing {

namespace {

constexpr double kPi = std::numbers::pi;
using glm::dvec3;

dvec3 anyPerpendicular(const dvec3& a) {
    return glm::normalize(glm::cross(std::fabs(a.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0), a));
}

// The real roots in (−π, π] of a0 + a1 cos φ + b1 sin φ + a2 cos 2φ + b2 sin 2φ: with z = e^{iφ},
// z²·g is a polynomial of degree 4 in z whose roots on the unit circle are the real roots.
int trigonometricRoots(double a0, double a1, double b1, double a2, double b2, double* roots) {
    using C = std::complex<double>;
    const C coefficients[5] = {C(a2, b2) * 0.5, C(a1, b1) * 0.5, C(a0, 0.0), C(a1, -b1) * 0.5, C(a2, -b2) * 0.5};
    double scale = 0.0;
    for (const C& c : coefficients) scale = std::max(scale, std::abs(c));
    if (!(scale > 0.0)) return 0;
    int high = 4, low = 0;
    while (high > 0 && std::abs(coefficients[high]) < 1e-14 * scale) --high;
    while (low < high && std::abs(coefficients[low]) < 1e-14 * scale) ++low;  // roots at z = 0
    const int degree = high - low;
    if (degree <= 0) return 0;
    Eigen::MatrixXcd companion = Eigen::MatrixXcd::Zero(degree, degree);
    for (int i = 0; i < degree; ++i) companion(0, i) = -coefficients[high - 1 - i] / coefficients[high];
    for (int i = 1; i < degree; ++i) companion(i, i - 1) = 1.0;
    const Eigen::ComplexEigenSolver<Eigen::MatrixXcd> solver(companion, false);
    auto g = [&](double p) { return a0 + a1 * std::cos(p) + b1 * std::sin(p) + a2 * std::cos(2 * p) + b2 * std::sin(2 * p); };
    auto dg = [&](double p) {
        return -a1 * std::sin(p) + b1 * std::cos(p) - 2 * a2 * std::sin(2 * p) + 2 * b2 * std::cos(2 * p);
    };
    int count = 0;
    for (int i = 0; i < degree; ++i) {
        const C z = solver.eigenvalues()[i];
        if (std::fabs(std::abs(z) - 1.0) > 1e-3) continue;
        double p = std::arg(z);
        for (int iteration = 0; iteration < 4; ++iteration) {
            const double slope = dg(p);
            if (slope == 0.0) break;
            const double next = p - g(p) / slope;
            if (std::fabs(next - p) > 1e-3) break;
            p = next;
        }
        roots[count++] = p;
    }
    return count;
}

}  // namespace

double ringOracle(const dvec3& n, const dvec3& v, const dvec3& u, double gloss, bool hemisphere, double relTol) {
    if (gloss == 0.0) return hemisphere ? kPi * (1.0 + glm::dot(n, u)) / 2.0 : kPi;
    const double nv = std::clamp(glm::dot(n, v), -1.0, 1.0);
    dvec3 t = v - nv * n;
    double sv = glm::length(t);
    if (sv > 1e-14) {
        t /= sv;
    } else {
        t = anyPerpendicular(n);
        sv = 0.0;
    }
    const dvec3 b = glm::cross(n, t);
    const double un = glm::dot(u, n), ut = glm::dot(u, t), ub = glm::dot(u, b), uv = glm::dot(u, v);
    const double e = gloss + 1.0;
    // On the ring h = c·n + st·(cos φ·t + sin φ·b): v·h = A + B cos φ, n·ω = 2c(v·h) − n·v, and
    // u·ω = 2(v·h)(u·h) − u·v; the integrand 4(v·h)(n·ω) = 4(P0 + P1 cos φ + P2 cos² φ).
    auto ring = [&](double s) {
        if (!(s > 0.0)) return 0.0;
        const double logC = std::log(s) / e, c = std::exp(logC), st = std::sqrt(-std::expm1(logC) * (1.0 + c));
        const double A = nv * c, B = sv * st, C = un * c, D = ut * st, E = ub * st;
        const double need = std::max(0.0, nv / (2.0 * c));
        const double phiN = B > 0.0 ? std::acos(std::clamp((need - A) / B, -1.0, 1.0)) : (A > need ? kPi : 0.0);
        if (!(phiN > 0.0)) return 0.0;
        const double P0 = A * (2 * c * A - nv), P1 = B * (2 * c * A - nv) + 2 * c * A * B, P2 = 2 * c * B * B;
        auto antiderivative = [&](double p) {
            return 4.0 * (P0 * p + P1 * std::sin(p) + P2 * (0.5 * p + 0.25 * std::sin(2 * p)));
        };
        if (!hemisphere) return antiderivative(phiN) - antiderivative(-phiN);
        double roots[4];
        const int count = trigonometricRoots(2 * A * C + B * D - uv, 2 * (A * D + B * C), 2 * A * E, B * D, B * E, roots);
        std::vector<double> cuts{-phiN, phiN};
        for (int i = 0; i < count; ++i) {
            const double p = std::remainder(roots[i], 2 * kPi);
            if (p > -phiN && p < phiN) cuts.push_back(p);
        }
        std::sort(cuts.begin(), cuts.end());
        double sum = 0.0;
        for (size_t i = 0; i + 1 < cuts.size(); ++i) {
            const double mid = 0.5 * (cuts[i] + cuts[i + 1]);
            if (2 * (A + B * std::cos(mid)) * (C + D * std::cos(mid) + E * std::sin(mid)) - uv > 0.0)
                sum += antiderivative(cuts[i + 1]) - antiderivative(cuts[i]);
        }
        return sum;
    };
    auto sAt = [&](double c) { return c <= 0.0 ? 0.0 : std::exp(e * std::log(std::min(c, 1.0))); };
    // Rings tangent to the surface's horizon.
    const double thetaV = std::acos(std::clamp(nv, 0.0, 1.0));
    std::vector<double> breaks{0.0, 1.0, sAt(std::cos(0.5 * (0.5 * kPi + thetaV))), sAt(std::cos(0.5 * (0.5 * kPi - thetaV)))};
    if (hemisphere) {
        // Rings tangent to the hemisphere's horizon: the extrema of n·h along it (720 samples, each
        // extremum refined by golden-section search); rings through the horizons' two crossings.
        const dvec3 p = anyPerpendicular(u), q = glm::cross(u, p);
        auto nh = [&](double psi) {
            const dvec3 w = std::cos(psi) * p + std::sin(psi) * q;
            const double length2 = 2.0 + 2.0 * glm::dot(v, w);
            return length2 > 0.0 ? (glm::dot(n, w) + nv) / std::sqrt(length2) : -1.0;
        };
        constexpr int M = 720;
        std::vector<double> f(M);
        for (int i = 0; i < M; ++i) f[i] = nh(2 * kPi * i / M);
        for (int i = 0; i < M; ++i) {
            const double prev = f[(i + M - 1) % M], next = f[(i + 1) % M];
            const bool isMax = f[i] >= prev && f[i] > next, isMin = f[i] <= prev && f[i] < next;
            if (!isMax && !isMin) continue;
            const double sign = isMax ? 1.0 : -1.0, ratio = 0.5 * (std::sqrt(5.0) - 1.0);
            double lo = 2 * kPi * (i - 1) / M, hi = 2 * kPi * (i + 1) / M;
            double x1 = hi - ratio * (hi - lo), x2 = lo + ratio * (hi - lo), f1 = sign * nh(x1), f2 = sign * nh(x2);
            for (int it = 0; it < 60; ++it) {
                if (f1 > f2) {
                    hi = x2, x2 = x1, f2 = f1, x1 = hi - ratio * (hi - lo), f1 = sign * nh(x1);
                } else {
                    lo = x1, x1 = x2, f1 = f2, x2 = lo + ratio * (hi - lo), f2 = sign * nh(x2);
                }
            }
            breaks.push_back(sAt(nh(0.5 * (lo + hi))));
        }
        dvec3 axis = glm::cross(n, u);
        if (glm::length(axis) > 1e-12) {
            axis = glm::normalize(axis);
            for (const dvec3& w : {axis, -axis}) {
                const double length2 = 2.0 + 2.0 * glm::dot(v, w);
                if (length2 > 0.0) breaks.push_back(sAt((glm::dot(n, w) + nv) / std::sqrt(length2)));
            }
        }
    }
    // Rings beyond double's range carry nothing; a break there only costs pieces.
    breaks.erase(std::remove_if(breaks.begin(), breaks.end(), [](double x) { return x > 0.0 && x < 1e-300; }), breaks.end());
    std::sort(breaks.begin(), breaks.end());
    breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
    // (n·h)^N dh = ds·dφ/(N+1); the ring carries dω = 4(v·h)dh.
    return integrateAdaptively(ring, breaks, relTol, 100000) / e;
}

double luneOracle(const dvec3& n, const dvec3& v, const dvec3& u, double gloss, double relTol) {
    // ω = cos ξ·(cos χ·n + sin χ·b2) + sin ξ·a with a ⊥ n, u: n·ω > 0 is |χ| < π/2 and u·ω > 0 is
    // |χ − χu| < π/2, χu the angle of u from n about a; dω = cos ξ dξ dχ.
    dvec3 a = glm::cross(n, u);
    double chiU = 0.0;
    if (glm::length(a) < 1e-14) {
        if (glm::dot(n, u) < 0.0) return 0.0;
        a = anyPerpendicular(n);
    } else {
        a = glm::normalize(a);
    }
    dvec3 b2 = glm::cross(a, n);
    chiU = std::atan2(glm::dot(u, b2), glm::dot(u, n));
    if (chiU < 0.0) {
        a = -a;
        b2 = -b2;
        chiU = -chiU;
    }
    const double chiLo = chiU - 0.5 * kPi, chiHi = 0.5 * kPi;
    if (!(chiHi > chiLo)) return 0.0;
    const double nv = glm::dot(n, v);
    const dvec3 r = 2.0 * nv * n - v;
    const double chiR = std::atan2(glm::dot(r, b2), glm::dot(r, n)), xiR = std::asin(std::clamp(glm::dot(r, a), -1.0, 1.0));
    const double sigma = 1.0 / std::sqrt(gloss + 1.0), w0 = std::max(1e-6, 0.25 * sigma * std::max(nv, sigma));
    auto graded = [&](double lo, double hi, double centre) {
        std::vector<double> b{lo, hi};
        centre = std::clamp(centre, lo, hi);
        b.push_back(centre);
        for (double d = w0; d < hi - lo; d *= 2.0)
            for (double x : {centre - d, centre + d})
                if (x > lo && x < hi) b.push_back(x);
        std::sort(b.begin(), b.end());
        b.erase(std::unique(b.begin(), b.end()), b.end());
        return b;
    };
    const std::vector<double> xiBreaks = graded(-0.5 * kPi, 0.5 * kPi, xiR), chiBreaks = graded(chiLo, chiHi, chiR);
    auto lobe = [&](const dvec3& w) {
        const double nw = glm::dot(n, w);
        const dvec3 sum = w + v;
        const double length2 = glm::dot(sum, sum);
        if (!(nw > 0.0) || !(length2 > 0.0)) return 0.0;
        const double nh = glm::dot(n, sum) / std::sqrt(length2);
        return nh > 0.0 ? std::pow(nh, gloss) * nw : 0.0;
    };
    auto inner = [&](double chi) {
        const dvec3 toward = std::cos(chi) * n + std::sin(chi) * b2;
        return integrateAdaptively([&](double xi) { return lobe(std::cos(xi) * toward + std::sin(xi) * a) * std::cos(xi); },
                                   xiBreaks, 0.1 * relTol);
    };
    return integrateAdaptively(inner, chiBreaks, relTol);
}

}  // namespace metamer::testing
