// An ICC profile of a display model (color/display_model.h), built with Little CMS: what a PNG
// written for that display carries (iCCP chunk), so that colour-managed viewers show its counts as
// the model says the display would. A matrix/TRC RGB profile (ICC v4):
//   XYZ = M′ · (TRC_r(d_r), TRC_g(d_g), TRC_b(d_b)),  d = count / (2^bits − 1)
// with the display's black folded into the curves: k = rgbToXyz⁻¹ · blackXyz per channel,
// TRC_i(d) = (R_i(d) + k_i) / (1 + k_i) (a parametric curve of ICC's type 2, lcms type 3:
// (a·d + b)^γ + c, and c alone below the cutoff) and M′ = rgbToXyz · diag(1 + k), so that
// XYZ = rgbToXyz · R(d) + blackXyz exactly, full drive giving whiteXyz. The primaries are the
// chromaticities of M′'s columns and the white whiteXyz's, adapted to ICC's D50 by Bradford
// (the profile's `chad` tag). docs/io.md, "Display PNGs and their colour space".
// Tests: engine/color/display_profile_test.cpp.
#pragma once

#include "color/display_model.h"

#include <cstdint>
#include <string>
#include <vector>

namespace metamer {

// The header's creation date, fixed (year, month, day, hour, minute, second, UTC): the same model
// gives the same bytes.
inline constexpr uint16_t kProfileDate[6] = {2026, 1, 1, 0, 0, 0};

// The profile's bytes (an sRGB model gets sRGB's parametric curve); `description` becomes its
// profileDescriptionTag. A runtime error if Little CMS fails.
std::vector<uint8_t> displayIccProfile(const DisplayModel& display, const std::string& description);

// How an image of a display model's counts says what colour space it is in, for colour-managed
// viewers: sRGB's own PNG chunk for the sRGB model, the model's ICC profile for any other (the
// render's display PNG, the preview's screenshots and a capture's developed frames).
struct DisplayColourTag {
    bool srgbChunk = false;
    std::vector<uint8_t> iccProfile;
};
DisplayColourTag displayColourTag(const DisplayModel& display);

}  // namespace metamer
