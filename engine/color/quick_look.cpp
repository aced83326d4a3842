#include "color/quick_look.h"

#include "color/cie_xyz.h"
#include "color/detector.h"
#include "color/display_model.h"
#include "color/srgb.h"
#include "core/statistics.h"

#include <algorithm>
#include <cmath>

namespace metamer {

namespace {

// Whether clipping to [0, 1] changes the 8-bit code: a white a hair above 1 (a D65 spectrum on a
// coarse grid lands within ~2e-4 of the display's white) is not reported as clipped.
bool clipVisible(double linear) {
    if (linear > 1.0) return srgbEncode(linear) * 255.0 >= 255.5;
    if (linear < 0.0) return srgbEncode(-linear) * 255.0 >= 0.5;  // the encoding mirrored
    return false;
}

}  // namespace

QuickLook quickLook(const SpectralCube& cube, const SpectrumLibrary& library) {
    const size_t pixels = static_cast<size_t>(cube.width) * cube.height;
    if (cube.width <= 0 || cube.height <= 0 || cube.data.size() != pixels * cube.bands())
        failRuntime("quick look: the cube is {}×{} with {} bands but holds {} values", cube.width, cube.height,
                    cube.bands(), cube.data.size());
    const Detector observer = observerDetector("cie1931", kCie1931Observer, library, cube.grid, Integration::Riemann);
    std::vector<glm::dvec3> xyz(pixels);
    for (size_t p = 0; p < pixels; ++p) xyz[p] = detectorResponse3(observer, cube.data.data() + p * cube.bands());
    return quickLookFromXyz(cube.width, cube.height, xyz, cube.grid);
}

QuickLook quickLookFromXyz(int width, int height, const std::vector<glm::dvec3>& xyz, const Grid& grid) {
    const size_t pixels = static_cast<size_t>(std::max(0, width)) * std::max(0, height);
    if (width <= 0 || height <= 0 || xyz.size() != pixels)
        failRuntime("quick look: the image is {}×{} but {} XYZ values were given", width, height, xyz.size());
    QuickLook q;
    q.width = width;
    q.height = height;
    // Auto-exposure: the 99th percentile of the lit pixels goes to Y = 1, so a few highlights clip
    // but a small bright light does not turn the rest of the image black.
    std::vector<double> lit;
    lit.reserve(pixels);
    for (const auto& c : xyz)
        if (std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && c.y > 0) lit.push_back(c.y);
    if (!lit.empty()) {
        q.yPercentile99 = percentile(lit, 0.99);
        q.yScale = 1.0 / q.yPercentile99;
    }

    const DisplayModel display = parseDisplay("srgb", 8, Where{});
    const glm::dmat3 toRgb = glm::inverse(display.rgbToXyz);
    q.counts.assign(pixels * 3, 0);
    for (size_t p = 0; p < pixels; ++p) {
        const glm::dvec3& c = xyz[p];
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) {
            ++q.nonFinitePixels;
            continue;
        }
        const EncodeResult e = encodeXyz(display, c * q.yScale);
        const glm::dvec3 rgb = toRgb * (c * q.yScale);
        bool clipped = false;
        for (int i = 0; i < 3; ++i) {
            clipped |= clipVisible(rgb[i]);
            q.counts[p * 3 + size_t(i)] = static_cast<uint16_t>(e.counts[i]);
        }
        q.clippedPixels += clipped;
    }
    q.description = fmt::format(
        "metamer quick-look: CIE 1931 XYZ -> sRGB (D65), no chromatic adaptation, Y scale 1/{:.6g} "
        "(99th percentile of Y>0, radiometric W.sr^-1.m^-2); grid {}",
        q.yPercentile99 > 0 ? q.yPercentile99 : 1.0, grid.str());
    return q;
}

}  // namespace metamer
