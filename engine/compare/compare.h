// Comparing two images value by value: a test image A against a reference B (the golden file).
// Both are spectral cubes (S0.<λ>nm or T.<λ>nm channels) or both ordinary multi-channel images
// (XYZ or response EXRs, display PNGs). The statistics are what a regression test gates on
// (compare/tolerance.h) and what `metamer compare` prints; docs/compare.md has every formula.
#pragma once

#include "color/tonemap.h"
#include "spectral/cube.h"
#include "spectral/grid.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace metamer {

// A spectral cube or any multi-channel float image, as read from a file.
struct ImageData {
    int width = 0, height = 0;
    std::vector<std::string> channels;  // spectral: "S0.<λ>nm" (or "T.<λ>nm") names; else the file's
    std::optional<Grid> grid;           // set for spectral cubes (S0 or T channels on a uniform grid)
    std::vector<float> data;            // pixel-interleaved, channels.size() per pixel, row 0 at the top
    std::string source;                 // the file as the user named it, for messages ("" = in memory)
    std::string kind;                   // "spectral radiance", "reflectance", "EXR float", "PNG counts", ...
    int countBits = 0;                  // integer images: the bits of their counts (8, 16); 0 for values

    bool reflective() const;            // a T.<λ>nm cube
};

// Reads a spectral EXR (any file with S0.<λ> or T.<λ> channels, through readSpectralExrImage) or
// any other image OpenImageIO reads (EXR channels as stored; PNG and other integer formats as
// counts, 0..255 for 8 bits, not normalized). Input errors (exit 2) name the file.
ImageData readComparable(const std::filesystem::path& path);

// A mask for CompareOptions::mask from an image file (e.g. the render's <scene>.edges.png): a pixel
// is masked where any channel is non-zero. It must be width × height; input errors name the file.
std::vector<uint8_t> readMask(const std::filesystem::path& path, int width, int height);

// A cube held in memory (tests, the lead's golden runner): emissive S0 channels.
ImageData fromCube(const SpectralCube& cube);

struct CompareOptions {
    // The relative error of a value is |a − b| / max(|b|, relativeFloor × max|b| of its channel):
    // the floor keeps near-black values of B from turning rounding noise into huge ratios.
    double relativeFloor = 1e-4;
    // A pixel "differs" when any channel's relative error exceeds this.
    double pixelThreshold = 1e-3;
    // Bring A onto B's grid (each pixel's spectrum, piecewise linear through its band values,
    // put onto B's bands by the grid rule: spectral/resampling.h) when the grids differ. Sizes
    // must still match.
    bool resample = false;
    // ΔE2000 through this detector, adaptation and display white (spectral cubes only); the white
    // is an equal-energy radiance at B's 99th-percentile CIE 1931 Y (docs/compare.md).
    std::optional<TonemapSettings> display;
    // One entry per pixel (row 0 at the top), or empty: pixels with a non-zero entry are left out
    // of every statistic — e.g. a golden's edge pixels, where a half-pixel shift of a silhouette
    // between two rasterizers is not an error (readMask).
    std::vector<uint8_t> mask;
};

struct ChannelStats {
    std::string name;
    double maxAbs = 0, maxRel = 0, rmse = 0;
};

struct CompareStats {
    int width = 0, height = 0;
    size_t channels = 0;
    std::vector<ChannelStats> perChannel;  // per band for cubes, in B's channel order
    double maxAbs = 0, maxRel = 0, rmse = 0;
    double rmseRelative = 0;               // rmse / mean |B|
    // Per pixel, the angle between the A and B vectors (over channels), for pixels where both are
    // non-zero and finite.
    double spectralAngleMaxDeg = 0, spectralAngleMeanDeg = 0;
    double fractionOverThreshold = 0;      // of pixels
    std::optional<double> deltaE2000Mean, deltaE2000P95, deltaE2000Max;
    std::vector<float> pixelError;         // per pixel, the max relative error over its channels (0 if masked)
    std::vector<uint8_t> mask;             // CompareOptions::mask, kept for the heat map

    // Context for reports.
    double pixelThreshold = 0, relativeFloor = 0;  // the options used
    size_t pixelsOverThreshold = 0;
    size_t maskedPixels = 0;               // left out by CompareOptions::mask
    size_t nonFiniteMismatches = 0;        // values non-finite in one image and not equal in the other
    int worstX = -1, worstY = -1;          // the pixel and channel of maxRel (-1: no difference)
    int worstChannel = -1;
    std::optional<Grid> grid;              // B's grid for cubes
    std::string resampledFrom;             // A's grid when --resample moved it onto B's, else ""
    std::string deltaE2000Setup;           // detector, white, adaptation, display, for reports
};

// A against the reference B. Input errors (exit 2), naming both files: different sizes, a cube
// against a non-spectral image, emissive against reflective, different channel sets, different
// grids without options.resample. Channels of plain images are matched by name.
CompareStats compareImages(const ImageData& a, const ImageData& b, const CompareOptions& options);

// The statistics (without the per-pixel errors) as JSON; non-finite numbers as the strings
// "inf", "-inf", "nan" (JSON has no such numbers).
nlohmann::json statsToJson(const CompareStats& stats);

// Writes statsToJson(stats), with the keys of `extra` added, atomically (temp file + rename).
void writeStatsJson(const std::filesystem::path& path, const CompareStats& stats,
                    const nlohmann::json& extra = nlohmann::json::object());

}  // namespace metamer
