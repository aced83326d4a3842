// ASTM E308 weighting factors (color/astm_e308.h) by known answers; against colour-science's
// sd_to_XYZ(method="ASTM E308") on the ColorChecker: tests/python/check_colorimetry_standards.py.
#include "color/astm_e308.h"

#include "color/cie_xyz.h"
#include "color/detector_registry.h"
#include "color/tonemap.h"
#include "spectral/resampling.h"
#include "support/capture_warnings.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

using namespace metamer;

namespace {

const SpectrumLibrary& library() {
    static const SpectrumLibrary lib;
    return lib;
}

const Grid kOneNm{kAstmE308StartNm, kAstmE308EndNm, 1.0};

std::vector<std::vector<double>> cmf1931() {
    const ColorMatchingFunctions c = loadCie1931(library(), kOneNm);
    return {c.x, c.y, c.z};
}

std::vector<double> d65() {
    ReferenceWhite w;
    w.terms = {{library().get("illuminants/D65", Where{}), 1.0}};
    return practiceRangeIlluminant(w);
}

// A quadratic reflectance, which the standard's Lagrange interpolation (quadratic at the ends,
// cubic inside; the 20 nm method's cubic midpoints and quadratic extrapolation) reproduces exactly.
double quadratic(double nm) {
    const double x = (nm - 570.0) / 100.0;
    return 0.42 + 0.21 * x - 0.13 * x * x;
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no error";
    return "";
}

}  // namespace

TEST(AstmE308, WeightsIntegrateAQuadraticReflectanceExactlyAt1Nm) {
    // Σ_b W_b·R(λb) on 10 and 20 nm grids spanning the practice range equals Σ_λ S·cmf·R at 1 nm.
    const auto cmf = cmf1931();
    const std::vector<double> s = d65();
    for (double step : {10.0, 20.0}) {
        const Grid grid{360, 780, step};
        const auto w = astmE308Weights(cmf, s, grid, Where{});
        for (size_t c = 0; c < 3; ++c) {
            double fine = 0, coarse = 0;
            for (int m = 0; m < kOneNm.bands(); ++m) fine += s[size_t(m)] * cmf[c][size_t(m)] * quadratic(kOneNm.wavelength(m));
            for (int b = 0; b < grid.bands(); ++b) coarse += w[c][size_t(b)] * quadratic(grid.wavelength(b));
            EXPECT_NEAR(coarse, fine, 1e-12 * fine) << step << " nm, channel " << c;
        }
        // Unit reflectance: the weights sum to Σ S·cmf at 1 nm (so k is the standard's).
        double sumY = 0, fineY = 0;
        for (double x : w[1]) sumY += x;
        for (int m = 0; m < kOneNm.bands(); ++m) fineY += s[size_t(m)] * cmf[1][size_t(m)];
        EXPECT_NEAR(sumY, fineY, 1e-12 * fineY);
    }
}

TEST(AstmE308, DataShorterThanThePracticeRangeFoldTheEndWeightsIn) {
    // 380–780 nm data: the weights of 360 and 370 nm go to the 380 nm band, as E308 prescribes —
    // the same as holding R(380) below 380 nm. Bands outside 360–780 nm weigh nothing.
    const auto cmf = cmf1931();
    const std::vector<double> s = d65();
    const auto full = astmE308Weights(cmf, s, Grid{360, 780, 10}, Where{});
    const auto part = astmE308Weights(cmf, s, Grid{300, 740, 10}, Where{});
    for (size_t c = 0; c < 3; ++c) {
        for (int b = 0; b < 6; ++b) EXPECT_EQ(part[c][size_t(b)], 0.0);  // 300–350 nm
        EXPECT_DOUBLE_EQ(part[c][6], full[c][0]);                       // 360 nm
        double tail = 0;
        for (size_t k = 38; k < full[c].size(); ++k) tail += full[c][k];  // 740–780 nm
        EXPECT_NEAR(part[c][44], tail, 1e-12 * tail);
    }
    // 1 and 5 nm data: the summation at the data's wavelengths over the practice range.
    const auto five = astmE308Weights(cmf, s, Grid{380, 780, 5}, Where{});
    EXPECT_DOUBLE_EQ(five[1][10], s[70] * cmf[1][70] * 5.0);  // 430 nm
}

