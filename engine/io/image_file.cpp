#include "io/image_file.h"

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/exr_file.h"
#include "io/png_file.h"

namespace metamer {

struct ImageFileWriter::Impl {
    std::filesystem::path path;
    ImageFile image;
    int bits = 8, nextRow = 0;
    AtomicOutput out;
    std::unique_ptr<PngWriter> png;  // .png: 8- or 16-bit counts
    std::unique_ptr<ExrWriter> exr;  // .exr: float, zip
    Impl(const std::filesystem::path& p, const ImageFile& i, int b) : path(p), image(i), bits(b), out(p) {}

    void check(int firstRow, int rows, size_t values) const {
        if (firstRow != nextRow || rows <= 0 || firstRow + rows > image.height ||
            values != size_t(image.width) * rows * image.channels.size())
            failRuntime("cannot write '{}': rows {}..{} with {} values do not continue a {}×{}×{} image at row {}",
                        path.string(), firstRow, firstRow + rows, values, image.width, image.height,
                        image.channels.size(), nextRow);
    }
};

ImageFileWriter::ImageFileWriter(const std::filesystem::path& path, const ImageFile& image, int bits)
    : impl_(std::make_unique<Impl>(path, image, bits)) {
    Impl& m = *impl_;
    const std::string ext = path.extension().string();
    if (ext == ".png") {
        if (bits != 8 && bits != 16) failRuntime("cannot write '{}': a PNG holds 8- or 16-bit counts, not {}", path.string(), bits);
        m.png = std::make_unique<PngWriter>(m.out.tempPath(), image.width, image.height, int(image.channels.size()),
                                            bits, image.attributes, image.iccProfile);
    } else if (ext == ".exr") {
        if (bits != 32) failRuntime("cannot write '{}': an EXR image here holds float32, not {} bits", path.string(), bits);
        StringAttributes a = image.attributes;
        a.push_back({"Software", "metamer"});
        ExrWriterExtras extras;
        extras.chromaticities = image.chromaticities;
        m.exr = std::make_unique<ExrWriter>(m.out.tempPath(), image.width, image.height, image.channels, false, "piz", a,
                                            extras);
    } else {
        failRuntime("cannot write '{}': images are written as .png or .exr", path.string());
    }
}

ImageFileWriter::~ImageFileWriter() = default;  // not committed: AtomicOutput removes the file

void ImageFileWriter::writeRows(int firstRow, int rows, const std::vector<uint16_t>& pixels) {
    Impl& m = *impl_;
    m.check(firstRow, rows, pixels.size());
    if (!m.png) failRuntime("cannot write '{}': counts go to a PNG", m.path.string());
    m.out.naming([&] { m.png->writeRows(firstRow, rows, pixels.data()); });
    m.nextRow = firstRow + rows;
}

void ImageFileWriter::writeRows(int firstRow, int rows, const std::vector<float>& pixels) {
    Impl& m = *impl_;
    m.check(firstRow, rows, pixels.size());
    if (!m.exr) failRuntime("cannot write '{}': float pixels go to an EXR", m.path.string());
    m.out.naming([&] { m.exr->writeRows(firstRow, rows, pixels.data()); });
    m.nextRow = firstRow + rows;
}

std::vector<AtomicOutput*> ImageFileWriter::finish() {
    Impl& m = *impl_;
    if (m.nextRow != m.image.height)
        failRuntime("cannot write '{}': {} of {} rows written", m.path.string(), m.nextRow, m.image.height);
    m.out.naming([&] {
        if (m.png) m.png->close();
        if (m.exr) m.exr->close();
    });
    return {&m.out};
}

void ImageFileWriter::commit() { commitTogether(finish()); }

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
