// The figures a camera report holds besides the SFR (issue 48, item 3; docs/camera.md, "The camera
// report"): the colour error of a developed image against the scene's own colours (ΔE00 per patch),
// and EMVA 1288's photon transfer from two frames of the same exposure (mean signal, temporal
// variance, SNR). The slanted-edge SFR is sensor/slanted_edge.
// Tests: engine/isp/camera_metrics_test.cpp, tests/python/test_camera_report.py.
#pragma once

#include "color/adaptation.h"
#include "core/error.h"

#include <glm/vec3.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace metamer {

struct DevelopedColourError {
    std::vector<glm::dvec3> developedLab, referenceLab;  // CIELAB of the D65 white, per colour
    std::vector<double> deltaE2000;
    double exposureScale = 1.0;  // what the developed XYZ were multiplied by
};

// ΔE00 of each developed colour (linear sRGB, D65) against the scene's colour it shows (CIE 1931
// XYZ on any scale whose perfect white under the scene's light is `referenceWhite`), the scene's
// colour adapted from that white to D65 by `adaptation`, as the processor adapts. The developed
// image's exposure is arbitrary, so its XYZ are scaled to give colour `exposureFrom` (the white
// patch, say) the reference's luminance Y. Input errors at `where` for unequal lists, a reference
// white with no luminance, or an exposure colour with none.
DevelopedColourError developedColourError(const std::vector<glm::dvec3>& developedLinearSrgb,
                                          const std::vector<glm::dvec3>& referenceXyz, const glm::dvec3& referenceWhite,
                                          Adaptation adaptation, size_t exposureFrom, const Where& where);

// A rectangle of pixels: x, y (top left), width, height.
using PixelRect = std::array<int, 4>;

struct PhotonTransferPoint {
    double mean_dn = 0.0;         // μ_y − black: the mean signal of the sites, DN above black
    double variance_dn2 = 0.0;    // σ²_y: the temporal variance, var(A − B)/2 over the sites
    double snr = 0.0;             // μ / σ (0 when σ is 0)
    size_t sites = 0;             // how many pixels of the rectangle were used
};

// EMVA 1288 (release 4, §6.2) from two frames A and B of the same exposure (width × height DN each):
// over the pixels of `rect` whose CFA channel is `channel` (`channelOf(x, y)`), μ_y = mean(A + B)/2
// and σ²_y = var(A − B)/2 — the difference removes the fixed patterns and the scene, leaving the
// temporal noise. Input errors at `where` for a rectangle outside the frames or with no such pixel.
template <typename ChannelOf>
PhotonTransferPoint photonTransfer(const uint16_t* a, const uint16_t* b, int width, int height, const PixelRect& rect,
                                   int channel, ChannelOf channelOf, double black, const Where& where);

void requireRectInside(const PixelRect& rect, int width, int height, const Where& where);

template <typename ChannelOf>
PhotonTransferPoint photonTransfer(const uint16_t* a, const uint16_t* b, int width, int height, const PixelRect& rect,
                                   int channel, ChannelOf channelOf, double black, const Where& where) {
    requireRectInside(rect, width, height, where);
    double sum = 0.0, diffSum = 0.0, diffSq = 0.0;
    size_t n = 0;
    for (int y = rect[1]; y < rect[1] + rect[3]; ++y)
        for (int x = rect[0]; x < rect[0] + rect[2]; ++x) {
            if (channelOf(x, y) != channel) continue;
            const size_t i = size_t(y) * size_t(width) + size_t(x);
            const double d = double(a[i]) - double(b[i]);
            sum += double(a[i]) + double(b[i]);
            diffSum += d;
            diffSq += d * d;
            ++n;
        }
    if (n < 2) failInput(where, "the rectangle holds {} pixel(s) of channel {}; the photon transfer needs 2 or more", n, channel);
    PhotonTransferPoint p;
    p.sites = n;
    p.mean_dn = sum / (2.0 * double(n)) - black;
    const double meanDiff = diffSum / double(n);
    p.variance_dn2 = (diffSq / double(n) - meanDiff * meanDiff) * double(n) / double(n - 1) / 2.0;
    p.snr = p.variance_dn2 > 0.0 ? p.mean_dn / std::sqrt(p.variance_dn2) : 0.0;
    return p;
}

}  // namespace metamer
