// OpenEXR files through the OpenEXR library itself: scanline images of named float or half
// channels with string attributes, read whole or by channel, written strip by strip. Compression
// runs on OpenEXR's thread pool, one thread per core (16-scanline blocks in parallel). The
// spectral layout (io/spectral_exr) and the XYZ and response images (io/image_file) are built on
// it. Tests: engine/io/exr_file_test.cpp.
#pragma once

#include "core/error.h"

#include <cstdint>
#include <filesystem>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

using StringAttributes = std::vector<std::pair<std::string, std::string>>;

// OpenEXR's compressions by the names OpenImageIO and oiiotool use, with an optional level:
// none, rle, zips, zip[:1-9], piz, pxr24, b44, b44a, dwaa[:level], dwab[:level].
bool knownExrCompression(const std::string& name);
std::string exrCompressionNames();  // "none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa, dwab"

// What the R, G, B channels of an image mean: the CIE 1931 xy chromaticities of its primaries and
// white (OpenEXR's `chromaticities` attribute; absent, readers assume BT.709 primaries and D65).
struct ExrChromaticities {
    std::array<double, 2> red{}, green{}, blue{}, white{};
    bool operator==(const ExrChromaticities&) const = default;
};
// OpenEXR's convention for CIE XYZ stored in R, G, B: red (1, 0), green (0, 1), blue (0, 0),
// white (1/3, 1/3), so that X, Y, Z are R, G, B as they stand.
ExrChromaticities xyzChromaticities();
// Whether `c` is that convention, within the attribute's float32 precision.
bool isXyzChromaticities(const ExrChromaticities& c);

struct ExrHeader {
    int width = 0, height = 0;
    std::vector<std::string> channels;  // in the file's (alphabetical) order
    std::vector<bool> halfChannels;     // per channel: stored as half
    std::string compression;            // "zip", "piz", …
    StringAttributes attributes;        // the header's string attributes
    std::optional<ExrChromaticities> chromaticities;  // the `chromaticities` attribute, when present
};

// Reads the header of a flat scanline or tiled OpenEXR file. Input errors name `where`: not
// found, a folder, not OpenEXR, deep, multi-part.
ExrHeader readExrHeader(const std::filesystem::path& path, const Where& where);
// Reads `channels` (names in the file) as float, interleaved in the order given, row 0 at the top.
std::vector<float> readExrChannels(const std::filesystem::path& path, const std::vector<std::string>& channels,
                                   const Where& where);

// More than one buffer's worth of channels, and what R, G, B mean.
struct ExrWriterExtras {
    // Channels whose pixels come in a second buffer, interleaved in this order (a display preview's
    // R, G, B, A beside a cube's bands): writeRows' `extraPixels`.
    std::vector<std::string> extraChannels;
    std::optional<ExrChromaticities> chromaticities;  // written as the `chromaticities` attribute
};

// Writes a scanline OpenEXR file strip by strip (rows in order) to `path` as it is — the callers
// write to a temporary name and rename (io/atomic_file). Pixels are float, interleaved in the
// order of `channels`; `half` stores them as half (finite values beyond ±65504 become ±Inf:
// clamp first).
class ExrWriter {
public:
    ExrWriter(const std::filesystem::path& path, int width, int height, const std::vector<std::string>& channels,
              bool half, const std::string& compression, const StringAttributes& attributes,
              const ExrWriterExtras& extras = {});
    ~ExrWriter();
    ExrWriter(const ExrWriter&) = delete;
    ExrWriter& operator=(const ExrWriter&) = delete;
    // `extraPixels`: the rows of extras.extraChannels, interleaved; required when there are any.
    void writeRows(int firstRow, int rows, const float* pixels, const float* extraPixels = nullptr);
    // Flushes and closes the file; errors name the path.
    void close();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace metamer
