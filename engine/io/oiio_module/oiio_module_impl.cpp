// libmetamer_oiio.so: everything Metamer asks of OpenImageIO, behind io/oiio_module.h's table.
// Built as a module of its own so that only processes that need it load OpenImageIO's ~260
// libraries; it uses no other part of the engine (only the plain structs of that header).
#include "io/oiio_module.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <cmath>

namespace metamer {
namespace {

// OpenImageIO's message on one line (its decoders' messages may hold several).
std::string oneLine(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    for (size_t i = 0; (i = text.find('\n', i)) != std::string::npos;) text.replace(i, 1, "; ");
    return text;
}

// The spec and pixels of an open image; integer pixels as counts (OpenImageIO hands them over as
// 0 … 1).
std::string readOpen(OIIO::ImageInput& in, RasterImage& out, bool headerOnly) {
    const OIIO::ImageSpec& spec = in.spec();
    if (spec.deep) return "deep images are not supported";
    if (spec.depth > 1) return "volume images are not supported";
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) return "an empty image";
    out.format = in.format_name();
    out.width = spec.width;
    out.height = spec.height;
    out.channels = spec.channelnames;
    out.floatingPoint = spec.format.is_floating_point();
    out.bits = spec.get_int_attribute("oiio:BitsPerSample", int(spec.format.size() * 8));
    for (const auto& p : spec.extra_attribs)
        if (p.type() == OIIO::TypeDesc::STRING) out.attributes.push_back({p.name().string(), p.get_string()});
    if (headerOnly) return "";
    out.pixels.resize(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in.read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, out.pixels.data()))
        return "cannot read pixels: " + oneLine(in.geterror());
    // A decoder may meet damage and still succeed: libjpeg fills the rows of a truncated JPEG with
    // grey and warns. What it reported is damage, not a picture.
    if (in.has_error()) return "damaged image data: " + oneLine(in.geterror());
    if (!out.floatingPoint) {
        const double maxCount = std::ldexp(1.0, out.bits) - 1.0;
        for (float& v : out.pixels) v = float(std::round(double(v) * maxCount));
    }
    return "";
}

std::string readFile(const std::string& path, RasterImage& out, bool headerOnly) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return "not a readable image: " + oneLine(OIIO::geterror());
    return readOpen(*in, out, headerOnly);
}

std::string readMemory(const std::vector<uint8_t>& bytes, const std::string& format, RasterImage& out,
                       bool headerOnly) {
    OIIO::Filesystem::IOMemReader memory(const_cast<unsigned char*>(bytes.data()), bytes.size());
    auto in = OIIO::ImageInput::create(format);
    OIIO::ImageSpec spec;
    if (!in || !in->set_ioproxy(&memory) || !in->open("memory." + format, spec))
        return "not a readable image: " + oneLine(in ? in->geterror() : OIIO::geterror());
    return readOpen(*in, out, headerOnly);
}

class OiioCanvas final : public ImageCanvas {
public:
    OiioCanvas(int w, int h, std::string font) : font_(std::move(font)) {
        buf_.reset(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT));
        OIIO::ImageBufAlgo::fill(buf_, {1.0f, 1.0f, 1.0f});
    }
    void line(int x0, int y0, int x1, int y1, const Color& c) override {
        OIIO::ImageBufAlgo::render_line(buf_, x0, y0, x1, y1, c);
    }
    void box(int x0, int y0, int x1, int y1, const Color& c, bool fill) override {
        OIIO::ImageBufAlgo::render_box(buf_, x0, y0, x1, y1, c, fill);
    }
    bool textBox(const std::string& s, int size, int& x0, int& y0, int& x1, int& y1) const override {
        if (font_.empty()) return false;
        OIIO::ROI r = OIIO::ImageBufAlgo::text_size(s, size, font_);
        if (!r.defined()) return false;
        x0 = r.xbegin;
        y0 = r.ybegin;
        x1 = r.xend - 1;
        y1 = r.yend - 1;
        return true;
    }
    void text(const std::string& s, int x, int y, int size, const Color& c, AlignX ax, AlignY ay) override {
        using TX = OIIO::ImageBufAlgo::TextAlignX;
        using TY = OIIO::ImageBufAlgo::TextAlignY;
        const TX tx = ax == AlignX::Right ? TX::Right : ax == AlignX::Center ? TX::Center : TX::Left;
        const TY ty = ay == AlignY::Top      ? TY::Top
                      : ay == AlignY::Bottom ? TY::Bottom
                      : ay == AlignY::Center ? TY::Center
                                             : TY::Baseline;
        if (!font_.empty()) OIIO::ImageBufAlgo::render_text(buf_, x, y, s, size, font_, c, tx, ty);
    }
    std::vector<float> pixels() const override {
        const OIIO::ImageSpec& s = buf_.spec();
        std::vector<float> f(size_t(s.width) * s.height * 3);
        buf_.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, f.data());
        return f;
    }

private:
    OIIO::ImageBuf buf_;
    std::string font_;
};

ImageCanvas* makeCanvas(int width, int height, const std::string& font) { return new OiioCanvas(width, height, font); }

const OiioModuleApi kApi{kOiioModuleVersion, readFile, readMemory, makeCanvas};

}  // namespace
}  // namespace metamer

extern "C" __attribute__((visibility("default"))) const metamer::OiioModuleApi* metamer_oiio_module() {
    return &metamer::kApi;
}
