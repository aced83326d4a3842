#include "io/exr_file.h"

#include "core/cpu_count.h"
#include "core/file_reads.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <OpenEXR/ImfThreading.h>
#include <Imath/half.h>

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <thread>

namespace fs = std::filesystem;

namespace metamer {

namespace {

struct CompressionName {
    const char* name;
    Imf::Compression value;
};
const CompressionName kCompressions[] = {
    {"none", Imf::NO_COMPRESSION}, {"rle", Imf::RLE_COMPRESSION},   {"zips", Imf::ZIPS_COMPRESSION},
    {"zip", Imf::ZIP_COMPRESSION}, {"piz", Imf::PIZ_COMPRESSION},   {"pxr24", Imf::PXR24_COMPRESSION},
    {"b44", Imf::B44_COMPRESSION}, {"b44a", Imf::B44A_COMPRESSION}, {"dwaa", Imf::DWAA_COMPRESSION},
    {"dwab", Imf::DWAB_COMPRESSION},
};

const CompressionName* compressionOf(const std::string& name) {
    const std::string base = name.substr(0, name.find(':'));
    for (const auto& c : kCompressions)
        if (base == c.name) return &c;
    return nullptr;
}

// OpenEXR compresses (and decompresses) line blocks on a global thread pool: one thread per CPU this
// process was given (core/cpu_count.h).
void useEveryCore() {
    static std::once_flag once;
    std::call_once(once, [] { Imf::setGlobalThreadCount(usableCpuCount()); });
}

}  // namespace

bool knownExrCompression(const std::string& name) {
    const CompressionName* c = compressionOf(name);
    if (!c) return false;
    const size_t colon = name.find(':');
    if (colon == std::string::npos) return true;
    // A level: zip and zips take zlib's 1–9, DWA a positive quality.
    char* end = nullptr;
    const double level = std::strtod(name.c_str() + colon + 1, &end);
    if (end == name.c_str() + colon + 1 || *end) return false;
    if (c->value == Imf::ZIP_COMPRESSION || c->value == Imf::ZIPS_COMPRESSION)
        return level >= 1 && level <= 9 && level == double(int(level));
    return (c->value == Imf::DWAA_COMPRESSION || c->value == Imf::DWAB_COMPRESSION) && level > 0;
}

std::string exrCompressionNames() {
    std::string s;
    for (const auto& c : kCompressions) s += (s.empty() ? "" : ", ") + std::string(c.name);
    return s;
}

ExrHeader readExrHeader(const fs::path& path, const Where& where) {
    requireRegularFile(path, where, "OpenEXR file");
    noteFileRead(path);
    bool tiled = false, deep = false, multiPart = false;
    if (!Imf::isOpenExrFile(path.c_str(), tiled, deep, multiPart))
        failInput(where, "not a readable OpenEXR file (it does not start with OpenEXR's signature)");
    if (deep) failInput(where, "deep OpenEXR images are not supported");
    if (multiPart) failInput(where, "multi-part OpenEXR files are not supported");
    useEveryCore();
    try {
        Imf::InputFile in(path.c_str());
        const Imf::Header& h = in.header();
        const Imath::Box2i dw = h.dataWindow();
        ExrHeader out;
        out.width = dw.max.x - dw.min.x + 1;
        out.height = dw.max.y - dw.min.y + 1;
        for (auto c = h.channels().begin(); c != h.channels().end(); ++c) {
            out.channels.push_back(c.name());
            out.halfChannels.push_back(c.channel().type == Imf::HALF);
        }
        for (const auto& c : kCompressions)
            if (c.value == h.compression()) out.compression = c.name;
        for (auto a = h.begin(); a != h.end(); ++a)
            if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&a.attribute()))
                out.attributes.push_back({a.name(), s->value()});
        return out;
    } catch (const std::exception& e) {
        failInput(where, "not a readable OpenEXR file: {}", e.what());
    }
}

