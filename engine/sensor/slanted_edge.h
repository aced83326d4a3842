// The slanted-edge spatial frequency response of ISO 12233 (e-SFR, the method of its Annex D and
// of sfrmat): a near-vertical edge's rows are located to sub-pixel precision, a line is fitted to
// them, every pixel is binned by its distance from the line into a 4× oversampled edge-spread
// function, whose derivative (the line-spread function, Hamming-windowed) is Fourier transformed.
// The MTF is its modulus normalized at f = 0, corrected for the derivative's own transfer, at
// frequencies along the edge's normal in cycles per pixel. Issue 48, item 3; docs/camera.md,
// "Slanted-edge SFR". Tests: engine/sensor/slanted_edge_test.cpp (an edge through the lens, against
// the lens's closed-form MTF).
#pragma once

#include "core/error.h"

#include <vector>

namespace metamer {

struct EdgeSfr {
    std::vector<double> frequency;  // cycles per pixel along the edge's normal, 0 … 1 (twice Nyquist)
    std::vector<double> mtf;        // the modulation transfer at each, 1 at f = 0
    double angle_deg = 0.0;         // the edge's angle from the vertical
    double mtf50 = 0.0;             // the frequency (cycles/pixel) where the MTF first falls to 0.5
};

// The e-SFR of a width × height image (row-major, row 0 at the top) holding one near-vertical
// edge (1° … 20° from the vertical, either side; dark and bright either way). Input errors at
// `where` for an image without a usable edge (too small, no contrast, an edge too steep or too
// flat for the 4× binning).
EdgeSfr slantedEdgeSfr(const std::vector<double>& image, int width, int height, const Where& where);

}  // namespace metamer
