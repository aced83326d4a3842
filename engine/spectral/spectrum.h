// A spectrum as read from the user or the library: a piecewise-linear function of wavelength
// (or a constant). Onto a Grid's bands it goes by spectral/resampling.h.
#pragma once

#include "core/error.h"
#include "spectral/grid.h"

#include <optional>
#include <string>
#include <vector>

namespace metamer {

// What a spectrum means decides what happens where its data do not cover the grid
// (docs/physics.md, "Coverage policy").
enum class SpectrumKind {
    Light,        // relative spectral power; × scale gives W·m⁻²·nm⁻¹ or W·sr⁻¹·nm⁻¹
    Reflectance,  // diffuse or specular reflectance factor, 0..1 (metals' specular may approach 1)
    Excitation,   // fluorescence absorptance, 0..1
    Emission,     // fluorescence emission shape, relative (normalized by the engine)
    Observer,     // a detector's spectral sensitivity
    Transmittance,  // a thin sheet's transmittance per crossing, 0..1
    Absorbance,     // decadic absorbance per metre (m⁻¹, ≥ 0), or a dye's molar absorptivity
    KubelkaMunk,    // a Kubelka–Munk absorption K or scattering S coefficient, m⁻¹ (≥ 0), or a
                    // pigment's per unit concentration
};

const char* kindName(SpectrumKind kind);

// The largest values a scene's spectra may hold (issue 51, class 1): the GPU path computes in
// float32, and a value past these became Inf, then NaN, in the cube with exit status 0.
// A ratio (reflectance, absorptance, a sheet's transmittance) above 1 is warned about and rendered,
// up to 10³: no passive surface returns a thousand times what reaches it.
constexpr double kMaxRatio = 1e3;
// A decadic absorbance per metre (the material's own plus its dyes' 100·ε·c), or a dye's molar
// absorptivity: 10²⁰ is an attenuation length far below a nucleus's size; a × any path stays finite.
constexpr double kMaxAbsorbance = 1e20;

struct Spectrum {
    // Data: strictly increasing wavelengths (nm) with values; or a constant over all wavelengths.
    std::vector<double> wavelengths_nm;
    std::vector<double> values;
    std::optional<double> constant;
    std::string source;  // for messages: "illuminants/D65", "my.csv", "inline", "constant 0.8"

    static Spectrum makeConstant(double value);
    bool isConstant() const { return constant.has_value(); }

    double minWavelength() const;  // -inf for a constant
    double maxWavelength() const;  // +inf for a constant

    // Piecewise-linear value; 0 outside the data.
    double at(double nm) const;
    // ∫ f(λ) dλ over [a, b] of the piecewise-linear function (0 outside the data).
    double integrate(double a, double b) const;
    // ∫ f over the whole data range (constants: error, it is unbounded).
    double integral() const;

    // Checks sorted, strictly increasing, finite, same lengths, ≥ 2 points (or constant).
    void validate(const Where& where) const;
};

}  // namespace metamer
