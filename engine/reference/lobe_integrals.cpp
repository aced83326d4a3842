#include "reference/lobe_integrals.h"

#include "core/quadrature.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace metamer {

namespace {

constexpr double kPi = std::numbers::pi;
using glm::dvec3;

// The view's frame (see the header).
struct ViewFrame {
    double nv, cv;       // sin θe, cos θe
    dvec3 n, v, r, e1, e2;
    explicit ViewFrame(double thetaE)
        : nv(std::sin(thetaE)), cv(std::cos(thetaE)), n(0, 0, 1), v(cv, 0, nv), r(-cv, 0, nv), e1(nv, 0, cv),
          e2(0, 1, 0) {}
};

// The integrand: (n·h)^N (n·ω) above the surface, 0 elsewhere (n = z). 1 − n·h = |n − h|²/2 keeps
// its relative precision where h → n, which pow(n·h, N) would lose at large N.
double lobe(const dvec3& v, const dvec3& w, double gloss) {
    const double nw = w.z;
    if (!(nw > 0.0)) return 0.0;
    const dvec3 sum = w + v;
    const double length2 = glm::dot(sum, sum);
    if (!(length2 > 0.0)) return 0.0;
    const dvec3 h = sum / std::sqrt(length2);
    if (!(h.z > 0.0)) return 0.0;
    const double oneMinus = 0.5 * (h.x * h.x + h.y * h.y + (1.0 - h.z) * (1.0 - h.z));
    // (1 − δ)^N ≤ e^(−Nδ): below e^−80 the value is nothing to any integral here (and costs a log
    // and an exp, most of the build's time, in the far tails).
    if (gloss * oneMinus > 80.0) return 0.0;
    return std::exp(gloss * std::log1p(-oneMinus)) * nw;
}

// Breaks at ±w/2, ±w, ±2w, … (ratio) about 0, clipped to [lo, hi], with lo, 0 and hi.
std::vector<double> gradedBreaks(double lo, double hi, double w, double ratio) {
    std::vector<double> b{lo, hi};
    if (0.0 > lo && 0.0 < hi) b.push_back(0.0);
    for (double d = 0.5 * w; d < std::max(-lo, hi); d *= ratio) {
        if (-d > lo) b.push_back(-d);
        if (d < hi) b.push_back(d);
    }
    return b;
}

// Adds centre and centre ± w0·2^k up to w1, inside (lo, hi).
void addGraded(std::vector<double>& b, double centre, double w0, double w1, double lo, double hi) {
    if (centre > lo && centre < hi) b.push_back(centre);
    for (double d = w0; d < w1; d *= 2.0)
        for (double x : {centre - d, centre + d})
            if (x > lo && x < hi) b.push_back(x);
}

void sortUnique(std::vector<double>& b) {
    std::sort(b.begin(), b.end());
    b.erase(std::unique(b.begin(), b.end()), b.end());
}

}  // namespace

