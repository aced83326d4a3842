// The slanted-edge SFR (ISO 12233 e-SFR) against a known answer: a noise-free edge, its pixels the
// exact area it covers, through a diffraction-limited lens (sensor/lens.h) measures the lens's
// closed-form MTF times the boxes of the pixels (issue 48, item 3).
#include "sensor/slanted_edge.h"

#include "sensor/lens.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace metamer;

namespace {

constexpr double kPi = std::numbers::pi;

double sinc(double x) { return std::abs(x) < 1e-12 ? 1.0 : std::sin(kPi * x) / (kPi * x); }

// A W × H cube whose every band holds, per pixel, the fraction of its area right of the line
// through (x0, y0) leaning `deg` from the vertical (32 × 32 samples a pixel).
SpectralCube edge(int W, int H, double deg, const Grid& grid) {
    SpectralCube c(W, H, grid);
    const double t = std::tan(deg * kPi / 180.0), x0 = 0.5 * W, y0 = 0.5 * H;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int in = 0;
            for (int j = 0; j < 32; ++j)
                for (int i = 0; i < 32; ++i) {
                    const double px = x + (i + 0.5) / 32, py = y + (j + 0.5) / 32;
                    in += px > x0 + t * (py - y0);
                }
            for (int b = 0; b < grid.bands(); ++b) c.pixel(x, y)[b] = float(in / 1024.0);
        }
    return c;
}

std::vector<double> band(const SpectralCube& c, int b) {
    std::vector<double> v(size_t(c.width) * size_t(c.height));
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) v[size_t(y) * c.width + size_t(x)] = c.pixel(x, y)[b];
    return v;
}

}  // namespace

TEST(SlantedEdge, AnEdgeThroughADiffractionLimitedLensMeasuresItsClosedFormMtf) {
    // f/16 at 550 nm on 5 µm pixels: the cutoff 1/(λN) = 0.568 cycles/pixel, just past Nyquist.
    const double deg = 5.0;
    const Grid grid{550, 560, 10};
    const SpectralCube scene = edge(96, 128, deg, grid);
    LensSpec lens;  // diffraction and the pixel aperture
    const LensGeometry g{0.005, 1.0, 16.0};
    const SpectralCube image = throughLens(scene, lens, g, 2);
    // The middle 64 columns: the frame's dark outside stays out of the region.
    std::vector<double> region;
    for (int y = 16; y < 112; ++y)
        for (int x = 16; x < 80; ++x) region.push_back(image.pixel(x, y)[0]);
    const EdgeSfr sfr = slantedEdgeSfr(region, 64, 96, Where{"edge"});
    EXPECT_NEAR(sfr.angle_deg, deg, 0.05);  // leaning right going down: x grows with y
    const double c = std::cos(deg * kPi / 180.0), s = std::sin(deg * kPi / 180.0);
    const double cutoff = 1.0 / (550e-6 * 16.0) * 0.005;  // cycles per pixel
    double worst = 0.0;
    for (size_t k = 0; k < sfr.frequency.size(); ++k) {
        const double f = sfr.frequency[k];
        if (f > 0.5) break;
        const double nu = f / cutoff;
        const double diffraction = nu >= 1.0 ? 0.0 : 2.0 / kPi * (std::acos(nu) - nu * std::sqrt(1.0 - nu * nu));
        // Three pixel boxes along the normal: the area each scene pixel averages, the lens model's
        // constant square, and the sensor pixel's aperture.
        const double box = sinc(f * c) * sinc(f * s);
        const double want = diffraction * box * box * box;
        worst = std::max(worst, std::abs(sfr.mtf[k] - want));
        // The e-SFR's Hamming window and the 64-pixel region cut the Airy LSF's 1/x² tails (the
        // cusp of the diffraction OTF at 0): below 0.05 cycles/pixel the measure reads up to 0.02 high.
        EXPECT_NEAR(sfr.mtf[k], want, 0.025) << "f = " << f << " cycles/pixel";
    }
    std::printf("slanted edge: worst |MTF − closed form| %.4f up to Nyquist; MTF50 %.4f cycles/pixel\n", worst, sfr.mtf50);
}

TEST(SlantedEdge, ARegionWithoutAUsableEdgeIsAnInputError) {
    const std::vector<double> flat(32 * 32, 0.5);
    EXPECT_THROW(slantedEdgeSfr(flat, 32, 32, Where{"chart.png"}), Error);
    EXPECT_THROW(slantedEdgeSfr(flat, 8, 8, Where{"chart.png"}), Error);
    const SpectralCube vertical = edge(32, 32, 0.0, Grid{550, 560, 10});
    try {
        slantedEdgeSfr(band(vertical, 0), 32, 32, Where{"chart.png"});
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(e.message().find("the slanted-edge method needs 1° … 20°"), std::string::npos) << e.message();
    }
}
