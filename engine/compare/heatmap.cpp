#include "compare/heatmap.h"

#include "color/display_model.h"
#include "color/lab.h"
#include "core/error.h"
#include "io/image_file.h"

#include <algorithm>
#include <cmath>

namespace metamer {

namespace {

constexpr double kDecades = 2.0;         // either side of the threshold
constexpr double kCentreWithoutThreshold = 1e-4;
constexpr uint16_t kMaskedGrey = 128;    // neutral, unlike both ramps

// The ramps are drawn in CIELAB so that equal steps of log error are roughly equal steps of
// lightness: both ramps climb in L*, so the whole scale reads dark → light, and the hue jumps
// from blue to red exactly at the threshold, which is what the eye should find first.
glm::dvec3 rampLab(bool over, double s) {
    if (!over) return {8.0 + 42.0 * s, 8.0 * s, -40.0 * s};  // near black → medium blue
    return {52.0 + 43.0 * s, 68.0 * (1.0 - s) - 4.0 * s, 52.0 * (1.0 - s) + 80.0 * s};  // red → light yellow
}

}  // namespace

std::array<uint8_t, 3> heatmapColor(double error, double threshold) {
    static const DisplayModel srgb = parseDisplay("srgb", 8, Where{});
    if (std::isnan(error) || std::isinf(error)) return {255, 0, 255};
    double centre = threshold > 0.0 ? threshold : kCentreWithoutThreshold;
    // Position in decades from the centre, clamped to the scale; an exact match sits at the bottom.
    double decades = error > 0.0 ? std::clamp(std::log10(error / centre), -kDecades, kDecades) : -kDecades;
    bool over = error > std::max(threshold, 0.0);
    double s = over ? std::max(decades, 0.0) / kDecades : 1.0 + std::min(decades, 0.0) / kDecades;
    glm::dvec3 xyz = labToXyz(rampLab(over, s), srgb.whiteXyz);
    glm::dvec3 counts = encodeXyz(srgb, xyz).counts;
    return {uint8_t(counts.x), uint8_t(counts.y), uint8_t(counts.z)};
}

void writeHeatmap(const std::filesystem::path& path, const CompareStats& stats, double threshold) {
    const size_t pixels = size_t(stats.width) * stats.height;
    if (stats.width <= 0 || stats.height <= 0 || stats.pixelError.size() != pixels)
        failRuntime("cannot write heat map '{}': {} per-pixel errors for {}×{} pixels", path.string(),
                    stats.pixelError.size(), stats.width, stats.height);
    // Errors repeat (exact matches above all); a small cache keeps big images quick.
    std::vector<uint16_t> rgb(pixels * 3);
    size_t over = 0;
    float lastError = -1.0f;
    std::array<uint8_t, 3> last{};
    for (size_t p = 0; p < pixels; ++p) {
        if (!stats.mask.empty() && stats.mask[p]) {
            for (int c = 0; c < 3; ++c) rgb[p * 3 + c] = kMaskedGrey;
            continue;
        }
        float e = stats.pixelError[p];
        over += !(e <= std::max(threshold, 0.0));
        if (!(e == lastError)) {
            last = heatmapColor(e, threshold);
            lastError = e;
        }
        for (int c = 0; c < 3; ++c) rgb[p * 3 + c] = last[size_t(c)];
    }
    double centre = threshold > 0.0 ? threshold : kCentreWithoutThreshold;
    ImageFile image{stats.width, stats.height, {"R", "G", "B"}, {}};
    image.attributes.push_back(
        {"ImageDescription",
         fmt::format("metamer compare heat map: per pixel the largest relative error over the channels, log scale "
                     "{:.3g} (near black) to {:.3g} (light blue) | over the threshold: red to {:.3g} (light yellow); "
                     "magenta: NaN or Inf in one image only; grey: masked; {} of {} pixels over",
                     centre / 100.0, std::max(threshold, 0.0), centre * 100.0, over, pixels - stats.maskedPixels)});
    image.attributes.push_back({"oiio:ColorSpace", "sRGB"});  // its colours are sRGB counts
    writeImage(path, image, rgb, 8);
}

}  // namespace metamer