LobeMoments lobeMoments(double thetaE, double gloss, double tail) {
    const ViewFrame f(thetaE);
    const double e = gloss + 1.0;
    static const GaussRule along = gaussLegendre(24);
    // One ring of half vectors h = c·n + st·(cos φ·x + sin φ·y): v·h = A + B cos φ, and n·ω > 0 on
    // the arc |φ| < φn. Its integrals of 4(v·h)(n·ω)·{1, ω·r, ω·e1, (ω·r)², (ω·e1)², (ω·r)(ω·e1),
    // (ω·e2)²}, all even in φ, over [0, φn] doubled.
    auto ring = [&](double s) {
        std::array<double, 7> m{};
        if (!(s > 0.0)) return m;
        const double logC = std::log(s) / e, c = std::exp(logC), st = std::sqrt(-std::expm1(logC) * (1.0 + c));
        const double a = f.nv * c, b = f.cv * st, need = f.nv / (2.0 * c);
        const double phiN = b > 0.0 ? std::acos(std::clamp((need - a) / b, -1.0, 1.0)) : (a > need ? kPi : 0.0);
        if (!(phiN > 0.0)) return m;
        for (size_t i = 0; i < along.x.size(); ++i) {
            const double phi = 0.5 * phiN * (along.x[i] + 1.0), weight = along.w[i] * phiN;  // ×2 for the mirror half
            const dvec3 h(st * std::cos(phi), st * std::sin(phi), c);
            const double vh = glm::dot(f.v, h);
            const dvec3 w = 2.0 * vh * h - f.v;
            const double g = weight * 4.0 * vh * std::max(w.z, 0.0);
            const double wr = glm::dot(w, f.r), w1 = glm::dot(w, f.e1), w2 = w.y;
            m[0] += g;
            m[1] += g * wr;
            m[2] += g * w1;
            m[3] += g * wr * wr;
            m[4] += g * w1 * w1;
            m[5] += g * wr * w1;
            m[6] += g * w2 * w2;
        }
        return m;
    };
    // Pieces in s: rings that touch the surface's horizon at φ = π and φ = 0 (θh = (π/2 ± θv)/2).
    const double thetaV = 0.5 * kPi - thetaE;
    auto sAt = [&](double c) { return c <= 0.0 ? 0.0 : std::exp(e * std::log(std::min(c, 1.0))); };
    std::vector<double> breaks{0.0, 1.0, sAt(std::cos(0.5 * (0.5 * kPi + thetaV))), sAt(std::cos(0.5 * (0.5 * kPi - thetaV)))};
    sortUnique(breaks);
    const CumulativeIntegral mass([&](double s) { return ring(s)[0]; }, breaks, 1e-12);
    // The other moments on the pieces the mass converged on (the same features), one G7K15 each.
    std::array<double, 7> sum{};
    for (size_t p = 0; p < mass.starts().size(); ++p) {
        const double mid = 0.5 * (mass.starts()[p] + mass.ends()[p]), half = 0.5 * (mass.ends()[p] - mass.starts()[p]);
        for (int i = 0; i < 15; ++i) {
            const auto m = ring(mid + half * quadrature_detail::kKronrodX[i]);
            for (int k = 0; k < 7; ++k) sum[k] += half * quadrature_detail::kKronrodW[i] * m[k];
        }
    }
    LobeMoments out;
    out.unoccluded = mass.total() / e;  // (n·h)^N dh = ds·dφ/(N+1); the ring carries dω = 4(v·h)dh
    const double total = sum[0];
    out.gamma = std::atan2(sum[2], sum[1]);
    const double cg = std::cos(out.gamma), sg = std::sin(out.gamma);
    // e1c = cos γ·e1 − sin γ·r: ⟨(ω·e1c)²⟩ from the moments in (r, e1).
    out.sigma1 = std::sqrt(std::max(0.0, (cg * cg * sum[4] - 2.0 * sg * cg * sum[5] + sg * sg * sum[3]) / total));
    out.sigma2 = std::sqrt(std::max(0.0, sum[6] / total));
    // The cone: the ring s0 below which (θh > θ0) the lobe holds `tail` of its mass, by bisection
    // on the cumulative mass (monotone in s).
    double lo = 0.0, hi = 1.0;
    const double target = tail * mass.total();
    for (int i = 0; i < 200 && hi - lo > 1e-300; ++i) {
        const double mid = 0.5 * (lo + hi);
        (mass(mid) > target ? hi : lo) = mid;
    }
    const double c0 = hi > 0.0 ? std::exp(std::log(hi) / e) : 0.0;
    out.coneHalfAngle = 2.0 * std::acos(std::clamp(c0, 0.0, 1.0));
    return out;
}

