// The statistics of compare/compare.h on cubes whose differences are known exactly.
#include "compare/compare.h"

#include "compare/compare_test_util.h"
#include "compare/tolerance.h"
#include "io/image_file.h"
#include "io/spectral_exr.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

using namespace metamer;
using metamer::test::smoothCube;
namespace fs = std::filesystem;

namespace {

const Grid kGrid{400, 700, 10};  // 31 bands

// Every criterion at 0: only exact equality passes.
Tolerance zeroTolerance() {
    Tolerance t;
    t.maxAbs = t.maxRel = t.rmseRelative = t.spectralAngleMaxDeg = t.fractionOverThreshold = t.deltaE2000P95 =
        t.deltaE2000Max = 0.0;
    return t;
}

ExitCode codeOf(const std::function<void()>& f, std::string* message = nullptr) {
    try {
        f();
    } catch (const Error& e) {
        if (message) *message = e.what();
        return e.code();
    }
    return ExitCode::Ok;
}

class CompareFiles : public metamer::test::ScratchDir {};

}  // namespace

TEST(CompareStats, IdenticalCubesGiveZerosAndPassAnyTolerance) {
    ImageData b = fromCube(smoothCube(6, 4, kGrid));
    CompareOptions o;
    o.display = TonemapSettings{};
    CompareStats s = compareImages(b, b, o);
    EXPECT_EQ(s.width, 6);
    EXPECT_EQ(s.height, 4);
    EXPECT_EQ(s.channels, 31u);
    EXPECT_EQ(s.maxAbs, 0.0);
    EXPECT_EQ(s.maxRel, 0.0);
    EXPECT_EQ(s.rmse, 0.0);
    EXPECT_EQ(s.rmseRelative, 0.0);
    EXPECT_EQ(s.spectralAngleMaxDeg, 0.0);
    EXPECT_EQ(s.spectralAngleMeanDeg, 0.0);
    EXPECT_EQ(s.fractionOverThreshold, 0.0);
    ASSERT_TRUE(s.deltaE2000Mean && s.deltaE2000P95 && s.deltaE2000Max);
    EXPECT_EQ(*s.deltaE2000Max, 0.0);
    EXPECT_EQ(s.worstChannel, -1);
    for (float e : s.pixelError) EXPECT_EQ(e, 0.0f);
    Verdict v = judge(s, zeroTolerance());
    EXPECT_TRUE(v.pass);
    EXPECT_TRUE(v.failures.empty());
}

TEST(CompareStats, HalfPercentOnOneBandShowsInThatBandOnlyAndFailsMaxRel) {
    SpectralCube cb = smoothCube(5, 3, kGrid), ca = cb;
    const int band = 12;  // 520 nm
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) ca.at(x, y, band) = float(double(cb.at(x, y, band)) * 1.005);
    CompareStats s = compareImages(fromCube(ca), fromCube(cb), {});
    EXPECT_NEAR(s.maxRel, 0.005, 1e-6);
    ASSERT_EQ(s.perChannel.size(), 31u);
    for (int c = 0; c < 31; ++c) {
        if (c == band) EXPECT_NEAR(s.perChannel[c].maxRel, 0.005, 1e-6) << s.perChannel[c].name;
        else EXPECT_EQ(s.perChannel[c].maxRel, 0.0) << s.perChannel[c].name;
    }
    EXPECT_EQ(s.perChannel[band].name, "S0.520,000000nm");
    EXPECT_EQ(s.worstChannel, band);
    // Every pixel has one band 0.5% off: all of them are over the default 1e-3.
    EXPECT_EQ(s.fractionOverThreshold, 1.0);

    Tolerance t;
    t.maxRel = 1e-3;
    Verdict v = judge(s, t);
    EXPECT_FALSE(v.pass);
    ASSERT_EQ(v.failures.size(), 1u);
    EXPECT_EQ(v.failures[0].rfind("max_rel 5e-03 > 1e-03", 0), 0u) << v.failures[0];
    t.maxRel = 6e-3;
    EXPECT_TRUE(judge(s, t).pass);
}

