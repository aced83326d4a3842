#include "io/exr_file.h"

#include "core/cpu_count.h"
#include "core/file_reads.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfStandardAttributes.h>
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
#include <cmath>
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

ExrChromaticities xyzChromaticities() { return {{1.0, 0.0}, {0.0, 1.0}, {0.0, 0.0}, {1.0 / 3.0, 1.0 / 3.0}}; }

bool isXyzChromaticities(const ExrChromaticities& c) {
    const ExrChromaticities x = xyzChromaticities();
    auto near = [](const std::array<double, 2>& a, const std::array<double, 2>& b) {
        return std::fabs(a[0] - b[0]) < 1e-6 && std::fabs(a[1] - b[1]) < 1e-6;  // the attribute is float32
    };
    return near(c.red, x.red) && near(c.green, x.green) && near(c.blue, x.blue) && near(c.white, x.white);
}

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
        if (Imf::hasChromaticities(h)) {
            const Imf::Chromaticities& c = Imf::chromaticities(h);
            auto xy = [](const Imath::V2f& v) { return std::array<double, 2>{v.x, v.y}; };
            out.chromaticities = ExrChromaticities{xy(c.red), xy(c.green), xy(c.blue), xy(c.white)};
        }
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
    std::vector<std::string> channels, extraChannels;
    // half: the strip converted (OpenEXR writes a frame buffer's own type), the extras after it
    std::vector<Imath::half> halves;
    std::unique_ptr<Imf::OutputFile> file;
};

ExrWriter::ExrWriter(const fs::path& path, int width, int height, const std::vector<std::string>& channels, bool half,
                     const std::string& compression, const StringAttributes& attributes, const ExrWriterExtras& extras)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.path = path;
    m.width = width;
    m.height = height;
    m.channels = channels;
    m.extraChannels = extras.extraChannels;
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
        for (const auto& name : extras.extraChannels) {
            if (h.channels().findChannel(name))
                failRuntime("cannot write '{}': channel '{}' is named twice", path.string(), name);
            h.channels().insert(name, Imf::Channel(half ? Imf::HALF : Imf::FLOAT));
        }
        for (const auto& [key, value] : attributes) h.insert(key, Imf::StringAttribute(value));
        if (const auto& c = extras.chromaticities) {
            auto xy = [](const std::array<double, 2>& v) { return Imath::V2f(float(v[0]), float(v[1])); };
            Imf::addChromaticities(h, Imf::Chromaticities(xy(c->red), xy(c->green), xy(c->blue), xy(c->white)));
        }
        m.file = std::make_unique<Imf::OutputFile>(path.c_str(), h);
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        failRuntime("cannot write '{}': {}", path.string(), e.what());
    }
}

ExrWriter::~ExrWriter() = default;

void ExrWriter::writeRows(int firstRow, int rows, const float* pixels, const float* extraPixels) {
    Impl& m = *impl_;
    if (!m.file || firstRow != m.nextRow || rows <= 0 || firstRow + rows > m.height)
        failRuntime("cannot write '{}': rows {}..{} do not continue a {}-row image at row {}", m.path.string(), firstRow,
                    firstRow + rows, m.height, m.nextRow);
    if (!m.extraChannels.empty() && !extraPixels)
        failRuntime("cannot write '{}': rows {}..{} come without their {} channels", m.path.string(), firstRow,
                    firstRow + rows, m.extraChannels.front());
    const size_t n = m.channels.size(), extras = m.extraChannels.size();
    const size_t count = size_t(m.width) * rows * n, extraCount = size_t(m.width) * rows * extras;
    const char* data = reinterpret_cast<const char*>(pixels);
    const char* extraData = reinterpret_cast<const char*>(extraPixels);
    size_t sample = sizeof(float);
    if (m.half) {
        m.halves.resize(count + extraCount);
        for (size_t i = 0; i < count; ++i) m.halves[i] = Imath::half(pixels[i]);
        for (size_t i = 0; i < extraCount; ++i) m.halves[count + i] = Imath::half(extraPixels[i]);
        data = reinterpret_cast<const char*>(m.halves.data());
        extraData = reinterpret_cast<const char*>(m.halves.data() + count);
        sample = sizeof(Imath::half);
    }
    const Imf::PixelType type = m.half ? Imf::HALF : Imf::FLOAT;
    try {
        Imf::FrameBuffer fb;
        // Each buffer's channels as slices; the strip's first row is row `firstRow` of the image,
        // so the base is shifted for OpenEXR to find it there.
        auto insert = [&](const std::vector<std::string>& names, const char* buffer) {
            const size_t xStride = names.size() * sample, yStride = size_t(m.width) * xStride;
            const char* base = buffer - ptrdiff_t(firstRow) * ptrdiff_t(yStride);
            for (size_t c = 0; c < names.size(); ++c)
                fb.insert(names[c], Imf::Slice(type, const_cast<char*>(base) + c * sample, xStride, yStride));
        };
        insert(m.channels, data);
        if (extras) insert(m.extraChannels, extraData);
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
