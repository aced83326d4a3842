#include "spectral/kubelka_munk.h"

#include "core/quadrature.h"
#include "spectral/dielectric.h"

#include <array>
#include <cmath>

namespace metamer {

KubelkaMunkConstants kubelkaMunkConstants(double K, double S) {
    // √K·√(K + 2S) rather than √(K² + 2KS), which overflows first.
    return {K, S, K + S, std::sqrt(K) * std::sqrt(K + 2.0 * S)};
}

KubelkaMunkLayer kubelkaMunkLayer(const KubelkaMunkConstants& f, double X) {
    KubelkaMunkLayer out;
    if (std::isinf(X)) {
        out.reflectance = kubelkaMunkInfinite(f.K, f.S);
        out.transmittance = (f.alpha > 0.0) ? 0.0 : 1.0;
        return out;
    }
    const double bx = f.beta * X;
    // t = tanh(βX)/β and sech(βX) from e = exp(−βX): tanh = −expm1(−2βX)/(1 + e²), sech = 2e/(1 + e²);
    // by its series where βX is small (tanh x/x = 1 − x²/3 + …), where the quotient would lose digits.
    const double e = std::exp(-bx), e2 = e * e;
    const double t = bx < 1e-4 ? X * (1.0 - bx * bx / 3.0) : -std::expm1(-2.0 * bx) / ((1.0 + e2) * f.beta);
    const double denominator = f.alpha * t + 1.0;
    // S·t/(α·t + 1) written as 1/(α/S + 1/(S·t)), finite when S·t overflows.
    out.reflectance = f.S > 0.0 ? 1.0 / (f.alpha / f.S + 1.0 / (f.S * t)) : 0.0;
    out.transmittance = 2.0 * e / ((1.0 + e2) * denominator);
    return out;
}

KubelkaMunkLayer kubelkaMunkLayer(double K, double S, double X) { return kubelkaMunkLayer(kubelkaMunkConstants(K, S), X); }

double kubelkaMunkInfinite(double K, double S) {
    if (S <= 0.0) return 0.0;
    const double q = K / S;
    return 1.0 / (1.0 + q + std::sqrt(q * (q + 2.0)));
}

double kubelkaMunkOverSubstrate(const KubelkaMunkConstants& film, double X, double Rg) {
    const KubelkaMunkLayer l = kubelkaMunkLayer(film, X);
    if (l.transmittance == 0.0) return l.reflectance;
    // R_l·Rg = 1 only for a layer that absorbs nothing over a white substrate: all light returns.
    const double denominator = 1.0 - l.reflectance * Rg;
    if (denominator <= 0.0) return 1.0;
    return l.reflectance + l.transmittance * l.transmittance * Rg / denominator;
}

double kubelkaMunkOverSubstrate(double K, double S, double X, double Rg) {
    return kubelkaMunkOverSubstrate(kubelkaMunkConstants(K, S), X, Rg);
}

double kubelkaMunkStack(std::span<const KubelkaMunkFilm> bottomUp, double substrate) {
    double r = substrate;
    for (const KubelkaMunkFilm& f : bottomUp) r = kubelkaMunkOverSubstrate(f.K, f.S, f.X, r);
    return r;
}

KubelkaMunkCoefficients kubelkaMunkMix(std::span<const KubelkaMunkPigment> pigments, KubelkaMunkCoefficients own) {
    for (const KubelkaMunkPigment& p : pigments) {
        own.K += p.concentration * p.k;
        own.S += p.concentration * p.s;
    }
    return own;
}

double kOverSFromInfinite(double rInfinite) { return (1.0 - rInfinite) * (1.0 - rInfinite) / (2.0 * rInfinite); }

double saundersonBody(double R, double k1, double k2) { return (1.0 - k1) * (1.0 - k2) * R / (1.0 - k2 * R); }

double saundersonMeasured(double R, double k1, double k2) { return k1 + saundersonBody(R, k1, k2); }

double saundersonInverse(double measured, double k1, double k2) {
    const double m = measured - k1;
    return m / ((1.0 - k1) * (1.0 - k2) + k2 * m);
}

double saundersonK1(double n) { return (n - 1.0) * (n - 1.0) / ((n + 1.0) * (n + 1.0)); }

double externalDiffuseReflectance(double n) {
    // u = sin²θ in air: ∫₀¹ R(θ) du. Smooth in u; the integrand is steep only near grazing.
    const auto f = [n](double u) { return fresnelReflectance(1.0, n, std::sqrt(std::max(0.0, 1.0 - u))).unpolarized(); };
    const std::array<double, 3> breaks{0.0, 0.9, 1.0};
    return integrateAdaptively(f, breaks, 1e-13);
}

double internalDiffuseReflectance(double n) {
    if (n <= 1.0) return 0.0;
    // Inside the medium, u = sin²θ: light with u > 1/n² is totally reflected (∫ du = 1 − 1/n²). Below
    // it, u = (1 − s²)/n² with s = cos θ in air, so the square-root edge at the critical angle becomes
    // a smooth end: du = 2s/n² ds.
    const double n2 = n * n;
    const auto f = [n, n2](double s) {
        const double u = (1.0 - s * s) / n2;
        return fresnelReflectance(n, 1.0, std::sqrt(std::max(0.0, 1.0 - u))).unpolarized() * 2.0 * s / n2;
    };
    const std::array<double, 3> breaks{0.0, 0.1, 1.0};
    return 1.0 - 1.0 / n2 + integrateAdaptively(f, breaks, 1e-13);
}

}  // namespace metamer
