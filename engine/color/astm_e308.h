// ASTM E308-15 colorimetry: tristimulus weighting factors for 10 and 20 nm data, computed from the
// 1 nm colour-matching functions and the illuminant per ASTM E2022-11 (the values colour-science
// 0.4.7 computes in sd_to_XYZ(method="ASTM E308")), and their use as a detector on a render grid.
// docs/color.md, "Integration". Tests: color/astm_e308_test.cpp, and against colour-science in
// tests/colorimetry_standards_test.cpp.
//
// The method, for data R at the grid's wavelengths λb (every 10 or 20 nm, on whole tens of nm):
//   * the practice range 360–780 nm: the CMFs beyond it are left out;
//   * a 1 nm table of S(λ)·cmf(λ) over 360–780 nm, S the illuminant at 1 nm (Sprague (CIE 167)
//     from uniform data, its end values held beyond its data);
//   * W_b = S·cmf at λb plus, for every 1 nm wavelength between samples, S·cmf times the Lagrange
//     coefficient of sample b in the interpolation of R there (cubic over 4 samples inside, quadratic
//     over 3 in the first and last interval): X = Σ_b W_b·R_b is X = Σ_λ S·x̄·R at 1 nm with R
//     interpolated the standard's way;
//   * weights of samples outside the data's range (the grid's bands inside 360–780 nm) are added to
//     its first and last band;
//   * 20 nm data: the 10 nm values between samples are interpolated first (weights −1/16, 9/16, 9/16,
//     −1/16, quadratic extrapolation past the ends), then the 10 nm weights apply (E308's "20 nm
//     interpolation method", colour-science's default);
//   * 1 and 5 nm data: the sum Σ S·cmf·R at the data's own wavelengths (E308 tabulates nothing
//     finer), over the practice range.
// k (the normalization) is left to the caller, who divides by the white's response.
#pragma once

#include "color/detector.h"
#include "color/reference_white.h"
#include "spectral/grid.h"

#include <vector>

namespace metamer {

inline constexpr double kAstmE308StartNm = 360.0, kAstmE308EndNm = 780.0;  // the practice range

// The weighting factors for reflectance factors on `grid`: W[channel][band], un-normalized
// (Σ_b W[1][b] is Σ S·ȳ over 360–780 nm at 1 nm). `cmf1nm` holds the observer's x̄, ȳ, z̄ at every
// whole nm of 360–780; `illuminant1nm` S at the same wavelengths. Bands outside 360–780 nm have
// weight 0. Input errors (at `where`) for a step other than 1, 5, 10, 20 nm, centres off whole tens
// of nm (10, 20 nm steps), or fewer than 3 bands inside the practice range.
std::vector<std::vector<double>> astmE308Weights(const std::vector<std::vector<double>>& cmf1nm,
                                                 const std::vector<double>& illuminant1nm, const Grid& grid,
                                                 const Where& where);

// The white's irradiance at every whole nm of 360–780 nm, as the weighting factors need it.
std::vector<double> practiceRangeIlluminant(const ReferenceWhite& white);

// Replaces an observer detector's weights by the E308 factors for the radiance of surfaces lit by
// `white`: weight_b = W_b / E_b, so that a reflectance factor R under the white (radiance R·E/π)
// responds Σ W_b·R_b / π. A band where E_b = 0 but W_b ≠ 0 is left out with a warning.
void applyAstmE308(Detector& observer, const SpectrumLibrary& library, const ReferenceWhite& white,
                   const Where& where);

}  // namespace metamer
