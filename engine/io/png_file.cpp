#include "io/png_file.h"

#include <png.h>

#include <algorithm>
#include <cstring>

namespace fs = std::filesystem;

namespace metamer {

namespace {

// libpng reports errors by longjmp: every call into it below sits in a function of its own with
// setjmp and nothing to destroy, so no C++ frame is skipped. The message is kept for the caller.
void onError(png_structp png, png_const_charp message) {
    auto* error = static_cast<std::string*>(png_get_error_ptr(png));
    if (error) *error = message ? message : "libpng error";
    png_longjmp(png, 1);
}
void onWarning(png_structp, png_const_charp) {}

bool isAscii(const std::string& s) {
    return std::all_of(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) < 0x80; });
}

// PNG keywords are 1–79 Latin-1 characters.
std::string keywordOf(const std::string& name) {
    std::string k = name == "ImageDescription" ? "Description" : name;
    if (k.size() > 79) k.resize(79);
    return k;
}

bool writeHeader(png_structp png, png_infop info, png_uint_32 w, png_uint_32 h, int bits, int colorType,
                 png_textp text, int texts, bool srgb, const std::vector<uint8_t>& icc) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_set_IHDR(png, info, w, h, bits, colorType, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (texts > 0) png_set_text(png, info, text, texts);
    if (srgb) png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    if (!icc.empty())
        png_set_iCCP(png, info, "ICC profile", PNG_COMPRESSION_TYPE_BASE, icc.data(), png_uint_32(icc.size()));
    // Display images are smooth: zlib level 6 with adaptive filters costs little and halves the file.
    png_set_compression_level(png, 6);
    png_write_info(png, info);
    return true;
}

bool writeRow(png_structp png, png_bytep row) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_write_row(png, row);
    return true;
}

bool writeEnd(png_structp png, png_infop info) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_write_end(png, info);
    return true;
}

int colorTypeOf(int channels) {
    return channels == 1 ? PNG_COLOR_TYPE_GRAY
           : channels == 2 ? PNG_COLOR_TYPE_GRAY_ALPHA
           : channels == 3 ? PNG_COLOR_TYPE_RGB
                           : PNG_COLOR_TYPE_RGBA;
}

}  // namespace

struct PngWriter::Impl {
    fs::path path;
    FILE* file = nullptr;
    png_structp png = nullptr;
    png_infop info = nullptr;
    int width = 0, height = 0, channels = 0, bits = 8, nextRow = 0;
    std::string error;
    std::vector<png_byte> row;

    ~Impl() {
        if (png) png_destroy_write_struct(&png, &info);
        if (file) std::fclose(file);
    }
    [[noreturn]] void fail(const std::string& what) {
        failRuntime("cannot write '{}': {}", path.string(), what.empty() ? error : what);
    }
};

PngWriter::PngWriter(const fs::path& path, int width, int height, int channels, int bits,
                     const std::vector<std::pair<std::string, std::string>>& attributes,
                     const std::vector<uint8_t>& iccProfile)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.path = path;
    m.width = width;
    m.height = height;
    m.channels = channels;
    m.bits = bits;
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4 || (bits != 8 && bits != 16))
        m.fail(fmt::format("a {}×{} PNG of {} channels at {} bits", width, height, channels, bits));
    m.file = std::fopen(path.c_str(), "wb");
    if (!m.file) m.fail(std::strerror(errno));
    m.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &m.error, onError, onWarning);
    if (m.png) m.info = png_create_info_struct(m.png);
    if (!m.png || !m.info) m.fail("libpng could not start");
    png_init_io(m.png, m.file);

    // Text chunks: the strings live in `keys` and `values` until png_write_info has copied them.
    std::vector<std::string> keys, values;
    bool srgb = false;
    for (const auto& [k, v] : attributes) {
        if (k == "oiio:ColorSpace") {
            srgb = v == "sRGB";
            continue;
        }
        keys.push_back(keywordOf(k));
        values.push_back(v);
    }
    keys.push_back("Software");
    values.push_back("metamer");
    std::vector<png_text> text(keys.size());
    for (size_t i = 0; i < keys.size(); ++i) {
        text[i] = {};
        text[i].compression = isAscii(values[i]) ? PNG_TEXT_COMPRESSION_NONE : PNG_ITXT_COMPRESSION_NONE;
        text[i].key = keys[i].data();
        text[i].text = values[i].data();
        text[i].text_length = values[i].size();
    }
    if (srgb && !iccProfile.empty()) m.fail("an sRGB chunk and an ICC profile both asked for; a PNG holds one");
    if (!writeHeader(m.png, m.info, png_uint_32(width), png_uint_32(height), bits, colorTypeOf(channels), text.data(),
                     int(text.size()), srgb, iccProfile))
        m.fail("");
    m.row.resize(size_t(width) * channels * (bits / 8));
}

PngWriter::~PngWriter() = default;

