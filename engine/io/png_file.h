// PNG files through libpng: 8- or 16-bit grey, RGB or RGBA images with text metadata, written
// row by row and read whole. Display images, quick looks, masks, heat maps and plots are written
// with it (io/image_file); `metamer compare` and scene textures read with it (io/image_reader).
// Tests: engine/io/png_file_test.cpp.
#pragma once

#include "io/raster_image.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

// Writes `path` as it is (callers write a temporary name and rename, io/atomic_file). Text
// attributes become tEXt chunks (iTXt when the value is not ASCII); "ImageDescription" is stored
// under PNG's own keyword, "Description", and "oiio:ColorSpace" = "sRGB" as an sRGB chunk (with
// the gAMA and cHRM chunks that stand for it). An `iccProfile` goes into an iCCP chunk, for images
// in another colour space (a PNG has one or the other: both is a runtime error).
class PngWriter {
public:
    PngWriter(const std::filesystem::path& path, int width, int height, int channels, int bits,
              const std::vector<std::pair<std::string, std::string>>& attributes,
              const std::vector<uint8_t>& iccProfile = {});
    ~PngWriter();
    PngWriter(const PngWriter&) = delete;
    PngWriter& operator=(const PngWriter&) = delete;
    // `rows` rows of width × channels counts (0 … 2^bits − 1), in order.
    void writeRows(int firstRow, int rows, const uint16_t* counts);
    void close();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Reads a PNG (any bit depth, palette and grey expanded) as counts; channels are named Y, YA, RGB
// or RGBA as OpenImageIO names them. Input errors name `where`.
// `check` sees the header before the rows are decoded (io/raster_image.h).
RasterImage readPng(const std::filesystem::path& path, const Where& where, const ImageHeaderCheck& check = {});
RasterImage readPng(const std::vector<uint8_t>& bytes, const Where& where, const ImageHeaderCheck& check = {});

}  // namespace metamer
