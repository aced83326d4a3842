// The camera report's figures (issue 48, item 3) on inputs whose answers are known: developed
// colours that are the scene's own give ΔE00 0 whatever the exposure; a known Lab offset comes back;
// the photon transfer's variance is the temporal noise's, the fixed pattern cancelling.
#include "isp/camera_metrics.h"

#include "color/delta_e.h"
#include "color/lab.h"
#include "color/srgb.h"

#include <gtest/gtest.h>

#include <random>

using namespace metamer;

TEST(CameraMetrics, TheScenesOwnColoursDevelopedAtAnyExposureHaveNoError) {
    // The reference under illuminant A's white, adapted to D65 by Bradford, is what a perfect
    // processor shows: its linear sRGB, at half the exposure.
    const glm::dvec3 whiteA{1.09850, 1.0, 0.35585};
    const std::vector<glm::dvec3> reference{{0.4, 0.35, 0.1}, {0.2, 0.25, 0.12}, {0.9, 0.82, 0.3}};
    const glm::dmat3 cat = adaptationMatrix(Adaptation::Bradford, whiteA, kD65WhiteXyz);
    std::vector<glm::dvec3> developed;
    for (const glm::dvec3& xyz : reference) developed.push_back(0.5 * xyzToLinearSrgb(cat * xyz));
    const DevelopedColourError e = developedColourError(developed, reference, 100.0 * whiteA / 100.0, Adaptation::Bradford, 2, Where{"t"});
    EXPECT_NEAR(e.exposureScale, 2.0, 1e-9);
    for (double d : e.deltaE2000) EXPECT_LT(d, 1e-9);
    // The same with the reference on the render's relative scale (white Y = 100).
    std::vector<glm::dvec3> relative;
    for (const glm::dvec3& xyz : reference) relative.push_back(100.0 * xyz);
    for (double d : developedColourError(developed, relative, 100.0 * whiteA, Adaptation::Bradford, 2, Where{"t"}).deltaE2000)
        EXPECT_LT(d, 1e-9);
}

TEST(CameraMetrics, AKnownLabOffsetComesBackAsItsDeltaE2000) {
    const std::vector<glm::dvec3> reference{{0.3, 0.3, 0.3}, kD65WhiteXyz * 0.9};
    const glm::dvec3 lab = xyzToLab(reference[0], kD65WhiteXyz), shifted = lab + glm::dvec3(0.0, 3.0, -2.0);
    const std::vector<glm::dvec3> developed{xyzToLinearSrgb(labToXyz(shifted, kD65WhiteXyz)), xyzToLinearSrgb(reference[1])};
    const DevelopedColourError e = developedColourError(developed, reference, kD65WhiteXyz, Adaptation::None, 1, Where{"t"});
    EXPECT_NEAR(e.deltaE2000[0], deltaE2000(lab, shifted), 1e-9);
    EXPECT_LT(e.deltaE2000[1], 1e-9);
    EXPECT_THROW(developedColourError(developed, {reference[0]}, kD65WhiteXyz, Adaptation::None, 0, Where{"t"}), Error);
    EXPECT_THROW(developedColourError(developed, reference, kD65WhiteXyz, Adaptation::None, 2, Where{"t"}), Error);
}

TEST(CameraMetrics, ThePhotonTransfersVarianceIsTheTemporalNoisesAndTheFixedPatternCancels) {
    const int w = 200, h = 200;
    std::mt19937_64 rng(3);
    std::normal_distribution<double> temporal(0.0, 5.0), fixed(0.0, 40.0);
    std::vector<uint16_t> a(size_t(w) * h), b(a.size());
    for (size_t i = 0; i < a.size(); ++i) {
        const double pattern = 1000.0 + fixed(rng);  // the same in both frames
        a[i] = uint16_t(std::lround(pattern + temporal(rng)));
        b[i] = uint16_t(std::lround(pattern + temporal(rng)));
    }
    auto bayer = [](int x, int y) { return (x & 1) + (y & 1); };  // 0 R, 1 G, 2 B
    const PhotonTransferPoint g = photonTransfer(a.data(), b.data(), w, h, {0, 0, w, h}, 1, bayer, 100.0, Where{"t"});
    EXPECT_EQ(g.sites, size_t(w * h / 2));
    EXPECT_NEAR(g.mean_dn, 900.0, 1.0);
    EXPECT_NEAR(g.variance_dn2, 25.0 + 1.0 / 12.0, 0.8);  // σ² plus the rounding's 1/12
    EXPECT_NEAR(g.snr, g.mean_dn / std::sqrt(g.variance_dn2), 1e-9);
    try {
        photonTransfer(a.data(), b.data(), w, h, {190, 0, 20, 5}, 1, bayer, 0.0, Where{"f", "rect"});
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("not inside the 200×200 frame"), std::string::npos) << e.what();
    }
}
