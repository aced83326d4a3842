// What the display's linear RGB means (color/display_rgb): the sRGB display's primaries are BT.709
// with D65, the CRT's its phosphors; and what linearRgbOfCounts gives, the display shows.
#include "color/display_rgb.h"

#include <gtest/gtest.h>

#include <string>

using namespace metamer;

namespace {

void expectXy(const glm::dvec2& actual, double x, double y, double tolerance, const char* what) {
    EXPECT_NEAR(actual.x, x, tolerance) << what;
    EXPECT_NEAR(actual.y, y, tolerance) << what;
}

}  // namespace

TEST(DisplayRgb, SrgbPrimariesAreBt709WithD65) {
    const DisplayPrimaries p = displayPrimaries(parseDisplay("srgb", 8, Where{}));
    expectXy(p.red, 0.64, 0.33, 1e-4, "red");
    expectXy(p.green, 0.30, 0.60, 1e-4, "green");
    expectXy(p.blue, 0.15, 0.06, 1e-4, "blue");
    expectXy(p.white, 0.3127, 0.3290, 1e-4, "white");
}

TEST(DisplayRgb, CrtPrimariesAreItsPhosphorsAndItsWhite) {
    const DisplayModel crt = parseDisplay("crt", 8, Where{});
    const DisplayPrimaries p = displayPrimaries(crt);
    // Brainard's phosphors (color/display_model.cpp) and the white's chromaticity.
    expectXy(p.red, 0.61885377, 0.34403993, 1e-8, "red");
    expectXy(p.green, 0.27649399, 0.60491706, 1e-8, "green");
    expectXy(p.blue, 0.15119002, 0.06108496, 1e-8, "blue");
    const double sum = crt.whiteXyz.x + crt.whiteXyz.y + crt.whiteXyz.z;
    expectXy(p.white, crt.whiteXyz.x / sum, crt.whiteXyz.y / sum, 1e-12, "white");
}

// The preview's numbers: counts through the transfer function alone; through rgbToXyz, plus the
// black, they are what the display shows (decodeCounts), and full drive is (1, 1, 1).
TEST(DisplayRgb, LinearRgbOfCountsIsWhatTheDisplayShowsLessItsBlack) {
    for (const char* name : {"srgb", "crt"}) {
        for (int bits : {8, 16}) {
            SCOPED_TRACE(std::string(name) + " " + std::to_string(bits));
            const DisplayModel d = parseDisplay(name, bits, Where{});
            const glm::dvec3 full = linearRgbOfCounts(d, glm::dvec3(maxCount(d)));
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(full[c], 1.0, 1e-15);
            const glm::dvec3 counts = glm::dvec3(0.1, 0.5, 0.9) * maxCount(d);
            const glm::dvec3 shown = d.rgbToXyz * linearRgbOfCounts(d, counts) + d.blackXyz;
            const glm::dvec3 decoded = decodeCounts(d, counts);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(shown[c], decoded[c], 1e-15);
        }
    }
}
