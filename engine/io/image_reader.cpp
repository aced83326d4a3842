#include "io/image_reader.h"

#include "core/file_reads.h"
#include "core/memory_limits.h"
#include "io/exr_file.h"
#include "io/oiio_module.h"
#include "io/png_file.h"

#include <cstring>
#include <fstream>

namespace fs = std::filesystem;

namespace metamer {

std::string imageSignature(const std::vector<uint8_t>& b) {
    if (b.size() >= 4 && b[0] == 0x76 && b[1] == 0x2f && b[2] == 0x31 && b[3] == 0x01) return "openexr";
    if (b.size() >= 8 && std::memcmp(b.data(), "\x89PNG\r\n\x1a\n", 8) == 0) return "png";
    if (b.size() >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff) return "jpeg";
    return "";
}

std::string imageSignature(const fs::path& path) {
    std::ifstream f(path, std::ios::binary);
    std::vector<uint8_t> head(8, 0);
    f.read(reinterpret_cast<char*>(head.data()), std::streamsize(head.size()));
    head.resize(size_t(std::max<std::streamsize>(0, f.gcount())));
    return imageSignature(head);
}

namespace {

// Before any pixel is decoded: the caller's check (its message says more: a texture's says the
// grid), then the machine's limit (float32 pixels plus, for integer formats, the decoder's buffer
// of the file's own samples).
ImageHeaderCheck sizeChecked(const Where& where, const ImageHeaderCheck& check) {
    return [where, check](const RasterImage& h) {
        if (check) check(h);
        const uint64_t fileBytes = h.floatingPoint ? 0 : uint64_t(std::max(1, (h.bits + 7) / 8));
        requireDecodableSize(uint64_t(std::max(0, h.width)), uint64_t(std::max(0, h.height)), h.channels.size(),
                             4 + fileBytes, 0, where, h.format.empty() ? std::string("the image") : "the " + h.format + " image");
    };
}

}  // namespace

RasterImage readRasterImage(const fs::path& path, const Where& where, const ImageHeaderCheck& userCheck) {
    requireRegularFile(path, where, "image");
    noteFileRead(path);
    const ImageHeaderCheck check = sizeChecked(where, userCheck);
    const std::string kind = imageSignature(path);
    if (kind == "png") return readPng(path, where, check);
    if (kind == "openexr") {
        const ExrHeader h = readExrHeader(path, where);
        RasterImage img;
        img.format = "openexr";
        img.width = h.width;
        img.height = h.height;
        img.channels = h.channels;
        // OpenEXR's XYZ convention (Metamer's .xyz.exr): R, G, B hold X, Y, Z, and are named so here.
        if (h.chromaticities && isXyzChromaticities(*h.chromaticities))
            for (std::string& c : img.channels) c = c == "R" ? "X" : c == "G" ? "Y" : c == "B" ? "Z" : c;
        img.floatingPoint = true;
        img.bits = !h.halfChannels.empty() && h.halfChannels[0] ? 16 : 32;
        img.attributes = h.attributes;
        check(img);
        img.pixels = readExrChannels(path, h.channels, where);  // the file's names, in img.channels' order
        return img;
    }
    return readWithOpenImageIO(path, where, check);
}

RasterImage readRasterImage(const std::vector<uint8_t>& bytes, const std::string& name, const Where& where,
                            const ImageHeaderCheck& userCheck) {
    const ImageHeaderCheck check = sizeChecked(where, userCheck);
    const std::string kind = imageSignature(bytes);
    if (kind == "png") return readPng(bytes, where, check);
    if (kind.empty()) failInput(where, "'{}' is not an image this reader knows from its first bytes", name);
    return readWithOpenImageIO(bytes, kind, where, check);
}

}  // namespace metamer
