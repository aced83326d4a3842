// The quick-look PNG: an 8-bit sRGB preview of a spectral cube, for eyes, not for measurement.
// The image is the display stage's (color/quick_look.h: CIE 1931 XYZ -> auto-exposure on Y -> the
// sRGB display model, no chromatic adaptation); this writes it (docs/io.md).
#pragma once

#include "spectral/cube.h"
#include "spectral/library.h"

#include <filesystem>
#include <string>

namespace metamer {

struct QuickLookReport {
    double yPercentile99 = 0;     // radiometric Y (W·sr⁻¹·m⁻²) at the 99th percentile of pixels with Y > 0
    double yScale = 1;            // exposure applied to XYZ: 1 / yPercentile99, or 1 for a black cube
    size_t clippedPixels = 0;     // pixels where clipping to [0, 1] changed an 8-bit value
    size_t nonFinitePixels = 0;   // pixels with NaN or Inf XYZ, written black
    std::string description;      // the ImageDescription stored in the PNG
};

// Writes the PNG through AtomicOutput. The observer comes from `library`
// (observers/cie1931_2deg). Runtime errors name the path.
QuickLookReport writeQuickLookPng(const std::filesystem::path& path, const SpectralCube& cube,
                                  const SpectrumLibrary& library);

}  // namespace metamer