TEST(CompareStats, SpectralAngleIsZeroForAScaledSpectrumAndNinetyForOrthogonalOnes) {
    SpectralCube cb = smoothCube(4, 4, kGrid), ca = cb;
    for (float& v : ca.data) v *= 3.0f;
    CompareStats scaled = compareImages(fromCube(ca), fromCube(cb), {});
    EXPECT_NEAR(scaled.spectralAngleMaxDeg, 0.0, 1e-5);
    EXPECT_NEAR(scaled.maxRel, 2.0, 1e-6);  // yet every value is off by 200%

    // B has light only below 550 nm, A only above: orthogonal in every pixel.
    SpectralCube ob(3, 2, kGrid), oa(3, 2, kGrid);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x)
            for (int b = 0; b < kGrid.bands(); ++b)
                (kGrid.wavelength(b) < 550 ? ob : oa).at(x, y, b) = 1.0f + 0.1f * float(b + x);
    CompareStats orthogonal = compareImages(fromCube(oa), fromCube(ob), {});
    EXPECT_NEAR(orthogonal.spectralAngleMaxDeg, 90.0, 1e-9);
    EXPECT_NEAR(orthogonal.spectralAngleMeanDeg, 90.0, 1e-9);

    // A black pixel has no direction: left out of the angle statistics.
    SpectralCube black(3, 2, kGrid);
    CompareStats none = compareImages(fromCube(black), fromCube(ob), {});
    EXPECT_EQ(none.spectralAngleMaxDeg, 0.0);
}

TEST(CompareStats, RmseOfAConstantOffset) {
    SpectralCube cb = smoothCube(4, 3, kGrid), ca = cb;
    const double offset = 0.25;
    for (float& v : ca.data) v = float(double(v) + offset);
    CompareStats s = compareImages(fromCube(ca), fromCube(cb), {});
    double meanB = 0.0;
    for (float v : cb.data) meanB += std::fabs(v);
    meanB /= double(cb.data.size());
    EXPECT_NEAR(s.rmse, offset, 1e-7);
    EXPECT_NEAR(s.maxAbs, offset, 1e-7);
    EXPECT_NEAR(s.rmseRelative, offset / meanB, 1e-6 * offset / meanB);
    for (const auto& c : s.perChannel) EXPECT_NEAR(c.rmse, offset, 1e-7) << c.name;
}

TEST(CompareStats, FractionOverThresholdCountsPixels) {
    SpectralCube cb = smoothCube(4, 3, kGrid), ca = cb;
    // Three of twelve pixels 1% off in one band; one more only 0.05% off (under 1e-3).
    for (auto [x, y] : {std::pair{0, 0}, {3, 1}, {2, 2}}) ca.at(x, y, 5) *= 1.01f;
    ca.at(1, 1, 7) *= 1.0005f;
    CompareOptions o;
    CompareStats s = compareImages(fromCube(ca), fromCube(cb), o);
    EXPECT_EQ(s.pixelsOverThreshold, 3u);
    EXPECT_DOUBLE_EQ(s.fractionOverThreshold, 0.25);
    EXPECT_NEAR(s.pixelError[0], 0.01, 1e-6);
    EXPECT_NEAR(s.pixelError[1 * 4 + 3], 0.01, 1e-6);
    EXPECT_NEAR(s.pixelError[1 * 4 + 1], 0.0005, 1e-6);
    EXPECT_EQ(s.pixelError[1], 0.0f);
    o.pixelThreshold = 1e-4;  // now the fourth counts too
    EXPECT_DOUBLE_EQ(compareImages(fromCube(ca), fromCube(cb), o).fractionOverThreshold, 4.0 / 12.0);
}

