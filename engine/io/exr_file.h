// OpenEXR files through the OpenEXR library itself: scanline images of named float or half
// channels with string attributes, read whole or by channel, written strip by strip. Compression
// runs on OpenEXR's thread pool, one thread per core (16-scanline blocks in parallel). The
// spectral layout (io/spectral_exr) and the XYZ and response images (io/image_file) are built on
// it. Tests: engine/io/exr_file_test.cpp.
#pragma once

#include "core/error.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

using StringAttributes = std::vector<std::pair<std::string, std::string>>;

// OpenEXR's compressions by the names OpenImageIO and oiiotool use, with an optional level:
// none, rle, zips, zip[:1-9], piz, pxr24, b44, b44a, dwaa[:level], dwab[:level].
bool knownExrCompression(const std::string& name);
std::string exrCompressionNames();  // "none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa, dwab"

struct ExrHeader {
    int width = 0, height = 0;
    std::vector<std::string> channels;  // in the file's (alphabetical) order
    std::vector<bool> halfChannels;     // per channel: stored as half
    std::string compression;            // "zip", "piz", …
    StringAttributes attributes;        // the header's string attributes
};

// Reads the header of a flat scanline or tiled OpenEXR file. Input errors name `where`: not
// found, a folder, not OpenEXR, deep, multi-part.
ExrHeader readExrHeader(const std::filesystem::path& path, const Where& where);
// Reads `channels` (names in the file) as float, interleaved in the order given, row 0 at the top.
std::vector<float> readExrChannels(const std::filesystem::path& path, const std::vector<std::string>& channels,
                                   const Where& where);

// Writes a scanline OpenEXR file strip by strip (rows in order) to `path` as it is — the callers
// write to a temporary name and rename (io/atomic_file). Pixels are float, interleaved in the
// order of `channels`; `half` stores them as half (finite values beyond ±65504 become ±Inf:
// clamp first).
class ExrWriter {
public:
    ExrWriter(const std::filesystem::path& path, int width, int height, const std::vector<std::string>& channels,
              bool half, const std::string& compression, const StringAttributes& attributes);
    ~ExrWriter();
    ExrWriter(const ExrWriter&) = delete;
    ExrWriter& operator=(const ExrWriter&) = delete;
    void writeRows(int firstRow, int rows, const float* pixels);
    // Flushes and closes the file; errors name the path.
    void close();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace metamer
