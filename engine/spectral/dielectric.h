// Light at dielectric interfaces and through absorbing media, per wavelength, in double: the
// physics of the slab material (the reference renderer calls it; shaders/transmit.frag evaluates
// the same formulas in float; docs/physics.md, "Transparent objects"). Unpolarized light throughout: s and p are carried separately and averaged
// only at the end, which is what an incoherent slab needs. Plain functions, no scene.
// Tests: spectral/dielectric_test.cpp.
#pragma once

#include <string>
#include <vector>

namespace metamer {

// n(λ) of a non-absorbing dielectric: a constant, a table (linear between its points, constant
// beyond), Sellmeier n² = 1 + Σ Bᵢλ²/(λ² − Cᵢ) or Cauchy n = A + B/λ² + C/λ⁴, with λ in µm (the
// convention of glass catalogues: Cᵢ in µm², B in µm², C in µm⁴).
struct RefractiveIndex {
    enum class Kind { Constant, Table, Sellmeier, Cauchy };
    Kind kind = Kind::Constant;
    double constant = 1.0;
    std::vector<double> wavelengths_nm, values;  // Table: increasing wavelengths
    std::vector<double> b, c;                    // Sellmeier: B₁…, C₁… (µm²); Cauchy: b = {A, B, C}

    double at(double wavelength_nm) const;
};

// Schott's N-BK7 (Sellmeier coefficients from its data sheet): n_d = 1.5168, V_d = 64.17.
RefractiveIndex nbk7();

// The Abbe number V_d = (n_d − 1)/(n_F − n_C), at the helium d line (587.5618 nm) and the
// hydrogen F (486.1327 nm) and C (656.2725 nm) lines.
double abbeNumber(const RefractiveIndex& n);

// Reflectance at one interface from a medium of index n1 into n2, for light arriving at cos θ₁
// (0 < cosI ≤ 1): s and p powers, and whether the light is totally reflected (then both are 1).
struct FresnelReflectance {
    double s = 0.0, p = 0.0;
    bool total = false;
    double unpolarized() const { return 0.5 * (s + p); }
};
FresnelReflectance fresnelReflectance(double n1, double n2, double cosI);

// cos θ of the refracted ray (Snell), 0 when the light is totally reflected.
double refractedCosine(double n1, double n2, double cosI);

// A plane-parallel slab of index n in air, seen at cos θ₀ in air, with internal transmittance
// `tau` along the refracted path (τ = 10^(−A·d/cos θt) for a decadic absorbance A per metre: see
// slabInternalTransmittance). Incoherent: the multiple reflections inside add in power, so
// R = R₁ + (1 − R₁)²·R₁·τ²/(1 − R₁²τ²) and T = (1 − R₁)²·τ/(1 − R₁²τ²) for each polarization,
// then averaged. Exact for a flat slab; the colour of a curved one is not (docs/physics.md).
struct SlabReflectanceTransmittance {
    double reflectance = 0.0, transmittance = 0.0;
};
SlabReflectanceTransmittance slab(double n, double cosIncidence, double tau);

// τ along the refracted path through a slab of thickness d (m) of decadic absorbance A (per
// metre): 10^(−A·d/cos θt).
double slabInternalTransmittance(double n, double cosIncidence, double absorbancePerMetre, double thickness_m);

// Beer–Lambert: the transmittance of a path of length d (m) through a medium of decadic
// absorbance A (per metre), 10^(−A·d); absorbances of dyes in one medium add (Σ εᵢ·cᵢ).
double beerLambert(double absorbancePerMetre, double path_m);

}  // namespace metamer