TEST(AstmE308, AsADetectorTheWhiteRespondsAsTheWeightsSum) {
    // weight_b = W_b/E_b: a perfect white diffuser under the white (radiance E/π) responds ΣW/π.
    Grid grid{380, 780, 10};
    Detector d = makeDetector("cie1931", library(), grid, Integration::Riemann, Where{});
    ReferenceWhite white;
    white.terms = {{library().get("illuminants/A", Where{}), 0.02}};
    white.irradiance = resample(library().get("illuminants/A", Where{}), grid);
    for (double& v : white.irradiance) v *= 0.02;
    white.radiance = white.irradiance;
    for (double& v : white.radiance) v /= M_PI;
    applyAstmE308(d, library(), white, Where{"", "--integration"});
    EXPECT_EQ(d.integration, Integration::AstmE308);
    const auto w = astmE308Weights(cmf1931(), practiceRangeIlluminant(white), grid, Where{});
    glm::dvec3 r = detectorResponse3(d, white.radiance.data());
    double sumY = 0;
    for (double x : w[1]) sumY += x;
    EXPECT_NEAR(r.y, sumY / M_PI, 1e-12 * sumY);
}

TEST(AstmE308, RefusesWhatTheStandardDoesNotDefine) {
    const auto cmf = cmf1931();
    const std::vector<double> s = d65();
    const Where at{"", "--integration"};
    EXPECT_NE(errorOf([&] { astmE308Weights(cmf, s, Grid{380, 780, 2}, at); }).find("1, 5, 10 and 20 nm"), std::string::npos);
    EXPECT_NE(errorOf([&] { astmE308Weights(cmf, s, Grid{385, 775, 10}, at); }).find("multiples of 10 nm"), std::string::npos);
    EXPECT_NE(errorOf([&] { astmE308Weights(cmf, s, Grid{382, 777, 5}, at); }).find("multiples of 5 nm"), std::string::npos);
    EXPECT_NE(errorOf([&] { astmE308Weights(cmf, s, Grid{760, 780, 20}, at); }).find("at least 3 bands"), std::string::npos);
    EXPECT_NE(errorOf([&] { astmE308Weights(cmf, s, Grid{800, 900, 10}, at); }).find("--integration"), std::string::npos);
    Detector camera = makeDetector("camera:nikon_d5100", library(), Grid{380, 780, 10}, Integration::Riemann, Where{});
    ReferenceWhite white;
    white.terms = {{Spectrum::makeConstant(1.0), 1.0}};
    white.irradiance.assign(41, 1.0);
    EXPECT_NE(errorOf([&] { applyAstmE308(camera, library(), white, at); }).find("CIE observers"), std::string::npos);
}

TEST(AstmE308, AWhiteWithoutPowerWhereTheWeightIsNotZeroIsWarnedAbout) {
    // A light that is 0 at 400 nm but not at 391–409 nm: the 400 nm band cannot be weighted.
    Grid grid{360, 780, 10};
    Detector d = makeDetector("cie1931", library(), grid, Integration::Riemann, Where{});
    Spectrum notch;
    notch.wavelengths_nm = {300, 399, 400, 401, 830};
    notch.values = {1, 1, 0, 1, 1};
    notch.source = "notch";
    ReferenceWhite white;
    white.source = "notch";
    white.terms = {{notch, 1.0}};
    white.irradiance = resample(notch, grid);
    ASSERT_EQ(white.irradiance[4], 0.0);
    test::CaptureWarnings warnings;
    applyAstmE308(d, library(), white, Where{"", "--integration"});
    EXPECT_EQ(d.weights[1][4], 0.0);
    EXPECT_TRUE(test::CaptureWarnings::any("no power at 400 nm"));
}
