// The one image reader that picks the library by the file's signature: OpenEXR for EXR
// (io/exr_file), libpng for PNG (io/png_file), and OpenImageIO for every other format — loaded
// only then (io/oiio_module), since loading it costs a process about 0.3 s (docs/performance.md,
// "Start-up"). Scene textures and `metamer compare` read through it; the image type is
// io/raster_image.h. Tests: engine/io/raster_image_test.cpp.
#pragma once

#include "core/error.h"
#include "io/raster_image.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace metamer {

// The file's format told by its first bytes: "openexr", "png", "jpeg", or "" (anything else).
std::string imageSignature(const std::filesystem::path& path);
std::string imageSignature(const std::vector<uint8_t>& bytes);

// Reads an image; an OpenEXR file with the XYZ chromaticities (io/exr_file.h) has its R, G, B
// channels named X, Y, Z. Input errors (missing, unreadable, damaged, deep, volume or too large to decode)
// name `where`.
RasterImage readRasterImage(const std::filesystem::path& path, const Where& where, const ImageHeaderCheck& check = {});
// The same from bytes in memory (a glTF's embedded PNG or JPEG); `name` is for messages.
RasterImage readRasterImage(const std::vector<uint8_t>& bytes, const std::string& name, const Where& where,
                            const ImageHeaderCheck& check = {});

}  // namespace metamer