TEST(CompareStats, RelativeFloorKeepsNearBlackValuesFromDominating) {
    SpectralCube cb(2, 1, Grid{500, 510, 10}), ca(2, 1, Grid{500, 510, 10});
    cb.at(0, 0, 0) = 1.0f;   // the channel's max |B|
    cb.at(1, 0, 0) = 1e-9f;  // near black
    ca = cb;
    ca.at(1, 0, 0) = 1e-6f;  // 1000× the reference, but 1e-6 of the channel's range
    CompareOptions o;        // floor 1e-4 × 1
    CompareStats s = compareImages(fromCube(ca), fromCube(cb), o);
    EXPECT_NEAR(s.maxRel, (1e-6 - 1e-9) / 1e-4, 1e-8);
    o.relativeFloor = 0.0;  // plain |a − b| / |b|
    EXPECT_NEAR(compareImages(fromCube(ca), fromCube(cb), o).maxRel, 999.0, 1e-3);
}

TEST(CompareStats, NonFiniteValuesInOneImageOnlyAreCountedAndFailTheTolerance) {
    SpectralCube cb = smoothCube(3, 2, kGrid), ca = cb;
    ca.at(1, 1, 3) = std::numeric_limits<float>::quiet_NaN();
    CompareStats s = compareImages(fromCube(ca), fromCube(cb), {});
    EXPECT_EQ(s.nonFiniteMismatches, 1u);
    EXPECT_TRUE(std::isinf(s.maxRel));
    EXPECT_TRUE(std::isinf(s.pixelError[1 * 3 + 1]));
    Tolerance t;
    t.spectralAngleMaxDeg = 1.0;  // the NaN pixel has no angle, yet the verdict must fail
    Verdict v = judge(s, t);
    EXPECT_FALSE(v.pass);
    ASSERT_EQ(v.failures.size(), 1u);
    EXPECT_NE(v.failures[0].find("NaN or infinite"), std::string::npos) << v.failures[0];
    // NaN at the same place in both is no difference.
    cb.at(1, 1, 3) = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(compareImages(fromCube(ca), fromCube(cb), {}).nonFiniteMismatches, 0u);
}

TEST(CompareStats, DeltaE2000IsZeroAgainstItselfAndPositiveForAChangedColour) {
    SpectralCube cb = smoothCube(4, 4, Grid{380, 730, 5}), ca = cb;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            for (int b = 0; b < cb.bands(); ++b)
                if (cb.grid.wavelength(b) > 600) ca.at(x, y, b) *= 1.3f;  // redder
    CompareOptions o;
    o.display = TonemapSettings{};
    CompareStats self = compareImages(fromCube(cb), fromCube(cb), o);
    ASSERT_TRUE(self.deltaE2000Max);
    EXPECT_EQ(*self.deltaE2000Max, 0.0);
    CompareStats changed = compareImages(fromCube(ca), fromCube(cb), o);
    ASSERT_TRUE(changed.deltaE2000Mean && changed.deltaE2000P95 && changed.deltaE2000Max);
    EXPECT_GT(*changed.deltaE2000Mean, 1.0);
    EXPECT_LE(*changed.deltaE2000Mean, *changed.deltaE2000Max);
    EXPECT_LE(*changed.deltaE2000P95, *changed.deltaE2000Max);
    EXPECT_NE(changed.deltaE2000Setup.find("cie1931"), std::string::npos) << changed.deltaE2000Setup;
    EXPECT_NE(changed.deltaE2000Setup.find("99th-percentile"), std::string::npos) << changed.deltaE2000Setup;
    // A brighter copy of the whole cube is a lighter colour, not the same one: the white is B's.
    SpectralCube brighter = cb;
    for (float& v : brighter.data) v *= 1.1f;
    EXPECT_GT(*compareImages(fromCube(brighter), fromCube(cb), o).deltaE2000Mean, 0.5);

    // The other detectors go through the same plan.
    for (const char* detector : {"cie1964", "camera:nikon_d5100", "film:reversal"}) {
        o.display->detector = detector;
        CompareStats s = compareImages(fromCube(ca), fromCube(cb), o);
        ASSERT_TRUE(s.deltaE2000Mean) << detector;
        EXPECT_GT(*s.deltaE2000Mean, 0.5) << detector;
        EXPECT_EQ(*compareImages(fromCube(cb), fromCube(cb), o).deltaE2000Max, 0.0) << detector;
    }
}

