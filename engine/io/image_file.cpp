#include "io/image_file.h"

#include "core/error.h"
#include "io/atomic_file.h"

#include <OpenImageIO/imageio.h>

namespace metamer {

namespace {

void write(const std::filesystem::path& path, const ImageFile& image, OIIO::TypeDesc stored, OIIO::TypeDesc given,
           const void* pixels) {
    OIIO::ImageSpec spec(image.width, image.height, int(image.channels.size()), stored);
    spec.channelnames = image.channels;
    spec.attribute("Software", "metamer");
    for (const auto& [k, v] : image.attributes) spec.attribute(k, v);
    if (path.extension() == ".exr") spec.attribute("compression", "zip");

    AtomicOutput out(path);
    auto writer = OIIO::ImageOutput::create(out.tempPath().string());  // format from the extension
    if (!writer) failRuntime("cannot write '{}': {}", path.string(), OIIO::geterror());
    if (!writer->open(out.tempPath().string(), spec))
        failRuntime("cannot write '{}': {}", path.string(), writer->geterror());
    bool ok = writer->write_image(given, pixels);
    std::string err = ok ? "" : writer->geterror();
    if (!writer->close() && ok) {
        ok = false;
        err = writer->geterror();
    }
    if (!ok) failRuntime("cannot write '{}': {}", path.string(), err);
    out.commit();
}

void checkSize(const std::filesystem::path& path, const ImageFile& image, size_t values) {
    if (values != size_t(image.width) * image.height * image.channels.size())
        failRuntime("cannot write '{}': {} values for a {}×{}×{} image", path.string(), values, image.width,
                    image.height, image.channels.size());
}

}  // namespace

void writeImage(const std::filesystem::path& path, const ImageFile& image, const std::vector<uint16_t>& pixels,
                int bits) {
    checkSize(path, image, pixels.size());
    if (bits == 16) {
        write(path, image, OIIO::TypeDesc::UINT16, OIIO::TypeDesc::UINT16, pixels.data());
        return;
    }
    std::vector<uint8_t> narrow(pixels.begin(), pixels.end());
    write(path, image, OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT8, narrow.data());
}

void writeImage(const std::filesystem::path& path, const ImageFile& image, const std::vector<float>& pixels) {
    checkSize(path, image, pixels.size());
    write(path, image, OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::FLOAT, pixels.data());
}

}  // namespace metamer
