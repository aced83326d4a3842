// An image as read from a file, whatever its format: the type every image reader returns
// (io/exr_file, io/png_file, io/oiio_module). Which reader reads a file is io/image_reader.h.
// Tests: engine/io/raster_image_test.cpp.
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

}  // namespace metamer