void PngWriter::writeRows(int firstRow, int rows, const uint16_t* counts) {
    Impl& m = *impl_;
    if (!m.png || firstRow != m.nextRow || rows <= 0 || firstRow + rows > m.height)
        failRuntime("cannot write '{}': rows {}..{} do not continue a {}-row image at row {}", m.path.string(), firstRow,
                    firstRow + rows, m.height, m.nextRow);
    const size_t values = size_t(m.width) * m.channels;
    for (int r = 0; r < rows; ++r) {
        const uint16_t* src = counts + size_t(r) * values;
        if (m.bits == 16) {
            for (size_t i = 0; i < values; ++i) {  // PNG's samples are big-endian
                m.row[2 * i] = png_byte(src[i] >> 8);
                m.row[2 * i + 1] = png_byte(src[i] & 0xff);
            }
        } else {
            for (size_t i = 0; i < values; ++i) m.row[i] = png_byte(std::min<uint16_t>(src[i], 255));
        }
        if (!writeRow(m.png, m.row.data())) m.fail("");
    }
    m.nextRow = firstRow + rows;
}

void PngWriter::close() {
    Impl& m = *impl_;
    if (!m.png) return;
    if (!writeEnd(m.png, m.info)) m.fail("");
    png_destroy_write_struct(&m.png, &m.info);
    m.png = nullptr;
    const bool flushed = std::fflush(m.file) == 0;
    const bool closed = std::fclose(m.file) == 0;
    m.file = nullptr;
    if (!flushed || !closed) m.fail(std::strerror(errno));
}

namespace {

struct MemoryReader {
    const std::vector<uint8_t>* bytes;
    size_t at = 0;
};

void readFromMemory(png_structp png, png_bytep out, png_size_t n) {
    auto* r = static_cast<MemoryReader*>(png_get_io_ptr(png));
    if (r->at + n > r->bytes->size()) png_error(png, "the image ends early");
    std::memcpy(out, r->bytes->data() + r->at, n);
    r->at += n;
}

struct ReadState {
    png_uint_32 width = 0, height = 0;
    int bits = 0, channels = 0;
    png_textp text = nullptr;
    int texts = 0;
};

// Header, expansions (palette and low-bit grey to 8 bits, transparency to alpha, 16-bit to host
// order), then the rows into `rows` (sized by the caller from `s` after readHeader).
bool readHeader(png_structp png, png_infop info, ReadState& s) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_read_info(png, info);
    png_set_expand(png);
    if (png_get_bit_depth(png, info) == 16) png_set_swap(png);
    png_read_update_info(png, info);
    s.width = png_get_image_width(png, info);
    s.height = png_get_image_height(png, info);
    s.bits = png_get_bit_depth(png, info);
    s.channels = png_get_channels(png, info);
    png_get_text(png, info, &s.text, &s.texts);
    return true;
}

bool readRows(png_structp png, png_bytepp rows) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_read_image(png, rows);
    return true;
}

RasterImage readPngWith(const Where& where, FILE* file, const std::vector<uint8_t>* bytes,
                        const ImageHeaderCheck& check) {
    std::string error;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error, onError, onWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    struct Guard {
        png_structp& png;
        png_infop& info;
        ~Guard() {
            if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
        }
    } guard{png, info};
    if (!png || !info) failInput(where, "not a readable PNG: libpng could not start");
    MemoryReader memory{bytes};
    if (file) png_init_io(png, file);
    else png_set_read_fn(png, &memory, readFromMemory);
    ReadState s;
    if (!readHeader(png, info, s)) failInput(where, "not a readable PNG: {}", error);
    if (s.width == 0 || s.height == 0 || s.width > 65536 || s.height > 65536)
        failInput(where, "a {}×{} PNG is not a usable image", s.width, s.height);
    RasterImage img;
    img.format = "png";
    img.width = int(s.width);
    img.height = int(s.height);
    img.bits = s.bits;
    static const std::vector<std::string> names[] = {{"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
    img.channels = names[std::clamp(s.channels, 1, 4) - 1];
    for (int i = 0; i < s.texts; ++i) {
        std::string key = s.text[i].key ? s.text[i].key : "";
        img.attributes.push_back({key == "Description" ? "ImageDescription" : key,
                                  std::string(s.text[i].text ? s.text[i].text : "")});  // iTXt has no text_length
    }
    if (check) check(img);
    const size_t rowBytes = size_t(s.width) * s.channels * (s.bits / 8);
    std::vector<png_byte> data(rowBytes * s.height);
    std::vector<png_bytep> rows(s.height);
    for (png_uint_32 y = 0; y < s.height; ++y) rows[y] = data.data() + y * rowBytes;
    if (!readRows(png, rows.data())) failInput(where, "cannot read pixels: {}", error);
    const size_t values = size_t(s.width) * s.height * s.channels;
    img.pixels.resize(values);
    if (s.bits == 16) {
        const auto* v = reinterpret_cast<const uint16_t*>(data.data());
        for (size_t i = 0; i < values; ++i) img.pixels[i] = float(v[i]);
    } else {
        for (size_t i = 0; i < values; ++i) img.pixels[i] = float(data[i]);
    }
    return img;
}

}  // namespace

RasterImage readPng(const fs::path& path, const Where& where, const ImageHeaderCheck& check) {
    FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) failInput(where, "cannot open: {}", std::strerror(errno));
    struct Close {
        FILE* f;
        ~Close() { std::fclose(f); }
    } close{f};
    return readPngWith(where, f, nullptr, check);
}

RasterImage readPng(const std::vector<uint8_t>& bytes, const Where& where, const ImageHeaderCheck& check) {
    return readPngWith(where, nullptr, &bytes, check);
}

}  // namespace metamer
