// The one rule that puts spectra given as data onto a Grid's bands (docs/physics.md,
// "Resampling"). Every spectrum of a scene and of the display path goes through it: lights,
// reflectances, excitation and emission, Donaldson matrices on both axes, texels of spectral
// textures, detector sensitivities, the representation modes' reference data. Tests:
// spectral/resampling_test.cpp.
//
// Band i (centre λi, width Δλ) of data w0 < … < wn−1 with values v, under grid.resampling:
//   1. λi is a data point (within kCoincidence_nm): the tabulated value, bit for bit.
//   2. the grid is coarser than the data at λi (Δλ > the spacing of the data interval holding λi,
//      or of the nearest end interval when λi lies outside the data): the mean over the band of
//      the piecewise-linear data, 0 outside them, except that a band whose centre lies inside the
//      data holds the end value over the part of the band the data do not reach.
//   3. otherwise: the interpolant at λi (linear, or Sprague for Resampling::Sprague), 0 outside.
// Resampling::BandMean applies rule 2 to every band.
//
// Every rule is linear in the data's values and depends only on their wavelengths, so it is a
// sparse matrix (BandWeights) that textures and matrices apply to many value sets at once.
#pragma once

#include "spectral/grid.h"
#include "spectral/spectrum.h"

#include <cstddef>
#include <vector>

namespace metamer {

// A band centre this close to a data point is on it (rule 1): far below any step a file or a grid
// can state, far above the rounding of start + i·step.
inline constexpr double kCoincidence_nm = 1e-9;

// Band b of a spectrum with values v at the data wavelengths is Σ_k weights[b][k]·v[first[b] + k].
struct BandWeights {
    std::vector<size_t> first;                 // per band, the first data index with a weight
    std::vector<std::vector<double>> weights;  // per band, the weights from first[b] on

    std::vector<double> apply(const std::vector<double>& values) const;
    // Band b alone from values at the data wavelengths (a pixel's bands, say), without a copy: a
    // tabulated value comes back as it is, not multiplied.
    template <typename T>
    double at(size_t b, const T* values) const {
        const std::vector<double>& wb = weights[b];
        if (wb.size() == 1 && wb[0] == 1.0) return double(values[first[b]]);
        double s = 0.0;
        for (size_t k = 0; k < wb.size(); ++k) s += wb[k] * double(values[first[b] + k]);
        return s;
    }
};
BandWeights bandWeights(const std::vector<double>& wavelengths_nm, const Grid& grid);

// The spectrum on the grid (a constant is that constant in every band).
std::vector<double> resample(const Spectrum& s, const Grid& grid);

// Which of the rules above gives band b (for messages, docs and tests).
enum class BandRule { Tabulated, BandMean, Interpolated, Outside };
BandRule bandRule(const std::vector<double>& wavelengths_nm, const Grid& grid, int band);

// Whether the data cover every band centre of the grid.
struct CoverageGap {
    bool covered = true;
    double data_lo = 0, data_hi = 0;  // the data's own range
    bool overlaps = true;             // false when the data lie entirely outside the grid
};
CoverageGap coverage(const Spectrum& s, const Grid& grid);
CoverageGap coverageOf(const std::vector<double>& wavelengths_nm, const Grid& grid);

// Sprague (1880) interpolation as CIE 167:2005 recommends it for uniformly spaced data: the
// weights of the n ≥ 6 data values at x, which lies in data interval j (w_j ≤ x ≤ w_j+1) at
// fraction t of it. The interval's quintic uses values j−2 … j+3, the first and last two of
// which may be the standard's extrapolated points beyond each end (themselves combinations of the
// six end values). Returns the weights of data values first, first + 1, … (at most 10).
std::vector<double> spragueWeights(size_t n, size_t j, double t, size_t& first);

}  // namespace metamer
