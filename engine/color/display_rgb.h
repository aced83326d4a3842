// The display's linear RGB: what a display model (color/display_model.h) drives its primaries
// with before its transfer function, and the primaries and white those numbers mean. The spectral
// EXR's R, G, B preview channels are this RGB (docs/io.md, "Preview channels"); the CRT's ICC
// profile is built from the same primaries (color/display_profile.h).
// Tests: engine/color/display_rgb_test.cpp.
#pragma once

#include "color/tonemap.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace metamer {

// CIE 1931 xy of the display's primaries (the columns of rgbToXyz) and of its linear RGB white,
// rgbToXyz · (1, 1, 1): the light the display adds to its black at full drive. sRGB: BT.709 and
// D65. The CRT: the phosphors and the white less nothing, since its black has the white's
// chromaticity.
struct DisplayPrimaries {
    glm::dvec2 red{0.0}, green{0.0}, blue{0.0}, white{0.0};
};
DisplayPrimaries displayPrimaries(const DisplayModel& display);

// Linear RGB from XYZ as the display path writes it (DisplayImage::xyz, scaled by the plan's
// xyzOutputScale, before adaptation): adapted, less the display's black, through rgbToXyz⁻¹.
// Not clipped: a colour outside the display's gamut keeps its negative or > 1 components; the
// display white is (1, 1, 1).
glm::dvec3 linearDisplayRgbOfXyz(const TonemapPlan& plan, const glm::dvec3& xyz);
// (From counts instead: linearRgbOfCounts, color/display_model.h.)

}  // namespace metamer
