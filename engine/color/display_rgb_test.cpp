// The display's linear RGB (color/display_rgb): the sRGB display's primaries are BT.709 with D65,
// the CRT's are its phosphors; XYZ and counts give the same RGB where the counts are exact.
#include "color/display_rgb.h"

#include "color/srgb.h"

#include <gtest/gtest.h>

#include <glm/matrix.hpp>

using namespace metamer;

namespace {

void expectXy(const glm::dvec2& actual, double x, double y, double tolerance, const char* what) {
    EXPECT_NEAR(actual.x, x, tolerance) << what;
    EXPECT_NEAR(actual.y, y, tolerance) << what;
}

TonemapPlan planFor(const std::string& display) {
    TonemapPlan p;
    p.display = parseDisplay(display, 8, Where{});
    p.xyzOutputScale = 100.0;
    return p;
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

TEST(DisplayRgb, WhiteIsOneAndOutOfGamutIsNotClipped) {
    for (const char* name : {"srgb", "crt"}) {
        SCOPED_TRACE(name);
        const TonemapPlan plan = planFor(name);
        // The display white at the XYZ file's scale (Y = 100) is (1, 1, 1), black included.
        const glm::dvec3 white = linearDisplayRgbOfXyz(plan, 100.0 * plan.display.whiteXyz);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(white[c], 1.0, 1e-12);
        // Twice the white is 2: the preview keeps what the PNG clips.
        const glm::dvec3 bright = linearDisplayRgbOfXyz(plan, 200.0 * plan.display.whiteXyz);
        // (The CRT's black is added once, not twice: 2 + its share of each channel.)
        const glm::dvec3 black = glm::inverse(plan.display.rgbToXyz) * plan.display.blackXyz;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(bright[c], 2.0 + black[c], 1e-12);
        // What a count triple shows, as XYZ, comes back as the counts' linear RGB.
        const glm::dvec3 counts(40, 128, 250);
        const glm::dvec3 fromXyz = linearDisplayRgbOfXyz(plan, 100.0 * decodeCounts(plan.display, counts));
        const glm::dvec3 fromCounts = linearRgbOfCounts(plan.display, counts);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(fromXyz[c], fromCounts[c], 1e-12) << c;
    }
}
