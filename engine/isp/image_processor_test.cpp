// The image processor (issue 48, item 2) on frames whose developed values can be written down: a
// perfect white at a known raw level develops to that level in sRGB, neutral; a Luther camera's
// fit leaves no ΔE00 under any light; the white balances agree on a neutral frame; the DNG's
// colour matrix maps the D65 white to the neutral; a saturated site is white; the input errors.
#include "isp/image_processor.h"

#include "color/camera_characterization.h"
#include "color/detector_registry.h"
#include "color/srgb.h"
#include "spectral/resampling.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace metamer;

namespace {

const SpectrumLibrary& library() {
    static const SpectrumLibrary lib;
    return lib;
}

const Grid kGrid{380, 780, 5};

std::vector<double> light(const std::string& name) { return resample(library().get("illuminants/" + name, Where{}), kGrid); }

Detector camera(const std::string& spec) { return makeDetector(spec, library(), kGrid, Integration::Riemann, Where{}); }

// Sensitivities M·(x̄, ȳ, z̄) for an invertible M with cross-talk: a camera that sees colour as
// the observer does.
Detector lutherCamera() {
    Detector d = camera("cie1931");
    const double M[3][3] = {{0.9, 0.3, -0.05}, {0.1, 0.8, 0.15}, {0.02, 0.1, 0.95}};
    const auto cmf = d.weights;
    for (int c = 0; c < 3; ++c)
        for (size_t b = 0; b < cmf[0].size(); ++b)
            d.weights[size_t(c)][b] = M[c][0] * cmf[0][b] + M[c][1] * cmf[1][b] + M[c][2] * cmf[2][b];
    return d;
}

// A Bayer frame (RGGB) whose every site of channel c reads black + level·n_c·(white − black).
std::vector<uint16_t> flatFrame(int w, int h, const glm::dvec3& n, double level, double black, double white) {
    std::vector<uint16_t> dn(size_t(w) * size_t(h));
    const int cfa[4] = {0, 1, 1, 2};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            dn[size_t(y) * size_t(w) + size_t(x)] =
                uint16_t(std::lround(black + level * n[cfa[(y & 1) * 2 + (x & 1)]] * (white - black)));
    return dn;
}

}  // namespace

TEST(ImageProcessor, ALutherCamerasFitLeavesNoErrorUnderAnyLightInEitherForm) {
    for (const char* name : {"D65", "A", "FL2"})
        for (CorrectionForm form : {CorrectionForm::Linear, CorrectionForm::RootPolynomial2}) {
            ProcessorSpec spec;
            spec.correction = form;
            spec.illuminant = std::string("illuminants/") + name;
            const ProcessorColour c = fitProcessorColour(lutherCamera(), light(name), kGrid, library(), spec, Where{"qe"});
            EXPECT_LT(c.rmsDeltaE2000, 1e-6) << name;
        }
}

TEST(ImageProcessor, APerfectWhiteAtAKnownRawLevelDevelopsToThatLevelNeutral) {
    // Under A the camera's neutral is far from equal: the white balance must bring it back.
    ProcessorSpec spec;
    spec.illuminant = "illuminants/A";
    const ProcessorColour c = fitProcessorColour(camera("camera:nikon_d5100"), light("A"), kGrid, library(), spec, Where{"qe"});
    EXPECT_DOUBLE_EQ(std::max({c.illuminantNeutral.x, c.illuminantNeutral.y, c.illuminantNeutral.z}), 1.0);
    EXPECT_LT(c.illuminantNeutral.z, 0.6);  // tungsten: little blue
    const double black = 512, white = 16383;
    for (DemosaicMethod method : {DemosaicMethod::Bilinear, DemosaicMethod::Malvar2004}) {
        spec.demosaic = method;
        const std::vector<uint16_t> dn = flatFrame(16, 12, c.illuminantNeutral, 0.4, black, white);
        const DevelopedImage d = develop(RawFrame{16, 12, dn.data(), black, white, {0, 1, 1, 2}}, spec, c, Where{"p"});
        // v_c = 0.4·n_c → balanced 0.4 → XYZ = 0.4·D65 white → sRGB 0.4 (to the DN's rounding).
        for (double v : d.linearRgb) EXPECT_NEAR(v, 0.4, 2e-4);
        // sRGB 0.4 encodes to 170.4 of 255.
        for (uint16_t e : encodeCounts(d, c.display)) EXPECT_EQ(e, 170);
    }
}

TEST(ImageProcessor, GreyWorldAndAPatchFindTheIlluminantsNeutralOnANeutralFrame) {
    ProcessorSpec spec;
    spec.illuminant = "illuminants/D50";
    const ProcessorColour c = fitProcessorColour(camera("camera:canon_eos_5d_mark_ii"), light("D50"), kGrid, library(), spec, Where{"qe"});
    const std::vector<uint16_t> dn = flatFrame(20, 20, c.illuminantNeutral, 0.3, 0, 4095);
    const RawFrame f{20, 20, dn.data(), 0, 4095, {0, 1, 1, 2}};
    for (WhiteBalance wb : {WhiteBalance::GreyWorld, WhiteBalance::Patch}) {
        spec.whiteBalance = wb;
        spec.patch = {4, 6, 5, 3};
        const glm::dvec3 n = whiteBalanceNeutral(f, spec, c, Where{"p"});
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(n[i], c.illuminantNeutral[i], 2e-3) << whiteBalanceName(wb);
    }
}

