#include "io/image_file.h"

#include "core/error.h"
#include "io/atomic_file.h"

#include <OpenImageIO/imageio.h>

namespace metamer {

struct ImageFileWriter::Impl {
    std::filesystem::path path;
    ImageFile image;
    int bits = 8, nextRow = 0;
    AtomicOutput out;
    std::unique_ptr<OIIO::ImageOutput> writer;
    std::vector<uint8_t> narrow;
    Impl(const std::filesystem::path& p, const ImageFile& i, int b) : path(p), image(i), bits(b), out(p) {}

    void write(int firstRow, int rows, size_t values, OIIO::TypeDesc type, const void* pixels) {
        if (firstRow != nextRow || rows <= 0 || firstRow + rows > image.height ||
            values != size_t(image.width) * rows * image.channels.size())
            failRuntime("cannot write '{}': rows {}..{} with {} values do not continue a {}×{}×{} image at row {}",
                        path.string(), firstRow, firstRow + rows, values, image.width, image.height,
                        image.channels.size(), nextRow);
        bool ok = rows == image.height ? writer->write_image(type, pixels)
                                       : writer->write_scanlines(firstRow, firstRow + rows, 0, type, pixels);
        if (!ok) failRuntime("cannot write '{}': {}", path.string(), writer->geterror());
        nextRow = firstRow + rows;
    }
};

ImageFileWriter::ImageFileWriter(const std::filesystem::path& path, const ImageFile& image, int bits)
    : impl_(std::make_unique<Impl>(path, image, bits)) {
    OIIO::TypeDesc stored = bits == 16 ? OIIO::TypeDesc::UINT16 : bits == 8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
    OIIO::ImageSpec spec(image.width, image.height, int(image.channels.size()), stored);
    spec.channelnames = image.channels;
    spec.attribute("Software", "metamer");
    for (const auto& [k, v] : image.attributes) spec.attribute(k, v);
    if (path.extension() == ".exr") spec.attribute("compression", "zip");
    impl_->writer = OIIO::ImageOutput::create(impl_->out.tempPath().string());  // format from the extension
    if (!impl_->writer) failRuntime("cannot write '{}': {}", path.string(), OIIO::geterror());
    if (!impl_->writer->open(impl_->out.tempPath().string(), spec))
        failRuntime("cannot write '{}': {}", path.string(), impl_->writer->geterror());
}

ImageFileWriter::~ImageFileWriter() {
    if (impl_ && impl_->writer) impl_->writer->close();  // not committed: AtomicOutput removes the file
}

void ImageFileWriter::writeRows(int firstRow, int rows, const std::vector<uint16_t>& pixels) {
    if (impl_->bits == 16) {
        impl_->write(firstRow, rows, pixels.size(), OIIO::TypeDesc::UINT16, pixels.data());
        return;
    }
    impl_->narrow.assign(pixels.begin(), pixels.end());
    impl_->write(firstRow, rows, pixels.size(), OIIO::TypeDesc::UINT8, impl_->narrow.data());
}

void ImageFileWriter::writeRows(int firstRow, int rows, const std::vector<float>& pixels) {
    impl_->write(firstRow, rows, pixels.size(), OIIO::TypeDesc::FLOAT, pixels.data());
}

void ImageFileWriter::commit() {
    Impl& m = *impl_;
    if (m.nextRow != m.image.height)
        failRuntime("cannot write '{}': {} of {} rows written", m.path.string(), m.nextRow, m.image.height);
    bool ok = m.writer->close();
    std::string err = ok ? "" : m.writer->geterror();
    m.writer.reset();
    if (!ok) failRuntime("cannot write '{}': {}", m.path.string(), err);
    m.out.commit();
}

void writeImage(const std::filesystem::path& path, const ImageFile& image, const std::vector<uint16_t>& pixels,
                int bits) {
    ImageFileWriter w(path, image, bits);
    w.writeRows(0, image.height, pixels);
    w.commit();
}

void writeImage(const std::filesystem::path& path, const ImageFile& image, const std::vector<float>& pixels) {
    ImageFileWriter w(path, image, 32);
    w.writeRows(0, image.height, pixels);
    w.commit();
}

}  // namespace metamer
