#include "reference/hemisphere_lobe.h"

#include "hemisphere_quadrature.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace metamer {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kGaussX[HEMISPHERE_GAUSS_HALF] = {HEMISPHERE_GAUSS_X};
constexpr double kGaussW[HEMISPHERE_GAUSS_HALF] = {HEMISPHERE_GAUSS_W};

// 1 − eˣ for x ≤ 0, keeping its relative precision as x → 0 (c = eˣ is then the cosine of a
// small angle, and 1 − c its square's half).
double oneMinusExp(double x) { return -std::expm1(x); }

}  // namespace

namespace {

// The rule; `cut` false: no hemisphere cut (u unused), the lobe over the whole upper hemisphere.
double lobeIntegral(const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& u, bool cut, double gloss,
                    int radialPanels, int ringSamples) {
    if (gloss == 0.0) return cut ? kPi * (1.0 + glm::dot(n, u)) / 2.0 : kPi;
    // The frame of n with t along v's tangential part: v = nv·n + sv·t.
    const double nv = std::clamp(glm::dot(n, v), -1.0, 1.0);
    glm::dvec3 t = v - nv * n;
    const double sv = glm::length(t);
    if (sv > 1e-12) {
        t /= sv;
    } else {
        const glm::dvec3 a = std::fabs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        t = glm::normalize(glm::cross(a, n));
    }
    const glm::dvec3 b = glm::cross(n, t);
    const double un = glm::dot(u, n), ut = glm::dot(u, t), ub = glm::dot(u, b), uv = glm::dot(u, v);
    const double e = gloss + 1.0;

    // The radial pieces: rings at θh = (π/2 ∓ θv)/2 touch the surface's horizon (ω·n = 0) at
    // φ = π and φ = 0; between them rings are cut by it, outside they are whole or gone. In s the
    // pieces are [0, s2], [s2, s1], [s1, 1]; each is mapped by a smoothstep so that the square-root
    // behaviour of the ring integral at its ends does not slow Gauss–Legendre down.
    const double thetaV = std::acos(std::clamp(nv, 0.0, 1.0));
    auto sAt = [e](double c) { return c <= 0.0 ? 0.0 : std::exp(e * std::log(std::min(c, 1.0))); };
    double cuts[HEMISPHERE_MAX_CUTS];
    int cutCount = 0;
    cuts[cutCount++] = 0.0;
    cuts[cutCount++] = 1.0;
    cuts[cutCount++] = sAt(std::cos(0.5 * (0.5 * kPi + thetaV)));
    cuts[cutCount++] = sAt(std::cos(0.5 * (0.5 * kPi - thetaV)));
    // Rings touch the hemisphere's horizon (u·ω = 0) where n·h is extremal along it: the great
    // circle ω(ψ) = cos ψ·p + sin ψ·q (p, q ⊥ u) maps to half vectors with
    // n·h(ψ) = (n·ω + n·v)/|ω + v|. Its extrema, found by sampling and golden-section search, are
    // the remaining cuts.
    if (cut) {
        const glm::dvec3 a = std::fabs(u.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        const glm::dvec3 p = glm::normalize(glm::cross(a, u)), q = glm::cross(u, p);
        auto nh = [&](double psi) {
            const glm::dvec3 w = std::cos(psi) * p + std::sin(psi) * q;
            const double len2 = 2.0 + 2.0 * glm::dot(v, w);
            return len2 > 0.0 ? (glm::dot(n, w) + nv) / std::sqrt(len2) : 0.0;
        };
        const double step = 2.0 * kPi / HEMISPHERE_HORIZON_SAMPLES;
        double f[HEMISPHERE_HORIZON_SAMPLES];
        for (int i = 0; i < HEMISPHERE_HORIZON_SAMPLES; ++i) f[i] = nh(i * step);
        for (int i = 0; i < HEMISPHERE_HORIZON_SAMPLES && cutCount < HEMISPHERE_MAX_CUTS; ++i) {
            const double prev = f[(i + HEMISPHERE_HORIZON_SAMPLES - 1) % HEMISPHERE_HORIZON_SAMPLES],
                         next = f[(i + 1) % HEMISPHERE_HORIZON_SAMPLES];
            const bool isMax = f[i] >= prev && f[i] > next, isMin = f[i] <= prev && f[i] < next;
            if (!isMax && !isMin) continue;
            // Golden-section search on [ψ − step, ψ + step] (for a minimum, of −n·h).
            const double sign = isMax ? 1.0 : -1.0, g = 0.5 * (std::sqrt(5.0) - 1.0);
            double lo = (i - 1) * step, hi = (i + 1) * step;
            double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = sign * nh(x1), f2 = sign * nh(x2);
            for (int it = 0; it < HEMISPHERE_GOLDEN_STEPS; ++it) {
                if (f1 > f2) {
                    hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = sign * nh(x1);
                } else {
                    lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = sign * nh(x2);
                }
            }
            cuts[cutCount++] = sAt(nh(0.5 * (lo + hi)));
        }
    }
    std::sort(cuts, cuts + cutCount);

    double total = 0.0;
    for (int piece = 0; piece + 1 < cutCount; ++piece) {
        const double sLo = cuts[piece], sHi = cuts[piece + 1];
        if (!(sHi > sLo)) continue;
    for (int panel = 0; panel < radialPanels; ++panel)
        for (int i = 0; i < 2 * HEMISPHERE_GAUSS_HALF; ++i) {
            const double x = (i % 2 ? 1.0 : -1.0) * kGaussX[i / 2];
            const double tt = (panel + 0.5 + 0.5 * x) / radialPanels;
            const double s = sLo + (sHi - sLo) * tt * tt * (3.0 - 2.0 * tt);
            const double ws = (sHi - sLo) * 6.0 * tt * (1.0 - tt) * 0.5 * kGaussW[i / 2] / radialPanels;
            if (!(s > 0.0)) continue;
            // The ring of half vectors at n·h = c, c = s^(1/(N+1)): s is uniform in the lobe's weight.
            const double logC = std::log(s) / e, c = std::exp(logC);
            const double oneMinusC = oneMinusExp(logC), st = std::sqrt(oneMinusC * (1.0 + c));
            // On the ring h(φ) = c·n + st·(cos φ·t + sin φ·b): v·h = A + B·cos φ, and
            // ω = 2(v·h)h − v has n·ω = 2c(v·h) − nv and u·ω = 2(v·h)(u·h) − u·v.
            const double A = nv * c, B = sv * st;
            const double C = un * c, D = ut * st, E = ub * st;
            // n·ω > 0 and v·h > 0: cos φ > k, an arc |φ| < φn around φ = 0.
            const double need = std::max(0.0, nv / (2.0 * c));
            double phiN;
            if (B <= 0.0)
                phiN = A > need ? kPi : 0.0;
            else
                phiN = std::acos(std::clamp((need - A) / B, -1.0, 1.0));
            if (!(phiN > 0.0)) continue;
            // 4(v·h)(n·ω) = 4(P0 + P1 cos φ + P2 cos² φ), integrated in closed form.
            const double P0 = A * (2.0 * c * A - nv), P1 = B * (2.0 * c * A - nv) + 2.0 * c * A * B, P2 = 2.0 * c * B * B;
            auto antiderivative = [&](double p) {
                return 4.0 * (P0 * p + P1 * std::sin(p) + P2 * (0.5 * p + 0.25 * std::sin(2.0 * p)));
            };
            auto g = [&](double p) {
                const double cp = std::cos(p), sp = std::sin(p);
                return 2.0 * (A + B * cp) * (C + D * cp + E * sp) - uv;
            };
            auto add = [&](double lo, double hi) {  // ∫ over [lo, hi] ∩ [−φn, φn]
                lo = std::max(lo, -phiN);
                hi = std::min(hi, phiN);
                return hi > lo ? antiderivative(hi) - antiderivative(lo) : 0.0;
            };
            // u·ω > 0: where g > 0, found by sampling the ring and refining each change of sign
            // (g is a trigonometric polynomial of degree 2: at most 4 roots).
            double ring = 0.0;
            if (!cut) {
                total += ws * add(-kPi, kPi);
                continue;
            }
            const double step = 2.0 * kPi / ringSamples;
            double p0 = -kPi, g0 = g(p0);
            for (int k = 1; k <= ringSamples; ++k) {
                const double p1 = -kPi + k * step, g1 = g(p1);
                if (g0 > 0.0 && g1 > 0.0) {
                    ring += add(p0, p1);
                } else if ((g0 > 0.0) != (g1 > 0.0)) {
                    // The Illinois variant of false position: superlinear, and never leaves [p0, p1].
                    double a = p0, fa = g0, b = p1, fb = g1;
                    for (int it = 0; it < HEMISPHERE_ROOT_STEPS && fb != fa; ++it) {
                        const double x = b - fb * (b - a) / (fb - fa), fx = g(x);
                        if ((fx > 0.0) != (fb > 0.0)) {
                            a = b;
                            fa = fb;
                        } else {
                            fa *= 0.5;
                        }
                        b = x;
                        fb = fx;
                    }
                    const double root = b;
                    ring += g0 > 0.0 ? add(p0, root) : add(root, p1);
                }
                p0 = p1;
                g0 = g1;
            }
            total += ws * ring;
        }
    }
    // dω = 4(v·h)·dh and (n·h)^N·dh = ds·dφ/(N+1); the ring integral above carries the 4(v·h).
    return total / e;
}

}  // namespace

double hemisphereLobe(const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& u, double gloss, int radialPanels,
                      int ringSamples) {
    return lobeIntegral(n, v, u, true, gloss, radialPanels, ringSamples);
}

double unoccludedLobe(const glm::dvec3& n, const glm::dvec3& v, double gloss, int radialPanels) {
    return lobeIntegral(n, v, n, false, gloss, radialPanels, HEMISPHERE_RING_SAMPLES);
}

double oppositeHemisphereLobe(const glm::dvec3& n, const glm::dvec3& v, double gloss, double lobeOfOpposite) {
    return std::max(0.0, unoccludedLobe(n, v, gloss) - lobeOfOpposite);
}

std::vector<bool> pairedWithPreviousHemisphere(const std::vector<Light>& lights) {
    std::vector<bool> paired(lights.size(), false);
    const Light* previous = nullptr;
    for (size_t l = 0; l < lights.size(); ++l) {
        if (lights[l].type != Light::Type::Hemisphere) continue;
        paired[l] = previous && lights[l].up == -previous->up;
        previous = &lights[l];
    }
    return paired;
}

}  // namespace metamer