std::vector<float> readExrChannels(const fs::path& path, const std::vector<std::string>& channels,
                                   const Where& where) {
    noteFileRead(path);
    useEveryCore();
    try {
        Imf::InputFile in(path.c_str());
        const Imath::Box2i dw = in.header().dataWindow();
        const size_t width = size_t(dw.max.x - dw.min.x + 1), height = size_t(dw.max.y - dw.min.y + 1);
        const size_t n = channels.size();
        std::vector<float> pixels(width * height * n);
        Imf::FrameBuffer fb;
        const size_t xStride = n * sizeof(float), yStride = width * xStride;
        // OpenEXR addresses the buffer by data-window coordinates: shift the base to (min.x, min.y).
        char* base = reinterpret_cast<char*>(pixels.data()) - ptrdiff_t(dw.min.x) * ptrdiff_t(xStride) -
                     ptrdiff_t(dw.min.y) * ptrdiff_t(yStride);
        for (size_t c = 0; c < n; ++c) {
            if (!in.header().channels().findChannel(channels[c]))
                failInput(where, "has no channel '{}'", channels[c]);
            fb.insert(channels[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xStride, yStride));
        }
        in.setFrameBuffer(fb);
        in.readPixels(dw.min.y, dw.max.y);
        return pixels;
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        failInput(where, "cannot read pixels: {}", e.what());
    }
}

struct ExrWriter::Impl {
    fs::path path;
    int width = 0, height = 0, nextRow = 0;
    bool half = false;
    std::vector<std::string> channels;
    std::vector<Imath::half> halves;  // half: the strip converted (OpenEXR writes a frame buffer's own type)
    std::unique_ptr<Imf::OutputFile> file;
};

ExrWriter::ExrWriter(const fs::path& path, int width, int height, const std::vector<std::string>& channels, bool half,
                     const std::string& compression, const StringAttributes& attributes)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.path = path;
    m.width = width;
    m.height = height;
    m.channels = channels;
    m.half = half;
    const CompressionName* c = compressionOf(compression);
    if (!c || !knownExrCompression(compression))
        failInput(Where{"", "compression"}, "unknown OpenEXR compression '{}' ({})", compression, exrCompressionNames());
    useEveryCore();
    try {
        Imf::Header h(width, height);
        h.compression() = c->value;
        if (const size_t colon = compression.find(':'); colon != std::string::npos) {
            const double level = std::strtod(compression.c_str() + colon + 1, nullptr);
            if (c->value == Imf::ZIP_COMPRESSION || c->value == Imf::ZIPS_COMPRESSION) h.zipCompressionLevel() = int(level);
            else h.dwaCompressionLevel() = float(level);
        }
        for (const auto& name : channels) h.channels().insert(name, Imf::Channel(half ? Imf::HALF : Imf::FLOAT));
        for (const auto& [key, value] : attributes) h.insert(key, Imf::StringAttribute(value));
        m.file = std::make_unique<Imf::OutputFile>(path.c_str(), h);
    } catch (const std::exception& e) {
        failRuntime("cannot write '{}': {}", path.string(), e.what());
    }
}

ExrWriter::~ExrWriter() = default;

void ExrWriter::writeRows(int firstRow, int rows, const float* pixels) {
    Impl& m = *impl_;
    if (!m.file || firstRow != m.nextRow || rows <= 0 || firstRow + rows > m.height)
        failRuntime("cannot write '{}': rows {}..{} do not continue a {}-row image at row {}", m.path.string(), firstRow,
                    firstRow + rows, m.height, m.nextRow);
    const size_t n = m.channels.size();
    const char* data = reinterpret_cast<const char*>(pixels);
    size_t sample = sizeof(float);
    if (m.half) {
        const size_t count = size_t(m.width) * rows * n;
        m.halves.resize(count);
        for (size_t i = 0; i < count; ++i) m.halves[i] = Imath::half(pixels[i]);
        data = reinterpret_cast<const char*>(m.halves.data());
        sample = sizeof(Imath::half);
    }
    const size_t xStride = n * sample, yStride = size_t(m.width) * xStride;
    // The strip's first row is row `firstRow` of the image: shift the base so OpenEXR finds it there.
    const char* base = data - ptrdiff_t(firstRow) * ptrdiff_t(yStride);
    const Imf::PixelType type = m.half ? Imf::HALF : Imf::FLOAT;
    try {
        Imf::FrameBuffer fb;
        for (size_t c = 0; c < n; ++c)
            fb.insert(m.channels[c], Imf::Slice(type, const_cast<char*>(base) + c * sample, xStride, yStride));
        m.file->setFrameBuffer(fb);
        m.file->writePixels(rows);
    } catch (const std::exception& e) {
        failRuntime("cannot write '{}': {}", m.path.string(), e.what());
    }
    m.nextRow = firstRow + rows;
}

void ExrWriter::close() {
    Impl& m = *impl_;
    try {
        m.file.reset();  // OpenEXR writes the line offset table when the file is destroyed
    } catch (const std::exception& e) {
        failRuntime("cannot write '{}': {}", m.path.string(), e.what());
    }
}

}  // namespace metamer
