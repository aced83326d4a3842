// An image as read from a file, whatever its format, and the one reader that picks the library by
// the file's signature: OpenEXR for EXR (io/exr_file), libpng for PNG (io/png_file), and
// OpenImageIO for every other format — loaded only then (io/oiio_module), since loading it costs a
// process about 0.3 s (docs/performance.md, "Start-up"). Scene textures and `metamer compare`
// read through it. Tests: engine/io/raster_image_test.cpp.
#pragma once

#include "core/error.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

struct RasterImage {
    std::string format;  // "openexr", "png", or OpenImageIO's name for it ("jpeg", "tiff", …)
    int width = 0, height = 0;
    std::vector<std::string> channels;  // names, in the file's order ("R", "G", "B"; "Y" for grey)
    // width × height × channels, interleaved, row 0 at the top. Integer formats hold their counts
    // (0 … 2^bits − 1), floating-point ones their values.
    std::vector<float> pixels;
    bool floatingPoint = false;
    int bits = 32;  // per sample
    std::vector<std::pair<std::string, std::string>> attributes;  // string metadata

    // The attribute's value, or "" without it.
    std::string attribute(const std::string& name) const;
    // Integer counts scaled to 0 … 1 (floating-point values unchanged).
    float normalized(size_t i) const;
};

// Called with an image's header (everything but the pixels, still empty) before its pixels are
// decoded; throws to refuse it (a texture too large for the grid). Every read then refuses, from
// the header, an image whose decoding would take more than a quarter of the machine's memory
// (core/memory_limits.h requireDecodableSize).
using ImageHeaderCheck = std::function<void(const RasterImage& header)>;

// The file's format told by its first bytes: "openexr", "png", "jpeg", or "" (anything else).
std::string imageSignature(const std::filesystem::path& path);
std::string imageSignature(const std::vector<uint8_t>& bytes);

// Reads an image; input errors (missing, unreadable, damaged, deep, volume or too large to decode)
// name `where`.
RasterImage readRasterImage(const std::filesystem::path& path, const Where& where, const ImageHeaderCheck& check = {});
// The same from bytes in memory (a glTF's embedded PNG or JPEG); `name` is for messages.
RasterImage readRasterImage(const std::vector<uint8_t>& bytes, const std::string& name, const Where& where,
                            const ImageHeaderCheck& check = {});

}  // namespace metamer
