#include "isp/colour_correction.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace metamer {

CorrectionForm parseCorrectionForm(const std::string& name, const Where& where) {
    if (name == "linear") return CorrectionForm::Linear;
    if (name == "root-polynomial") return CorrectionForm::RootPolynomial2;
    failInput(where, "'{}' is not a colour correction: linear or root-polynomial", name);
}

std::vector<double> correctionTerms(CorrectionForm form, const glm::dvec3& rgb) {
    if (form == CorrectionForm::Linear) return {rgb.r, rgb.g, rgb.b};
    const double r = std::max(rgb.r, 0.0), g = std::max(rgb.g, 0.0), b = std::max(rgb.b, 0.0);
    return {rgb.r, rgb.g, rgb.b, std::sqrt(r * g), std::sqrt(g * b), std::sqrt(r * b)};
}

ColourCorrection fitColourCorrection(CorrectionForm form, const std::vector<glm::dvec3>& rgb,
                                     const std::vector<glm::dvec3>& xyz, const Where& where) {
    const size_t terms = form == CorrectionForm::Linear ? 3 : 6;
    if (rgb.size() != xyz.size() || rgb.size() < terms)
        failInput(where, "a {}-term colour correction needs at least {} patches with camera RGB and XYZ each; got {} and {}",
                  terms, terms, rgb.size(), xyz.size());
    Eigen::MatrixXd A(Eigen::Index(rgb.size()), Eigen::Index(terms)), B(Eigen::Index(rgb.size()), 3);
    for (size_t p = 0; p < rgb.size(); ++p) {
        const std::vector<double> t = correctionTerms(form, rgb[p]);
        for (size_t k = 0; k < terms; ++k) A(Eigen::Index(p), Eigen::Index(k)) = t[k];
        for (int c = 0; c < 3; ++c) B(Eigen::Index(p), c) = xyz[p][c];
    }
    // Column-pivoted QR: a rank-deficient set of patches (a grey ramp alone) is found, not solved.
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
    if (qr.rank() < Eigen::Index(terms))
        failInput(where, "the patches determine only {} of the {} terms of the colour correction (too few distinct colours)",
                  qr.rank(), terms);
    const Eigen::MatrixXd X = qr.solve(B);  // terms × 3
    ColourCorrection c;
    c.form = form;
    for (size_t k = 0; k < terms; ++k)
        c.columns.push_back(glm::dvec3(X(Eigen::Index(k), 0), X(Eigen::Index(k), 1), X(Eigen::Index(k), 2)));
    return c;
}

glm::dvec3 applyColourCorrection(const ColourCorrection& c, const glm::dvec3& rgb) {
    // Per pixel of a developed frame: the terms without correctionTerms' allocation.
    glm::dvec3 xyz = rgb.r * c.columns[0] + rgb.g * c.columns[1] + rgb.b * c.columns[2];
    if (c.form == CorrectionForm::RootPolynomial2) {
        const double r = std::max(rgb.r, 0.0), g = std::max(rgb.g, 0.0), b = std::max(rgb.b, 0.0);
        xyz += std::sqrt(r * g) * c.columns[3] + std::sqrt(g * b) * c.columns[4] + std::sqrt(r * b) * c.columns[5];
    }
    return xyz;
}

}  // namespace metamer