TEST(CompareStats, DeltaE2000NeedsSpectralCubesAndVisibleLight) {
    CompareOptions o;
    o.display = TonemapSettings{};
    ImageData rgb;
    rgb.width = 1;
    rgb.height = 1;
    rgb.channels = {"R", "G", "B"};
    rgb.data = {1, 2, 3};
    std::string message;
    EXPECT_EQ(codeOf([&] { compareImages(rgb, rgb, o); }, &message), ExitCode::BadInput);
    EXPECT_NE(message.find("spectral"), std::string::npos) << message;
    SpectralCube infrared = smoothCube(2, 2, Grid{900, 1000, 10});
    EXPECT_EQ(codeOf([&] { compareImages(fromCube(infrared), fromCube(infrared), o); }, &message), ExitCode::BadInput);
    EXPECT_NE(message.find("900:1000:10"), std::string::npos) << message;
}

TEST(CompareStats, MismatchedSizesChannelsAndGridsAreInputErrorsNamingBoth) {
    ImageData b = fromCube(smoothCube(4, 3, kGrid));
    b.source = "golden/ref.exr";
    ImageData a = fromCube(smoothCube(3, 3, kGrid));
    a.source = "out/new.exr";
    std::string message;
    EXPECT_EQ(codeOf([&] { compareImages(a, b, {}); }, &message), ExitCode::BadInput);
    EXPECT_NE(message.find("out/new.exr"), std::string::npos) << message;
    EXPECT_NE(message.find("golden/ref.exr"), std::string::npos) << message;
    EXPECT_NE(message.find("3×3"), std::string::npos) << message;
    EXPECT_NE(message.find("4×3"), std::string::npos) << message;

    a = fromCube(smoothCube(4, 3, Grid{400, 700, 5}));
    a.source = "out/new.exr";
    EXPECT_EQ(codeOf([&] { compareImages(a, b, {}); }, &message), ExitCode::BadInput);
    EXPECT_NE(message.find("400:700:5"), std::string::npos) << message;
    EXPECT_NE(message.find("400:700:10"), std::string::npos) << message;
    EXPECT_NE(message.find("golden/ref.exr"), std::string::npos) << message;
    EXPECT_NE(message.find("--resample"), std::string::npos) << message;

    ImageData rgb;
    rgb.width = 4;
    rgb.height = 3;
    rgb.channels = {"R", "G", "B"};
    rgb.data.assign(4 * 3 * 3, 0.5f);
    EXPECT_EQ(codeOf([&] { compareImages(rgb, b, {}); }, &message), ExitCode::BadInput);
    EXPECT_NE(message.find("not spectral"), std::string::npos) << message;

    ImageData xyz = rgb;
    xyz.channels = {"X", "Y", "Z"};
    EXPECT_EQ(codeOf([&] { compareImages(rgb, xyz, {}); }, &message), ExitCode::BadInput);
    EXPECT_NE(message.find("missing: X,Y,Z"), std::string::npos) << message;

    // Reflectance against radiance on the same grid.
    ImageData t = b;
    for (auto& c : t.channels) c = "T" + c.substr(2);
    EXPECT_EQ(codeOf([&] { compareImages(t, b, {}); }, &message), ExitCode::BadInput);
    EXPECT_NE(message.find("reflectance"), std::string::npos) << message;
}

TEST(CompareStats, PlainImageChannelsAreMatchedByName) {
    ImageData b, a;
    b.width = a.width = 2;
    b.height = a.height = 1;
    b.channels = {"X", "Y", "Z"};
    b.data = {1, 2, 3, 4, 5, 6};
    a.channels = {"Z", "X", "Y"};
    a.data = {3, 1, 2, 6, 4, 5.5f};
    CompareStats s = compareImages(a, b, {});
    EXPECT_EQ(s.perChannel[0].maxAbs, 0.0);
    EXPECT_EQ(s.perChannel[1].maxAbs, 0.5);
    EXPECT_EQ(s.perChannel[1].name, "Y");
    EXPECT_EQ(s.perChannel[2].maxAbs, 0.0);
}

