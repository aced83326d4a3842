// What the display's linear RGB means — what a display model (color/display_model.h) drives its
// primaries with, before its transfer function (linearRgbOfCounts): the primaries and the white.
// The spectral EXR's R, G, B preview channels are that RGB of the display image and carry these
// as their chromaticities (docs/io.md, "Preview channels").
// Tests: engine/color/display_rgb_test.cpp.
#pragma once

#include "color/display_model.h"

#include <glm/vec2.hpp>

namespace metamer {

// CIE 1931 xy of the display's primaries (the columns of rgbToXyz) and of its linear RGB white,
// rgbToXyz · (1, 1, 1): the light the display adds to its black at full drive. sRGB: BT.709 and
// D65. The CRT: its phosphors, and its white's chromaticity (its black has the same, so taking
// it away changes none).
struct DisplayPrimaries {
    glm::dvec2 red{0.0}, green{0.0}, blue{0.0}, white{0.0};
};
DisplayPrimaries displayPrimaries(const DisplayModel& display);

}  // namespace metamer
