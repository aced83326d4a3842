// The image processor's colour correction (issue 48, item 2): white-balanced camera RGB → CIE 1931
// XYZ by a matrix fitted on ColorChecker patches, in two forms — a 3 × 3 least-squares matrix,
// and Finlayson, Mackiewicz and Hurlbert's root-polynomial of degree 2 (IEEE TIP 24, 2015: the
// terms r, g, b, √(rg), √(gb), √(rb), each of degree one, so the correction is exposure-invariant
// as a 3 × 3 is and a plain polynomial is not). Tests: engine/isp/colour_correction_test.cpp.
#pragma once

#include "core/error.h"

#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace metamer {

enum class CorrectionForm { Linear, RootPolynomial2 };

// "linear" or "root-polynomial"; an input error at `where` otherwise.
CorrectionForm parseCorrectionForm(const std::string& name, const Where& where);

struct ColourCorrection {
    CorrectionForm form = CorrectionForm::Linear;
    std::vector<glm::dvec3> columns;  // XYZ = Σ_t term_t(rgb) · columns[t]: 3 terms, or 6
};

// The expansion's terms of `rgb` (negative values are clamped at 0 under the roots).
std::vector<double> correctionTerms(CorrectionForm form, const glm::dvec3& rgb);

// The least-squares fit Σ_p ‖Σ_t term_t(rgb_p)·c_t − XYZ_p‖² → min over the patches (at least as
// many as terms; an input error at `where` when the patches do not determine the terms).
ColourCorrection fitColourCorrection(CorrectionForm form, const std::vector<glm::dvec3>& rgb,
                                     const std::vector<glm::dvec3>& xyz, const Where& where);

glm::dvec3 applyColourCorrection(const ColourCorrection& c, const glm::dvec3& rgb);

}  // namespace metamer