TEST(ImageProcessor, TheDngColourMatrixMapsTheD65WhiteToTheIlluminantsNeutral) {
    // What LibRaw relies on: ColorMatrix1·white_D65 is the neutral, and diag(n)⁻¹·ColorMatrix1 is the
    // inverse of the processor's 3 × 3 — so its camera → sRGB matrix is the processor's.
    for (const char* name : {"D65", "A"}) {
        ProcessorSpec spec;
        spec.illuminant = std::string("illuminants/") + name;
        const ProcessorColour c = fitProcessorColour(camera("camera:nikon_d5100"), light(name), kGrid, library(), spec, Where{"qe"});
        for (int r = 0; r < 3; ++r) {
            double mapped = 0.0;
            for (int k = 0; k < 3; ++k) mapped += c.dngColorMatrix[size_t(r * 3 + k)] * kD65WhiteXyz[k];
            EXPECT_NEAR(mapped, c.illuminantNeutral[r], 1e-9) << name;
        }
        // The 3 × 3 keeps the white: M·(1, 1, 1) = the D65 white.
        const glm::dvec3 w = c.linearToXyz * glm::dvec3(1.0);
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(w[i], kD65WhiteXyz[i], 1e-9) << name;
    }
}

TEST(ImageProcessor, ASaturatedSiteIsWhiteAndNegativeSignalIsBlack) {
    ProcessorSpec spec;
    spec.demosaic = DemosaicMethod::Bilinear;
    const ProcessorColour c = fitProcessorColour(camera("camera:nikon_d5100"), light("D65"), kGrid, library(), spec, Where{"qe"});
    std::vector<uint16_t> saturated(64, 4095), dark(64, 10);
    const DevelopedImage s = develop(RawFrame{8, 8, saturated.data(), 64, 4095, {0, 1, 1, 2}}, spec, c, Where{"p"});
    for (double v : s.linearRgb) EXPECT_NEAR(v, 1.0, 1e-9);  // every channel clipped at 1 after its gain
    const DevelopedImage d = develop(RawFrame{8, 8, dark.data(), 64, 4095, {0, 1, 1, 2}}, spec, c, Where{"p"});
    for (double v : d.linearRgb) EXPECT_EQ(v, 0.0);  // below black: 0, as a raw converter clips
}

TEST(ImageProcessor, APatchOutsideTheFrameOrAChannelWithNoSignalIsAnInputError) {
    ProcessorSpec spec;
    const ProcessorColour c = fitProcessorColour(camera("camera:nikon_d5100"), light("D65"), kGrid, library(), spec, Where{"qe"});
    std::vector<uint16_t> dn(100, 100);
    const RawFrame f{10, 10, dn.data(), 0, 4095, {0, 1, 1, 2}};
    spec.whiteBalance = WhiteBalance::Patch;
    spec.patch = {8, 8, 4, 4};
    try {
        whiteBalanceNeutral(f, spec, c, Where{"s.json", "processor"});
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("processor.patch"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("10×10"), std::string::npos) << e.what();
    }
    spec.whiteBalance = WhiteBalance::GreyWorld;
    std::vector<uint16_t> black(100, 0);
    EXPECT_THROW(whiteBalanceNeutral(RawFrame{10, 10, black.data(), 0, 4095, {0, 1, 1, 2}}, spec, c, Where{"p"}), Error);
    EXPECT_THROW(parseWhiteBalance("gray world", Where{"p"}), Error);
    // Two equal channels: no colour matrix.
    Detector twins = camera("camera:nikon_d5100");
    twins.weights[2] = twins.weights[1];
    EXPECT_THROW(fitProcessorColour(twins, light("D65"), kGrid, library(), ProcessorSpec{}, Where{"qe"}), Error);
}

TEST(ImageProcessor, ACrtDisplayGetsTheWhiteItShowsAndTheRendersEncodingWhileTheDngStaysD65s) {
    // The output for the CRT model of color/display_model: the illuminant's white adapts to the
    // CRT's white, a perfect diffuser at 0.4 of the white level is 0.4 × that white in XYZ, and its
    // counts are what the render's encoder writes for it; the DNG's matrix still maps D65 to the
    // neutral (a raw converter's XYZ are D65's).
    ProcessorSpec spec;
    spec.illuminant = "illuminants/A";
    spec.display = "crt";
    spec.bits = 16;
    const ProcessorColour c = fitProcessorColour(camera("camera:nikon_d5100"), light("A"), kGrid, library(), spec, Where{"qe"});
    ASSERT_EQ(c.display.kind, DisplayKind::CrtGog);
    const glm::dvec3 crtWhite = c.display.whiteXyz / c.display.whiteXyz.y;
    const std::vector<uint16_t> dn = flatFrame(8, 8, c.illuminantNeutral, 0.4, 0, 16383);
    const DevelopedImage d = develop(RawFrame{8, 8, dn.data(), 0, 16383, {0, 1, 1, 2}}, spec, c, Where{"p"});
    for (size_t i = 0; i < d.xyz.size(); ++i) EXPECT_NEAR(d.xyz[i], 0.4 * crtWhite[int(i % 3)], 2e-4);
    const glm::dvec3 want = encodeXyz(c.display, 0.4 * crtWhite).counts;
    const std::vector<uint16_t> counts = encodeCounts(d, c.display);
    for (size_t i = 0; i < counts.size(); ++i) EXPECT_NEAR(counts[i], want[int(i % 3)], 2.0);  // 16 bits: the DN's rounding
    for (int r = 0; r < 3; ++r) {
        double mapped = 0.0;
        for (int k = 0; k < 3; ++k) mapped += c.dngColorMatrix[size_t(r * 3 + k)] * kD65WhiteXyz[k];
        EXPECT_NEAR(mapped, c.illuminantNeutral[r], 1e-9);
    }
    EXPECT_THROW(parseDisplay("lcd", 8, Where{"display"}), Error);
}
