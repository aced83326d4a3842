// Demosaicing, the first step of the image processor after the raw (issue 48, item 2): a 2 × 2
// Bayer mosaic to three channels per pixel, by bilinear interpolation or by Malvar, He and
// Cutler's gradient-corrected linear interpolation (ICASSP 2004), the edge-aware method raw
// converters use as their fast path. Borders as colour-demosaicing's (so results equal its to
// rounding), or mirrored in the CFA's phase (the image processor's): DemosaicBorder below.
// Tests: engine/isp/demosaic_test.cpp, tests/python/test_isp.py (against colour-demosaicing).
#pragma once

#include "core/error.h"

#include <array>
#include <string>
#include <vector>

namespace metamer {

enum class DemosaicMethod { Bilinear, Malvar2004 };

// "bilinear" or "malvar2004"; an input error at `where` otherwise.
DemosaicMethod parseDemosaicMethod(const std::string& name, const Where& where);

// The 2 × 2 tile's colours, row by row: 0 red, 1 green, 2 blue ("RGGB" = {0, 1, 1, 2}). An input
// error at `where` unless it is one of RGGB, BGGR, GRBG, GBRG.
std::array<int, 4> bayerPattern(const std::string& name, const Where& where);

// What lies beyond the frame's edge. Reflect (half a sample out: …c b a | a b c…) is scipy.ndimage's
// "reflect", colour-demosaicing's: it shifts the CFA's phase, so a flat field's outermost pixels
// come out wrong (red 2.25× at an RGGB corner, bilinear). Mirror (about the edge sample: …c b | a
// b c…) keeps the phase, so every pixel of a flat field is exact: the image processor's.
enum class DemosaicBorder { Reflect, Mirror };

// width × height mosaic (row-major, any linear units) → width × height × 3 (R, G, B per pixel).
std::vector<double> demosaic(const std::vector<double>& mosaic, int width, int height, const std::array<int, 4>& pattern,
                             DemosaicMethod method, DemosaicBorder border = DemosaicBorder::Reflect);

}  // namespace metamer
