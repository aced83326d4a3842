// A picture of where two images differ: each pixel's largest relative error over its channels
// (CompareStats::pixelError) as an 8-bit sRGB PNG the size of the images. docs/compare.md,
// "Heat map", has the colour scale.
#pragma once

#include "compare/compare.h"

#include <array>
#include <cstdint>
#include <filesystem>

namespace metamer {

// Writes the heat map atomically (io/image_file). The scale is logarithmic and centred on
// `threshold` (the pixel threshold of the comparison), two decades either side: errors at or
// below the threshold run from near black (≤ threshold/100, and exact matches) through
// increasingly light blues; errors above it jump to a warm ramp, red just above the threshold to
// light yellow at ≥ threshold×100. Values NaN or infinite in one image only are magenta, masked
// pixels (CompareOptions::mask) neutral grey (128). A
// threshold ≤ 0 marks every non-zero error as over and centres the scale on 1e-4.
void writeHeatmap(const std::filesystem::path& path, const CompareStats& stats, double threshold);

// The 8-bit sRGB colour of one error value (the same rule; for tests and the legend in the docs).
std::array<uint8_t, 3> heatmapColor(double error, double threshold);

}  // namespace metamer
