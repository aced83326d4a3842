// Translucent layers by Kubelka–Munk: a paint, ink or coating film of absorption K and scattering
// S per unit thickness, its reflectance and transmittance for diffuse light, over a substrate, in
// stacks, with the Saunderson correction for its surface (docs/physics.md, "Paints and coatings").
// Per wavelength, in double; plain functions, no scene. The scene's layered materials call them
// once per scene (scene/scene_on_grid): their result is a body reflectance like any other.
// Tests: spectral/kubelka_munk_test.cpp; tests/python/check_kubelka_munk.py (numpy closed forms
// and a scipy two-flux solve).
#pragma once

#include <span>

namespace metamer {

// One layer's reflectance R (over a black substrate) and transmittance T, for diffuse light.
struct KubelkaMunkLayer {
    double reflectance = 0.0, transmittance = 1.0;
};

// A homogeneous layer of thickness X with K, S ≥ 0 (units: K·X and S·X are numbers, e.g. K and S
// in m⁻¹ and X in m). With α = K + S and β = √(K² + 2KS) (i.e. a·S and b·S in the usual
// a = 1 + K/S, b = √(a² − 1)): R = S·t/(α·t + 1) and T = sech(βX)/(α·t + 1), t = tanh(βX)/β.
// That form has no 0/0 at S = 0 (T = e^(−KX)) or K = 0 (R = SX/(1 + SX)), and none at X = ∞
// (R = R∞, T = 0).
KubelkaMunkLayer kubelkaMunkLayer(double K, double S, double X);

// What every thickness of one film shares (α, β above), for evaluating it at many thicknesses — a
// thickness map's texels: one exp per evaluation, no square root, tanh or cosh.
struct KubelkaMunkConstants {
    double K = 0.0, S = 0.0, alpha = 0.0, beta = 0.0;
};
KubelkaMunkConstants kubelkaMunkConstants(double K, double S);
KubelkaMunkLayer kubelkaMunkLayer(const KubelkaMunkConstants& film, double X);
double kubelkaMunkOverSubstrate(const KubelkaMunkConstants& film, double X, double Rg);

// R∞ = a − b, the reflectance of a layer thick enough to hide anything, in the form
// 1/(1 + K/S + √((K/S)² + 2K/S)), which does not cancel when K/S is large. 0 when S = 0.
double kubelkaMunkInfinite(double K, double S);

// The reflectance of the layer over a substrate of reflectance Rg:
// R = R_l + T²·Rg/(1 − R_l·Rg) (equal to Kubelka's closed form
// (1 − Rg(a − b·coth bSX))/(a − Rg + b·coth bSX)). X = ∞ gives R∞ whatever Rg.
double kubelkaMunkOverSubstrate(double K, double S, double X, double Rg);

// A stack of layers applied bottom-up over `substrate`: each layer's result is the next one's Rg.
struct KubelkaMunkFilm {
    double K = 0.0, S = 0.0, X = 0.0;
};
double kubelkaMunkStack(std::span<const KubelkaMunkFilm> bottomUp, double substrate);

// A film's K and S from its pigments by the two-constant rule (Duncan): its own K₀, S₀ plus each
// pigment's concentration times its k and s per unit concentration, added in order —
// K = K₀ + Σ cᵢkᵢ, S = S₀ + Σ cᵢsᵢ. The concentrations are not normalized to sum to 1: they are
// amounts in whatever unit the pigment data are per (docs/physics.md, "Pigment mixtures").
struct KubelkaMunkPigment {
    double concentration = 0.0, k = 0.0, s = 0.0;
};
struct KubelkaMunkCoefficients {
    double K = 0.0, S = 0.0;
};
KubelkaMunkCoefficients kubelkaMunkMix(std::span<const KubelkaMunkPigment> pigments, KubelkaMunkCoefficients own = {});

// K/S from R∞ (the inverse of kubelkaMunkInfinite): (1 − R∞)²/(2R∞).
double kOverSFromInfinite(double rInfinite);

// Saunderson's correction of a KM (body) reflectance R for a surface with external reflectance
// k1 (specular, at normal incidence) and internal diffuse reflectance k2:
//   measured  R_m = k1 + (1 − k1)(1 − k2)·R/(1 − k2·R)      (specular included)
//   body      R_b = (1 − k1)(1 − k2)·R/(1 − k2·R)           (what Metamer draws as ρd: the surface's
//                                                            own reflection k1 is the specular term)
//   inverse   R = (R_m − k1)/((1 − k1)(1 − k2) + k2·(R_m − k1))
double saundersonMeasured(double R, double k1, double k2);
double saundersonBody(double R, double k1, double k2);
double saundersonInverse(double measured, double k1, double k2);

// k1: the Fresnel reflectance at normal incidence from air into index n, ((n − 1)/(n + 1))².
double saundersonK1(double n);
// The diffuse reflectance of a flat interface between air and index n ≥ 1 for perfectly diffuse
// (Lambertian) light, ∫ R(θ)·2 sin θ cos θ dθ over the hemisphere, unpolarized, by adaptive
// Gauss–Kronrod integration of Fresnel's equations (not a fit). Internal: light inside the medium
// (total reflection beyond the critical angle) — Saunderson's k2; external: light from the air.
// At n = 1.5: 0.59635 and 0.09178, related by 1 − r_i = (1 − r_e)/n².
double internalDiffuseReflectance(double n);
double externalDiffuseReflectance(double n);

}  // namespace metamer
