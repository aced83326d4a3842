#include "io/quicklook_png.h"

#include "io/image_file.h"

#include "color/cie_xyz.h"
#include "color/srgb.h"
#include "core/error.h"
#include "io/atomic_file.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace metamer {

namespace {

// Whether clipping to [0, 1] changes the 8-bit code: a white a hair above 1 (a D65 spectrum on a
// coarse grid lands within ~2e-4 of the matrix's white) is not reported as clipped.
bool clipVisible(double linear) {
    if (linear > 1.0) return srgbEncode(linear) * 255.0 >= 255.5;
    if (linear < 0.0) return srgbEncode(-linear) * 255.0 >= 0.5;  // the encoding mirrored
    return false;
}

// Nearest-rank percentile; reorders `values`.
double percentile(std::vector<double>& values, double p) {
    size_t rank = static_cast<size_t>(std::ceil(p * static_cast<double>(values.size())));
    size_t k = std::clamp<size_t>(rank, 1, values.size()) - 1;
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
    return values[k];
}

}  // namespace

QuickLookReport writeQuickLookPng(const std::filesystem::path& path, const SpectralCube& cube,
                                  const SpectrumLibrary& library) {
    const size_t pixels = static_cast<size_t>(cube.width) * cube.height;
    if (cube.width <= 0 || cube.height <= 0 || cube.data.size() != pixels * cube.bands())
        failRuntime("cannot write '{}': cube is {}×{} with {} bands but holds {} values", path.string(),
                    cube.width, cube.height, cube.bands(), cube.data.size());
    std::vector<glm::dvec3> xyz = cubeToXyz(cube, loadCie1931(library, cube.grid));

    QuickLookReport report;
    // Auto-exposure: the 99th percentile of the lit pixels goes to Y = 1, so a few highlights clip
    // but a small bright light does not turn the rest of the image black.
    std::vector<double> lit;
    lit.reserve(pixels);
    for (const auto& c : xyz)
        if (std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && c.y > 0) lit.push_back(c.y);
    if (!lit.empty()) {
        report.yPercentile99 = percentile(lit, 0.99);
        report.yScale = 1.0 / report.yPercentile99;
    }

    std::vector<uint8_t> rgb8(pixels * 3, 0);
    for (size_t p = 0; p < pixels; ++p) {
        const glm::dvec3& c = xyz[p];
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) {
            ++report.nonFinitePixels;
            continue;
        }
        glm::dvec3 rgb = xyzToLinearSrgb(c * report.yScale);
        bool clipped = false;
        for (int i = 0; i < 3; ++i) {
            clipped |= clipVisible(rgb[i]);
            double v = srgbEncode(std::clamp(rgb[i], 0.0, 1.0));
            rgb8[p * 3 + i] = static_cast<uint8_t>(std::lround(v * 255.0));
        }
        report.clippedPixels += clipped;
    }

    report.description = fmt::format(
        "metamer quick-look: CIE 1931 XYZ -> sRGB (D65), no chromatic adaptation, Y scale 1/{:.6g} "
        "(99th percentile of Y>0, radiometric W.sr^-1.m^-2); grid {}",
        report.yPercentile99 > 0 ? report.yPercentile99 : 1.0, cube.grid.str());

    ImageFile file{cube.width, cube.height, {"R", "G", "B"},
                   {{"ImageDescription", report.description}, {"oiio:ColorSpace", "sRGB"}}};
    writeImage(path, file, std::vector<uint16_t>(rgb8.begin(), rgb8.end()), 8);
    return report;
}

}  // namespace metamer
