// The colour correction's fits (issue 48, items 2 and 3) on the 24 ColorChecker patches: a camera
// whose sensitivities are a linear transform of the CIE 1931 functions is corrected exactly
// (ΔE00 = 0) by either form; a real camera's errors fall with the root-polynomial; the
// root-polynomial is exposure-invariant.
#include "isp/colour_correction.h"

#include "color/camera_characterization.h"
#include "color/delta_e.h"
#include "color/detector_registry.h"
#include "color/lab.h"
#include "spectral/resampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace metamer;

namespace {

const SpectrumLibrary& library() {
    static const SpectrumLibrary lib;
    return lib;
}

const Grid kGrid{380, 730, 5};

struct Patches {
    std::vector<glm::dvec3> rgb, xyz;  // white-balanced camera RGB; XYZ with the white's Y = 1
    glm::dvec3 white{0.0};
};

// Each patch's camera response and XYZ under `light`, the camera white-balanced on the perfect
// diffuser (its RGB = 1, 1, 1).
Patches patches(const Detector& camera, const std::string& light) {
    const Detector cmf = makeDetector("cie1931", library(), kGrid, Integration::Riemann, Where{});
    const std::vector<double> e = resample(library().get("illuminants/" + light, Where{}), kGrid);
    const glm::dvec3 rawWhite = detectorResponse3(camera, e.data()), xyzWhite = detectorResponse3(cmf, e.data());
    Patches p;
    p.white = xyzWhite / xyzWhite.y;
    for (const std::string& name : colorCheckerPatchNames()) {
        const std::vector<double> rho = resample(library().get("colorchecker/" + name, Where{}), kGrid);
        std::vector<double> radiance(e.size());
        for (size_t b = 0; b < e.size(); ++b) radiance[b] = rho[b] * e[b];
        p.rgb.push_back(detectorResponse3(camera, radiance.data()) / rawWhite);
        p.xyz.push_back(detectorResponse3(cmf, radiance.data()) / xyzWhite.y);
    }
    return p;
}

struct Errors {
    double rms = 0.0, max = 0.0;
};
Errors deltaE(const ColourCorrection& c, const Patches& p) {
    Errors e;
    for (size_t i = 0; i < p.rgb.size(); ++i) {
        const double d = deltaE2000(xyzToLab(applyColourCorrection(c, p.rgb[i]), p.white), xyzToLab(p.xyz[i], p.white));
        e.rms += d * d;
        e.max = std::max(e.max, d);
    }
    e.rms = std::sqrt(e.rms / double(p.rgb.size()));
    return e;
}

}  // namespace

TEST(ColourCorrection, ACameraThatIsALinearTransformOfTheCmfsIsCorrectedExactly) {
    // Sensitivities M·(x̄, ȳ, z̄) for an invertible M with cross-talk.
    Detector luther = makeDetector("cie1931", library(), kGrid, Integration::Riemann, Where{});
    const double M[3][3] = {{0.9, 0.3, -0.05}, {0.1, 0.8, 0.15}, {0.02, 0.1, 0.95}};
    const auto cmf = luther.weights;
    for (int c = 0; c < 3; ++c)
        for (size_t b = 0; b < cmf[0].size(); ++b)
            luther.weights[size_t(c)][b] = M[c][0] * cmf[0][b] + M[c][1] * cmf[1][b] + M[c][2] * cmf[2][b];
    for (const char* light : {"D65", "A", "FL2"})
        for (CorrectionForm form : {CorrectionForm::Linear, CorrectionForm::RootPolynomial2}) {
            const Patches p = patches(luther, light);
            const Errors e = deltaE(fitColourCorrection(form, p.rgb, p.xyz, Where{"patches"}), p);
            EXPECT_LT(e.max, 1e-8) << light << (form == CorrectionForm::Linear ? " linear" : " root-polynomial");
        }
}

TEST(ColourCorrection, ARealCamerasErrorsFallWithTheRootPolynomialWhichIsExposureInvariant) {
    for (const char* spec : {"camera:nikon_d5100", "camera:canon_eos_5d_mark_ii", "camera:sigma_sd_merrill"})
        for (const char* light : {"D65", "A"}) {
            const Detector camera = makeDetector(spec, library(), kGrid, Integration::Riemann, Where{});
            const Patches p = patches(camera, light);
            const ColourCorrection linear = fitColourCorrection(CorrectionForm::Linear, p.rgb, p.xyz, Where{"patches"});
            const ColourCorrection root = fitColourCorrection(CorrectionForm::RootPolynomial2, p.rgb, p.xyz, Where{"patches"});
            const Errors el = deltaE(linear, p), er = deltaE(root, p);
            std::printf("    %-28s %-3s ΔE00 on the 24 patches: 3×3 rms %.3f max %.3f; root-polynomial rms %.3f max %.3f\n",
                        spec, light, el.rms, el.max, er.rms, er.max);
            EXPECT_LT(er.rms, el.rms) << spec << " " << light;  // six terms fit the same patches better
            // Twice the exposure, twice the XYZ: the roots keep every term of degree one.
            for (size_t i = 0; i < p.rgb.size(); ++i) {
                const glm::dvec3 once = applyColourCorrection(root, p.rgb[i]), twice = applyColourCorrection(root, 2.0 * p.rgb[i]);
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(twice[c], 2.0 * once[c], 1e-12);
            }
        }
}

TEST(ColourCorrection, TooFewOrDependentPatchesAreInputErrors) {
    const std::vector<glm::dvec3> grey{{0.1, 0.1, 0.1}, {0.2, 0.2, 0.2}, {0.4, 0.4, 0.4}, {0.8, 0.8, 0.8}};
    EXPECT_THROW(fitColourCorrection(CorrectionForm::Linear, grey, grey, Where{"patches"}), Error);
    EXPECT_THROW(fitColourCorrection(CorrectionForm::RootPolynomial2, grey, grey, Where{"patches"}), Error);
    EXPECT_THROW(parseCorrectionForm("polynomial", Where{"ccm"}), Error);
}
