// Display models: sRGB white and grey, the out-of-gamut rule, the GOG round trip over a grid of
// counts at 8 and 16 bits, the GOG cutoff, the CRT's primaries against colour-science
// (tests/data/color/colorimetry/crt_primaries.txt), and parseDisplay's errors.
#include "color/display_model.h"

#include "color/srgb.h"

#include <gtest/gtest.h>

#include <glm/matrix.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

using namespace metamer;

namespace {

DisplayModel display(const std::string& name, int bits = 8) { return parseDisplay(name, bits, Where{}); }

void expectCounts(const EncodeResult& r, glm::dvec3 counts, bool clipped, const std::string& what) {
    EXPECT_EQ(r.counts.x, counts.x) << what;
    EXPECT_EQ(r.counts.y, counts.y) << what;
    EXPECT_EQ(r.counts.z, counts.z) << what;
    EXPECT_EQ(r.clipped, clipped) << what;
}

void expectXyz(glm::dvec3 actual, glm::dvec3 expected, double tolerance, const std::string& what) {
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(actual[i], expected[i], tolerance) << what << " [" << i << "]";
}

std::string str(glm::dvec3 v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

// decodeCounts then encodeXyz must give back every count triple of a grid, unclipped; counts at or
// below a channel's GOG cutoff all show black and come back as 0.
void expectRoundTrip(const DisplayModel& d, double step) {
    const double n = maxCount(d);
    const glm::dvec3 cutoff = cutoffCounts(d);
    int checked = 0;
    for (double r = 0; r <= n; r += step)
        for (double g = 0; g <= n; g += step)
            for (double b = 0; b <= n; b += step) {
                glm::dvec3 counts(r, g, b);
                glm::dvec3 expected = counts;
                for (int i = 0; i < 3; ++i)
                    if (counts[i] <= cutoff[i]) expected[i] = 0.0;
                EncodeResult back = encodeXyz(d, decodeCounts(d, counts));
                if (back.counts != expected || back.clipped) {
                    ADD_FAILURE() << d.name << " " << d.bits << " bits: " << str(counts) << " came back as "
                                  << str(back.counts) << (back.clipped ? " clipped" : "");
                    return;
                }
                ++checked;
            }
    EXPECT_EQ(checked, 16 * 16 * 16);
}

}  // namespace

TEST(Display, SrgbWhiteIsFullCounts) {
    for (int bits : {8, 16}) {
        DisplayModel d = display("srgb", bits);
        const double n = bits == 8 ? 255.0 : 65535.0;
        EXPECT_EQ(maxCount(d), n);
        expectCounts(encodeXyz(d, kD65WhiteXyz), glm::dvec3(n), false, "D65 white");
        expectXyz(decodeCounts(d, glm::dvec3(n)), kD65WhiteXyz, 1e-12, "full counts");
        expectXyz(d.whiteXyz, kD65WhiteXyz, 0.0, "whiteXyz");
        expectXyz(d.rgbToXyz * glm::dvec3(1.0), kD65WhiteXyz, 1e-12, "rgbToXyz white");
        expectCounts(encodeXyz(d, glm::dvec3(0.0)), glm::dvec3(0.0), false, "black");
    }
}

TEST(Display, SrgbMidGrey) {
    DisplayModel d = display("srgb");
    // 18% grey: sRGB encoding 1.055·0.18^(1/2.4) − 0.055 = 0.46135, × 255 = 117.6 → 118.
    expectCounts(encodeXyz(d, 0.18 * kD65WhiteXyz), glm::dvec3(118.0), false, "18% grey");
    // Count 128 decodes to ((128/255 + 0.055)/1.055)^2.4 = 0.2158605 of the white.
    glm::dvec3 xyz = decodeCounts(d, glm::dvec3(128.0));
    expectXyz(xyz, 0.21586050011389926 * kD65WhiteXyz, 1e-12, "count 128");
    expectCounts(encodeXyz(d, xyz), glm::dvec3(128.0), false, "count 128 back");
}

TEST(Display, OutOfRangeIsClippedAndFlagged) {
    DisplayModel d = display("srgb");
    // Too bright: twice the white clips every channel at 1.
    expectCounts(encodeXyz(d, 2.0 * kD65WhiteXyz), glm::dvec3(255.0), true, "twice white");
    // Negative: below black clips to 0.
    expectCounts(encodeXyz(d, glm::dvec3(-0.01)), glm::dvec3(0.0), true, "negative");
    // Too saturated: a spectral-locus green (520 nm, x 0.0743, y 0.8338) at Y 0.3 has negative red
    // and blue in sRGB; green alone stays inside [0, 1].
    const double x = 0.0743, y = 0.8338, Y = 0.3;
    glm::dvec3 green(x / y * Y, Y, (1.0 - x - y) / y * Y);
    glm::dvec3 linear = xyzToLinearSrgb(green);
    ASSERT_LT(linear.r, 0.0);
    ASSERT_LT(linear.b, 0.0);
    ASSERT_GT(linear.g, 0.0);
    ASSERT_LT(linear.g, 1.0);
    EncodeResult r = encodeXyz(d, green);
    EXPECT_TRUE(r.clipped);
    EXPECT_EQ(r.counts.x, 0.0);
    EXPECT_EQ(r.counts.z, 0.0);
    EXPECT_EQ(r.counts.y, std::round(srgbEncode(linear.g) * 255.0));
    // Just inside the tolerance is not flagged: 1 + 1e-7 of the white.
    expectCounts(encodeXyz(d, (1.0 + 1e-7) * kD65WhiteXyz), glm::dvec3(255.0), false, "white + 1e-7");
    // Not a number: flagged and shown as black.
    EncodeResult nan = encodeXyz(d, glm::dvec3(std::nan(""), 0.5, 0.5));
    EXPECT_TRUE(nan.clipped);
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(nan.counts[c]));
}