TEST(CompareStats, ResampleMakesA5nmCubeComparableTo10nm) {
    // A spectrum linear in λ is its own band average, and band averaging the piecewise-linear
    // 5 nm data onto 10 nm bands inside the data reproduces it exactly.
    auto linear = [](const Grid& g) {
        SpectralCube c(3, 2, g);
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 3; ++x)
                for (int b = 0; b < g.bands(); ++b) c.at(x, y, b) = float(0.1 + 0.001 * (g.wavelength(b) - 400) * (1 + x + y));
        return c;
    };
    ImageData a = fromCube(linear(Grid{400, 700, 5})), b = fromCube(linear(Grid{410, 690, 10}));
    EXPECT_EQ(codeOf([&] { compareImages(a, b, {}); }), ExitCode::BadInput);
    CompareOptions o;
    o.resample = true;
    CompareStats s = compareImages(a, b, o);
    EXPECT_EQ(s.channels, size_t(b.grid->bands()));
    EXPECT_EQ(s.resampledFrom, "400:700:5");
    EXPECT_LT(s.maxRel, 1e-6);
    EXPECT_EQ(s.perChannel.front().name, "S0.410,000000nm");

    // A smooth but curved spectrum on the full range: close, not exact.
    SpectralCube fine = smoothCube(3, 2, Grid{400, 700, 5}), coarse = smoothCube(3, 2, Grid{400, 700, 10});
    CompareStats curved = compareImages(fromCube(fine), fromCube(coarse), o);
    EXPECT_LT(curved.rmseRelative, 2e-2);
    EXPECT_LT(curved.spectralAngleMaxDeg, 2.0);
}

TEST_F(CompareFiles, ReadsSpectralExrsAndPlainImages) {
    SpectralCube cube = smoothCube(5, 4, kGrid);
    writeSpectralExr(dir / "cube.exr", cube);
    ImageData d = readComparable(dir / "cube.exr");
    EXPECT_EQ(d.width, 5);
    EXPECT_EQ(d.height, 4);
    ASSERT_TRUE(d.grid);
    EXPECT_EQ(*d.grid, kGrid);
    EXPECT_EQ(d.channels.front(), "S0.400,000000nm");
    EXPECT_EQ(d.data, cube.data);
    EXPECT_EQ(d.source, (dir / "cube.exr").string());
    EXPECT_EQ(compareImages(d, fromCube(cube), {}).maxAbs, 0.0);

    // A PNG reads as counts, not 0..1.
    ImageFile png{2, 1, {"R", "G", "B"}, {}};
    writeImage(dir / "img.png", png, std::vector<uint16_t>{0, 128, 255, 10, 20, 30}, 8);
    ImageData p = readComparable(dir / "img.png");
    EXPECT_FALSE(p.grid);
    EXPECT_EQ(p.channels, (std::vector<std::string>{"R", "G", "B"}));
    EXPECT_EQ(p.data, (std::vector<float>{0, 128, 255, 10, 20, 30}));

    // A float EXR without spectral channels keeps its channels.
    ImageFile xyz{1, 1, {"X", "Y", "Z"}, {}};
    writeImage(dir / "xyz.exr", xyz, std::vector<float>{0.25f, 0.5f, 0.75f});
    ImageData x = readComparable(dir / "xyz.exr");
    EXPECT_FALSE(x.grid);
    EXPECT_EQ(x.data, (std::vector<float>{0.25f, 0.5f, 0.75f}));

    // Metamer's XYZ EXR (OpenEXR's convention: X, Y, Z in R, G, B with the XYZ chromaticities)
    // reads as X, Y, Z, so it compares with a file of the earlier X, Y, Z layout.
    ImageFile convention{1, 1, {"R", "G", "B"}, {}};
    convention.chromaticities = xyzChromaticities();
    writeImage(dir / "new.xyz.exr", convention, std::vector<float>{0.25f, 0.5f, 0.75f});
    ImageData n = readComparable(dir / "new.xyz.exr");
    // (In the file's order, which OpenEXR sorts by name: B, G, R.)
    EXPECT_EQ(n.channels, (std::vector<std::string>{"Z", "Y", "X"}));
    EXPECT_EQ(n.data, (std::vector<float>{0.75f, 0.5f, 0.25f}));
    EXPECT_EQ(compareImages(n, x, {}).maxAbs, 0.0);
    // Plain RGB stays RGB.
    writeImage(dir / "rgb.exr", ImageFile{1, 1, {"R", "G", "B"}, {}}, std::vector<float>{0.25f, 0.5f, 0.75f});
    EXPECT_EQ(readComparable(dir / "rgb.exr").channels, (std::vector<std::string>{"B", "G", "R"}));
}

