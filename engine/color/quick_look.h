// The quick look: a display image of a cube for eyes, not for measurement, made by the display
// stage's own parts — the CIE 1931 detector, the sRGB display model's encoder — with the one thing
// a quick look adds: an exposure chosen from the image itself, since a cube on its own has no
// reference white (a csv: detector's render, `metamer compare`-style inspection). docs/io.md,
// "Quick-look PNG". Tests: render/quicklook_png_test.cpp.
#pragma once

#include "spectral/cube.h"
#include "spectral/library.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace metamer {

struct QuickLook {
    int width = 0, height = 0;
    std::vector<uint16_t> counts;  // 3 per pixel, 8-bit sRGB counts, row 0 at the top
    double yPercentile99 = 0;      // radiometric Y (W·sr⁻¹·m⁻²) at the 99th percentile of pixels with Y > 0
    double yScale = 1;             // exposure applied to XYZ: 1 / yPercentile99, or 1 for a black cube
    size_t clippedPixels = 0;      // pixels where clipping to [0, 1] changed an 8-bit value
    size_t nonFinitePixels = 0;    // pixels with NaN or Inf XYZ, shown black
    std::string description;       // one line: what the image is
};

// CIE 1931 XYZ (Riemann, the observer from `library`) → exposure (the 99th percentile of the lit
// pixels' Y to Y = 1) → the sRGB display model (D65 white, no chromatic adaptation) → 8 bits.
QuickLook quickLook(const SpectralCube& cube, const SpectrumLibrary& library);

// The same from the cube's CIE 1931 XYZ (radiometric, W·sr⁻¹·m⁻²; 3 per pixel, row 0 at the top),
// as the response pass draws it without the bands (render/display_frame.h); `grid` is named in the
// description.
QuickLook quickLookFromXyz(int width, int height, const std::vector<glm::dvec3>& xyz, const Grid& grid);

}  // namespace metamer