TEST(Display, SrgbRoundTripsEveryGridCount) {
    expectRoundTrip(display("srgb", 8), 17.0);
    expectRoundTrip(display("srgb", 16), 4369.0);
}

TEST(Display, GogRoundTripsEveryGridCount) {
    expectRoundTrip(display("crt", 8), 17.0);
    expectRoundTrip(display("crt", 16), 4369.0);
}

TEST(Display, GogRoundTripsWithUnequalChannels) {
    // Per-channel parameters really are per channel (and a non-integer cutoff).
    DisplayModel d = display("crt");
    d.gain = glm::dvec3(1.05, 1.0, 1.1);
    d.offset = glm::dvec3(-0.05, 0.0, -0.1);
    d.gamma = glm::dvec3(2.2, 2.5, 1.8);
    // Cutoffs c₀ = −offset·n/gain, rounded: red 0.05/1.05·255 = 12.1, green 0 (offset 0: only
    // count 0 is black), blue 23.2; at 16 bits red 3120.7 and blue 5957.7 round up, so the first
    // count above the cutoff (less than half a count of drive) is written as 0 too.
    EXPECT_EQ(cutoffCounts(d), glm::dvec3(12.0, 0.0, 23.0));
    expectRoundTrip(d, 17.0);
    DisplayModel d16 = d;
    d16.bits = 16;
    EXPECT_EQ(cutoffCounts(d16), glm::dvec3(3121.0, 0.0, 5958.0));
    expectRoundTrip(d16, 4369.0);
    for (double c : {0.0, 1.0, 3120.0, 3121.0, 3122.0, 5957.0, 5958.0, 5959.0}) {
        glm::dvec3 back = encodeXyz(d16, decodeCounts(d16, glm::dvec3(c))).counts;
        EXPECT_EQ(back.x, c <= 3121.0 ? 0.0 : c) << c;
        EXPECT_EQ(back.y, c) << c;
        EXPECT_EQ(back.z, c <= 5958.0 ? 0.0 : c) << c;
    }
    // A positive offset: no count is black, count 0 decodes to offset^γ and comes back as 0.
    DisplayModel lifted = d;
    lifted.offset = glm::dvec3(0.03);
    lifted.gain = glm::dvec3(0.97);
    EXPECT_EQ(cutoffCounts(lifted), glm::dvec3(-1.0));
    expectRoundTrip(lifted, 17.0);
    for (double c = 0; c <= 255; ++c) {
        glm::dvec3 counts(c, c, c);
        glm::dvec3 back = encodeXyz(d, decodeCounts(d, counts)).counts;
        glm::dvec3 cutoff = cutoffCounts(d);
        for (int i = 0; i < 3; ++i) EXPECT_EQ(back[i], c <= cutoff[i] ? 0.0 : c) << "count " << c << " channel " << i;
    }
}

