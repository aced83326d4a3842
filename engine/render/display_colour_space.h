// How an image of a display model's counts says what colour space it is in, for colour-managed
// viewers: sRGB's own PNG chunk for the sRGB model, the model's ICC profile (color/display_profile)
// for any other. The display PNG of a render and the preview's screenshots carry it.
// Tests: tests/python/check_ordinary_tools.py (the render's PNG chunks, sRGB and CRT),
// tests/preview_test.sh (the screenshots' chunks equal the render's).
#pragma once

#include "color/display_model.h"
#include "io/image_file.h"

namespace metamer {

void tagDisplayColourSpace(ImageFile& image, const DisplayModel& display);

}  // namespace metamer
