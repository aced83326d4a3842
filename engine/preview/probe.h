// The pixel probe: what one pixel of the preview holds, in the units of docs/preview.md — its
// spectrum (or a non-spectral mode's channels), its colour as the detector sees it, and the display
// counts the window shows there.
// Tests: engine/preview/view_test.cpp.
#pragma once

#include "color/tonemap.h"
#include "represent/representation.h"
#include "spectral/cube.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace metamer::preview {

struct ProbeReadout {
    int x = 0, y = 0;  // image pixel, row 0 at the top
    // The pixel's cube values as `metamer render` writes them: spectral radiance per band,
    // W·sr⁻¹·m⁻²·nm⁻¹ (full; linear:K projected onto its basis), or channel radiance (rgb, ac1c2).
    std::vector<float> values;
    std::vector<double> wavelengths_nm;  // band centres (spectral modes); empty otherwise
    std::vector<std::string> channelNames;  // the mode's channel names (non-spectral modes)
    bool colorimetric = false;  // XYZ and L*a*b* exist (not a custom detector's responses only)
    // Relative XYZ as the detector sees the pixel, before chromatic adaptation, with the scene's
    // reference white at Y = 100 (computed on the CPU in double precision from `values`).
    glm::dvec3 xyz{0.0};
    glm::dvec3 whiteXyz{0.0};  // the reference white on the same scale (Y = 100)
    glm::dvec3 lab{0.0};       // CIELAB of xyz against whiteXyz
    std::vector<double> responses;  // detector responses (detector units)
    // The display counts the window shows at this pixel (from the GPU tonemap pass), 0..2^bits−1.
    glm::ivec3 counts{0};
    int bits = 8;
    bool clipped = false;  // outside the display's gamut or range
};

// Pixel (x, y) (inside `image`, the tonemap pass's output for the frame): `values` are its
// grid.bands() cube values as the spectral pass read them back, before any linear:K projection.
ProbeReadout probePixel(const TonemapPlan& plan, const Representation& representation, const float* values,
                        const Grid& grid, const DisplayImage& image, int x, int y);

// One line for the terminal: "probe 64,64: XYZ 20.10 21.31 18.20  L*a*b* 53.28 1.20 -0.53  counts 128 127 126".
std::string describeProbe(const ProbeReadout& p);

}  // namespace metamer::preview