TEST_F(CompareFiles, UnreadableFilesAreInputErrorsNamingThem) {
    std::string message;
    EXPECT_EQ(codeOf([&] { readComparable(dir / "missing.exr"); }, &message), ExitCode::BadInput);
    EXPECT_NE(message.find("missing.exr"), std::string::npos) << message;
    fs::path junk = write("junk.exr", "not an image");
    EXPECT_EQ(codeOf([&] { readComparable(junk); }, &message), ExitCode::BadInput);
    EXPECT_NE(message.find("junk.exr"), std::string::npos) << message;
}

TEST_F(CompareFiles, StatsJsonIsWrittenWithEveryStatistic) {
    SpectralCube cb = smoothCube(3, 2, kGrid), ca = cb;
    ca.at(0, 0, 0) *= 1.01f;
    ca.at(1, 0, 0) = std::numeric_limits<float>::infinity();
    CompareStats s = compareImages(fromCube(ca), fromCube(cb), {});
    writeStatsJson(dir / "stats.json", s, {{"a", "A.exr"}});
    std::ifstream in(dir / "stats.json");
    nlohmann::json j = nlohmann::json::parse(in);
    for (const char* key : {"max_abs", "max_rel", "rmse", "rmse_relative", "spectral_angle_max_deg",
                            "spectral_angle_mean_deg", "fraction_over_threshold", "per_channel", "grid"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["max_rel"], "inf");
    EXPECT_EQ(j["non_finite_mismatches"], 1);
    EXPECT_EQ(j["a"], "A.exr");
    EXPECT_EQ(j["per_channel"].size(), 31u);
    EXPECT_EQ(j["grid"], "400:700:10");
    // Only the file itself: the temporary is gone.
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST_F(CompareFiles, MaskedPixelsAreLeftOutOfEveryStatistic) {
    SpectralCube cb = smoothCube(4, 2, kGrid), ca = cb;
    for (int b = 0; b < kGrid.bands(); ++b) ca.at(2, 1, b) *= 2.0f;  // a silhouette pixel, far off
    ca.at(0, 0, 3) *= 1.01f;                                          // a real 1% error elsewhere
    ImageFile edges{4, 2, {"Y"}, {}};
    writeImage(dir / "edges.png", edges, std::vector<uint16_t>{0, 0, 0, 0, 0, 0, 255, 0}, 8);
    CompareOptions o;
    o.mask = readMask(dir / "edges.png", 4, 2);
    o.display = TonemapSettings{};
    CompareStats s = compareImages(fromCube(ca), fromCube(cb), o);
    EXPECT_EQ(s.maskedPixels, 1u);
    EXPECT_NEAR(s.maxRel, 0.01, 1e-6);
    EXPECT_EQ(s.worstX, 0);
    EXPECT_EQ(s.pixelsOverThreshold, 1u);
    EXPECT_DOUBLE_EQ(s.fractionOverThreshold, 1.0 / 7.0);
    EXPECT_EQ(s.pixelError[6], 0.0f);
    EXPECT_LT(*s.deltaE2000Max, 1.0);  // the doubled pixel would be far more
    CompareStats unmasked = compareImages(fromCube(ca), fromCube(cb), {});
    EXPECT_NEAR(unmasked.maxRel, 1.0, 1e-6);

    std::string message;
    EXPECT_EQ(codeOf([&] { readMask(dir / "edges.png", 5, 2); }, &message), ExitCode::BadInput);
    EXPECT_NE(message.find("edges.png: the mask is 4×2 but the images are 5×2"), std::string::npos) << message;
}
