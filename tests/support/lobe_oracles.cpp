#include "support/lobe_oracles.h"

#include "core/quadrature.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

namespace metamer::test {

namespace {

constexpr double kPi = std::numbers::pi;
using glm::dvec3;

dvec3 anyPerpendicular(const dvec3& a) {
    return glm::normalize(glm::cross(std::fabs(a.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0), a));
}

// The real roots of the monic cubic m³ + a m² + b m + c: the largest one (there is at least one).
double largestCubicRoot(double a, double b, double c) {
    const double q = (a * a - 3.0 * b) / 9.0, r = (2.0 * a * a * a - 9.0 * a * b + 27.0 * c) / 54.0;
    double m;
    if (r * r < q * q * q) {  // three real roots
        const double theta = std::acos(std::clamp(r / std::sqrt(q * q * q), -1.0, 1.0));
        m = -2.0 * std::sqrt(q) * std::cos(theta / 3.0) - a / 3.0;  // the largest of the three
    } else {
        const double big = -std::copysign(std::cbrt(std::fabs(r) + std::sqrt(r * r - q * q * q)), r);
        m = big + (big != 0.0 ? q / big : 0.0) - a / 3.0;
    }
    for (int i = 0; i < 3; ++i) {  // Newton polish
        const double f = ((m + a) * m + b) * m + c, df = (3.0 * m + 2.0 * a) * m + b;
        if (df == 0.0) break;
        m -= f / df;
    }
    return m;
}

// The real roots of a t⁴ + b t³ + c t² + d t + e (a ≠ 0) by Ferrari's method, into roots; a
// discriminant within rounding of 0 counts as a double root (the caller polishes and tests signs).
int quarticRoots(double a, double b, double c, double d, double e, double* roots) {
    const double B = b / a, C = c / a, D = d / a, E = e / a;
    const double p = C - 3.0 * B * B / 8.0, q = D - B * C / 2.0 + B * B * B / 8.0,
                 r = E - B * D / 4.0 + B * B * C / 16.0 - 3.0 * B * B * B * B / 256.0;
    const double scale = 1.0 + std::fabs(p) + std::sqrt(std::fabs(r));
    int count = 0;
    auto quadratic = [&](double qb, double qc) {  // y² + qb y + qc
        const double disc = qb * qb - 4.0 * qc;
        if (disc < -1e-12 * scale * scale) return;
        const double root = std::sqrt(std::max(0.0, disc));
        roots[count++] = 0.5 * (-qb - root) - B / 4.0;
        roots[count++] = 0.5 * (-qb + root) - B / 4.0;
    };
    if (std::fabs(q) < 1e-14 * scale * scale * scale) {  // biquadratic: y² = z
        const double disc = p * p - 4.0 * r;
        if (disc < -1e-12 * scale * scale) return 0;
        for (double z : {0.5 * (-p - std::sqrt(std::max(0.0, disc))), 0.5 * (-p + std::sqrt(std::max(0.0, disc)))}) {
            if (z < -1e-12 * scale) continue;
            roots[count++] = std::sqrt(std::max(0.0, z)) - B / 4.0;
            roots[count++] = -std::sqrt(std::max(0.0, z)) - B / 4.0;
        }
        return count;
    }
    const double m = std::max(largestCubicRoot(p, p * p / 4.0 - r, -q * q / 8.0), 1e-300);
    const double s = std::sqrt(2.0 * m);
    quadratic(s, p / 2.0 + m - q / (2.0 * s));
    quadratic(-s, p / 2.0 + m + q / (2.0 * s));
    return count;
}

// The real roots of g(φ) = a0 + a1 cos φ + b1 sin φ + a2 cos 2φ + b2 sin 2φ (a trigonometric
// polynomial of degree 2: at most 4). With φ = s + θ and t = tan(θ/2), (1 + t²)²·g is a quartic
// in t whose leading coefficient is g(s + π); s is taken among 8 angles where |g(s + π)| is largest,
// so that no root sits at t = ∞. Each root is polished by Newton's method on g.
int trigonometricRoots(double a0, double a1, double b1, double a2, double b2, double* roots) {
    // g from cos φ and sin φ (the double angles by identity), g' beside it: one sincos per
    // Newton step, none for the 8 shifts; this runs for every ring.
    auto gOf = [&](double c, double s) { return a0 + a1 * c + b1 * s + a2 * (c * c - s * s) + b2 * 2.0 * s * c; };
    auto gAndSlope = [&](double p, double& slope) {
        const double c = std::cos(p), s = std::sin(p);
        slope = -a1 * s + b1 * c - 2 * a2 * (2.0 * s * c) + 2 * b2 * (c * c - s * s);
        return gOf(c, s);
    };
    // g(kπ/4 + π) for k = 0..7, from the exact cosines and sines of multiples of π/4.
    constexpr double h = 0.70710678118654752440;
    static constexpr double kCos[8] = {-1, -h, 0, h, 1, h, 0, -h}, kSin[8] = {0, -h, -1, -h, 0, h, 1, h};
    int best = 0;
    double largest = -1.0;
    for (int k = 0; k < 8; ++k) {
        const double value = std::fabs(gOf(kCos[k], kSin[k]));
        if (value > largest) largest = value, best = k;
    }
    if (!(largest > 0.0)) return 0;
    const double shift = best * kPi / 4.0, cs = -kCos[best], ss = -kSin[best], c2 = cs * cs - ss * ss, s2 = 2.0 * ss * cs;
    const double A1 = a1 * cs + b1 * ss, B1 = b1 * cs - a1 * ss, A2 = a2 * c2 + b2 * s2, B2 = b2 * c2 - a2 * s2;
    double t[4];
    const int n = quarticRoots(a0 - A1 + A2, 2 * B1 - 4 * B2, 2 * a0 - 6 * A2, 2 * B1 + 4 * B2, a0 + A1 + A2, t);
    for (int i = 0; i < n; ++i) {
        double p = shift + 2.0 * std::atan(t[i]);
        for (int iteration = 0; iteration < 3; ++iteration) {
            double slope;
            const double value = gAndSlope(p, slope);
            if (slope == 0.0) break;
            const double step = value / slope;
            if (!(std::fabs(step) < 1e-3)) break;
            p -= step;
        }
        roots[i] = p;
    }
    return n;
}

}  // namespace

LobeConfiguration LobeConfigurations::next(double gloss, double maxNv, bool nearBoundary) {
    auto direction = [&] { return glm::normalize(dvec3(gaussian_(rng_), gaussian_(rng_), gaussian_(rng_))); };
    LobeConfiguration c{direction(), {}, direction()};
    dvec3 p = direction();
    p = glm::normalize(p - glm::dot(p, c.n) * c.n);
    const double nv = maxNv * unit_(rng_);
    c.v = nv * c.n + std::sqrt(1.0 - nv * nv) * p;
    if (nearBoundary) {
        const dvec3 r = 2.0 * nv * c.n - c.v, w = glm::normalize(c.u - glm::dot(c.u, r) * r);
        const double e = (2.0 * unit_(rng_) - 1.0) * 4.0 / std::sqrt(gloss + 1.0);
        c.u = std::sin(e) * r + std::cos(e) * w;
    }
    return c;
}

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
            const double sine = std::sin(p);  // sin 2p = 2 sin p cos p: one sincos
            return 4.0 * (P0 * p + P1 * sine + P2 * (0.5 * p + 0.5 * sine * std::cos(p)));
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

}  // namespace metamer::test
