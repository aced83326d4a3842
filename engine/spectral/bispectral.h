// A Donaldson (bispectral re-radiation) matrix D(λin, λout) as read from a file, and its
// resampling onto a Grid: the two-dimensional counterpart of spectrum.h. See docs/physics.md,
// "Fluorescence" (what D means, its units) and "Resampling" (band averages).
#pragma once

#include "core/error.h"
#include "spectral/grid.h"
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

// The band-averaging of spectrum.h's resample() as a linear operator on data values: band b of a
// spectrum with values v at `wavelengths_nm` is Σ_j weight(b, j) · v_j. Sparse: each band has a
// run of consecutive non-zero weights starting at first[b].
struct BandWeights {
    std::vector<size_t> first;                 // per band, the first data index with a weight
    std::vector<std::vector<double>> weights;  // per band, the weights from first[b] on

    std::vector<double> apply(const std::vector<double>& values) const;
};
BandWeights bandWeights(const std::vector<double>& wavelengths_nm, const Grid& grid);

// The matrix on the grid: band (i, o) holds the mean of D over band i of λin × band o of λout,
// R[i·N + o] with N = grid.bands(), in nm⁻¹. The operator is resample() along each axis (its end
// rule included), so Σ R·Δλ² = ∫∫ D when the data lie inside the grid, and for a rank-one matrix
// u(λin)·w(λout) R is exactly resample(u) ⊗ resample(w).
std::vector<double> resampleMatrix(const BispectralMatrix& d, const Grid& grid);

// Whether each axis's data cover every band centre of the grid (as coverage() for spectra).
CoverageGap coverageOf(const std::vector<double>& wavelengths_nm, const Grid& grid);

}  // namespace metamer