HemisphereFractions hemisphereFractions(double thetaE, double gloss, double gamma, double sigma1, double sigma2,
                                        double beta, const std::vector<double>& epsilons, double relTol) {
    const ViewFrame f(thetaE);
    const double cb = std::cos(beta), sb = std::sin(beta);
    // The lobe's spread along m (ψ), and the centre line and spread of ζ given ψ, for a Gaussian
    // of spreads σ1 (along e1c) and σ2 (along e2): the pieces' first layout.
    const double alongM = std::sqrt(sigma1 * sigma1 * cb * cb + sigma2 * sigma2 * sb * sb);
    const double slope = (sigma2 * sigma2 - sigma1 * sigma1) * sb * cb / (alongM * alongM);
    const double across = sigma1 * sigma2 / alongM;
    const dvec3 c = std::cos(gamma) * f.r + std::sin(gamma) * f.e1, e1c = std::cos(gamma) * f.e1 - std::sin(gamma) * f.r;
    const dvec3 m = cb * e1c + sb * f.e2, axis = glm::cross(c, m);
    // Beyond 2θ from r the lobe is below cos(θ)^N < e^−60 of its peak (the reflection bound of
    // shaders/lobe_lookup.h), so a lobe smaller than a hemisphere is integrated over a square about c.
    double reach = 2.0 * std::acos(std::exp(-60.0 / gloss)) + std::fabs(gamma);
    double psiLo = -0.5 * kPi, psiHi = 1.5 * kPi, zetaMax = 0.5 * kPi;
    if (reach < 0.5 * kPi) psiLo = -reach, psiHi = reach, zetaMax = reach;
    const double ratio = 2.0;  // of the first pieces' widths, in ψ and in ζ
    std::vector<double> breaks = gradedBreaks(psiLo, psiHi, alongM, ratio);
    const double nc = c.z, nm = m.z, naxis = axis.z;
    // Where the surface's horizon runs along ζ, the profile has a kink.
    const double psiHorizon = std::atan2(-nc, nm);
    for (double p : {psiHorizon, psiHorizon + kPi, psiHorizon - kPi, psiHorizon + 2.0 * kPi})
        addGraded(breaks, p, 0.5 * alongM, 8.0 * alongM, psiLo, psiHi);
    // The point −v, where a grazing lobe ends in a wedge (only near the lobe: −v is 2θe from r).
    const double psiV = std::atan2(-glm::dot(f.v, m), -glm::dot(f.v, c));
    const double zetaV = std::asin(std::clamp(-glm::dot(f.v, axis), -1.0, 1.0));
    const bool wedge = 2.0 * thetaE < std::fabs(gamma) + 8.0 * sigma1;
    if (wedge)
        for (double p : {psiV, psiV + 2.0 * kPi, psiV - 2.0 * kPi}) addGraded(breaks, p, 1e-4 * alongM, 4.0 * alongM, psiLo, psiHi);
    sortUnique(breaks);

    auto profile = [&](double psi) {
        const dvec3 toward = std::cos(psi) * c + std::sin(psi) * m;
        const double centre = std::clamp(psi * slope, -zetaMax, zetaMax);
        std::vector<double> zb = gradedBreaks(-zetaMax - centre, zetaMax - centre, across, ratio);
        for (double& z : zb) z += centre;
        const double fromV = std::fabs(std::remainder(psi - psiV, 2.0 * kPi));
        if (wedge && fromV < 4.0 * alongM)
            addGraded(zb, zetaV + (psi - psiV) * slope, std::max(1e-9, 0.05 * fromV * across / alongM), across, -zetaMax, zetaMax);
        if (std::fabs(naxis) > 1e-15) {
            const double zh = std::atan(-(std::cos(psi) * nc + std::sin(psi) * nm) / naxis);
            if (zh > -zetaMax && zh < zetaMax) zb.push_back(zh);
        }
        sortUnique(zb);
        // In t = tan(ζ/2) the semicircle is rational (cos ζ = (1 − t²)/(1 + t²), sin ζ = 2t/(1 + t²),
        // dζ = 2dt/(1 + t²)): no sine or cosine per node, which were half the build's time.
        for (double& z : zb) z = std::tan(0.5 * z);
        auto along = [&](double t) {
            const double q = 1.0 / (1.0 + t * t), cz = (1.0 - t * t) * q;
            return lobe(f.v, cz * toward + 2.0 * t * q * axis, gloss) * cz * 2.0 * q;
        };
        return integrateAdaptively(along, zb, 0.1 * relTol);
    };
    const CumulativeIntegral cumulative(profile, breaks, relTol);
    HemisphereFractions out;
    out.unoccluded = cumulative.total();
    for (double eps : epsilons) out.fractions.push_back((cumulative(kPi - eps) - cumulative(-eps)) / out.unoccluded);
    return out;
}

}  // namespace metamer