TEST(Display, GogCutoffCountsShowBlackAndEncodeToZero) {
    for (int bits : {8, 16}) {
        DisplayModel d = display("crt", bits);
        // gain·d + offset ≤ 0 for d ≤ 0.02/1.02: count 5 of 255, 1285 of 65535 (both exact).
        const double cutoff = bits == 8 ? 5.0 : 1285.0;
        EXPECT_EQ(cutoffCounts(d), glm::dvec3(cutoff));
        for (double c : {0.0, 1.0, cutoff - 1.0, cutoff}) {
            glm::dvec3 xyz = decodeCounts(d, glm::dvec3(c));
            expectXyz(xyz, d.blackXyz, 1e-15, "count " + std::to_string(c) + " shows the black level");
            expectCounts(encodeXyz(d, xyz), glm::dvec3(0.0), false, "black encodes to 0");
        }
        // The first count above the cutoff is lighter than black and comes back as itself.
        glm::dvec3 above = decodeCounts(d, glm::dvec3(cutoff + 1.0));
        EXPECT_GT(above.y, d.blackXyz.y);
        expectCounts(encodeXyz(d, above), glm::dvec3(cutoff + 1.0), false, "first count above the cutoff");
        // Darker than the display's black is out of range.
        expectCounts(encodeXyz(d, glm::dvec3(0.0)), glm::dvec3(0.0), true, "XYZ 0 is below the black level");
    }
}

TEST(Display, GogForwardModel) {
    DisplayModel d = display("crt");
    // Full drive: R = (1.02 − 0.02)^2.4 = 1, so counts 255 show the white (black included).
    expectXyz(decodeCounts(d, glm::dvec3(255.0)), d.whiteXyz, 1e-15, "full drive");
    expectCounts(encodeXyz(d, d.whiteXyz), glm::dvec3(255.0), false, "white");
    // Count 128 on green only: R_g = (1.02·128/255 − 0.02)^2.4.
    const double rg = std::pow(1.02 * 128.0 / 255.0 - 0.02, 2.4);
    expectXyz(decodeCounts(d, glm::dvec3(0.0, 128.0, 0.0)), d.rgbToXyz[1] * rg + d.blackXyz, 1e-15, "green 128");
}

TEST(Display, CrtWhiteAndPrimariesMatchBrainard1997) {
    DisplayModel d = display("crt");
    EXPECT_EQ(d.kind, DisplayKind::CrtGog);
    EXPECT_EQ(d.name, "crt");
    EXPECT_NEAR(d.whiteXyz.y, 1.0, 1e-15);
    expectXyz(d.rgbToXyz * glm::dvec3(1.0) + d.blackXyz, d.whiteXyz, 1e-15, "white = phosphors + black");
    EXPECT_NEAR(d.blackXyz.y, 0.005, 1e-15);
    // The black has the white's chromaticity.
    EXPECT_NEAR(d.blackXyz.x / d.blackXyz.y, d.whiteXyz.x / d.whiteXyz.y, 1e-12);
    EXPECT_NEAR(d.blackXyz.z / d.blackXyz.y, d.whiteXyz.z / d.whiteXyz.y, 1e-12);

    std::ifstream in(std::filesystem::path(METAMER_TEST_DATA_DIR) / "color" / "colorimetry" / "crt_primaries.txt");
    ASSERT_TRUE(in);
    int c = 0;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        std::string name;
        double x, y, share;
        ASSERT_TRUE(s >> name >> x >> y >> share) << line;
        ASSERT_LT(c, 3);
        glm::dvec3 p = d.rgbToXyz[c];  // column c: primary c at full drive, without the black
        const double sum = p.x + p.y + p.z;
        EXPECT_NEAR(p.x / sum, x, 1e-4) << name;
        EXPECT_NEAR(p.y / sum, y, 1e-4) << name;
        EXPECT_NEAR(p.y / (1.0 - d.blackXyz.y), share, 1e-4) << name;
        ++c;
    }
    EXPECT_EQ(c, 3);
}

TEST(Display, ParseErrors) {
    try {
        parseDisplay("srbg", 8, Where{"scene.json", "output.display"});
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        std::string what = e.what();
        EXPECT_NE(what.find("scene.json: output.display"), std::string::npos) << what;
        EXPECT_NE(what.find("did you mean 'srgb'"), std::string::npos) << what;
    }
    try {
        parseDisplay("oled", 8, Where{"", "display"});
        FAIL() << "no error";
    } catch (const Error& e) {
        std::string what = e.what();
        EXPECT_NE(what.find("'oled'"), std::string::npos) << what;
        EXPECT_NE(what.find("srgb, crt"), std::string::npos) << what;
    }
    for (int bits : {12, 0, 10, 32}) {
        try {
            parseDisplay("crt", bits, Where{"", "output.bits"});
            FAIL() << "no error for " << bits;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput);
            std::string what = e.what();
            EXPECT_NE(what.find("8 or 16"), std::string::npos) << what;
            EXPECT_NE(what.find(std::to_string(bits)), std::string::npos) << what;
        }
    }
}
