// A Donaldson (bispectral re-radiation) matrix D(λin, λout) as read from a file, and its
// resampling onto a Grid: the two-dimensional counterpart of spectrum.h. See docs/physics.md,
// "Fluorescence" (what D means, its units) and "Resampling" (band averages).
#pragma once

#include "core/error.h"
#include "spectral/grid.h"
#include "spectral/resampling.h"
#include "spectral/spectrum.h"

#include <string>
#include <vector>

namespace metamer {

// D at data points (in_nm[i], out_nm[o]), bilinear between them (the tensor product of the
// piecewise-linear interpolation of spectra) and 0 outside. D is the fluorescent re-radiation
// per unit excitation wavelength, nm⁻¹: under irradiance E(λin) a surface with matrix D emits
// the radiance L(λout) = (1/π) ∫ D(λin, λout) E(λin) dλin (energy units, as the CIE's
// bispectral luminescent radiance factor). The reflected part (λin = λout as a Dirac) is not in
// D: it is the material's diffuse reflectance.
struct BispectralMatrix {
    std::vector<double> in_nm;   // excitation wavelengths, strictly increasing
    std::vector<double> out_nm;  // emission wavelengths, strictly increasing
    std::vector<double> values;  // D(in_nm[i], out_nm[o]) at [i * out_nm.size() + o], nm⁻¹
    std::string source;          // for messages: "fluorescent/x", "my.csv", "my.exr"

    size_t inCount() const { return in_nm.size(); }
    size_t outCount() const { return out_nm.size(); }
    double value(size_t i, size_t o) const { return values[i * out_nm.size() + o]; }

    // Bilinear value; 0 outside the data.
    double at(double in, double out) const;

    // ∫∫ D dλin dλout over the data (exact for the bilinear function), nm⁻¹·nm² = nm.
    double integral() const;

    // At least 2 wavelengths on each axis, strictly increasing and finite; values finite and
    // ≥ 0; sizes agree. Errors name `where`.
    void validate(const Where& where) const;

    // D(λin, λout) = excitation(λin) · emission(λout) sampled at the two spectra's own data
    // points: a rank-one matrix, whose resampling is the product of the factors' resamplings.
    static BispectralMatrix outer(const Spectrum& excitation, const Spectrum& emission);
};

// The matrix on the grid, R[i·N + o] with N = grid.bands(), in nm⁻¹: resample() along each axis
// (spectral/resampling.h, every rule), R = W_in · D · W_outᵀ. So a band pair whose centres are
// both data points holds the tabulated D, band means keep Σ R·Δλ² = ∫∫ D on grids coarser than
// the data, and for a rank-one matrix u(λin)·w(λout) R is exactly resample(u) ⊗ resample(w).
std::vector<double> resampleMatrix(const BispectralMatrix& d, const Grid& grid);

}  // namespace metamer
