// PNG through libpng (io/png_file): what it writes OpenImageIO reads back (pixels, text, the sRGB
// chunk, an ICC profile); what OpenImageIO writes it reads (grey, RGBA, 16-bit); broken files are refused.
#include "io/png_file.h"

#include "color/display_profile.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
    fs::path dir = fs::temp_directory_path() / fmt::format("metamer-png-{}-{}", ::getpid(), name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::vector<uint16_t> pattern(size_t n, int bits) {
    std::vector<uint16_t> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = uint16_t((i * 2654435761u >> 7) & ((1u << bits) - 1));
    return v;
}

}  // namespace

TEST(PngFile, EightAndSixteenBitsReadBackByOpenImageIOWithTheirText) {
    const fs::path dir = scratch("bits");
    for (int bits : {8, 16}) {
        SCOPED_TRACE(bits);
        const fs::path file = dir / fmt::format("p{}.png", bits);
        const int W = 13, H = 9;
        const std::vector<uint16_t> counts = pattern(size_t(W) * H * 3, bits);
        {
            PngWriter w(file, W, H, 3, bits,
                        {{"ImageDescription", "display counts: detector cie1931 → sRGB, 5 nm²"},
                         {"metamer:scene", "spheres.json"},
                         {"oiio:ColorSpace", "sRGB"}});
            w.writeRows(0, 5, counts.data());
            w.writeRows(5, 4, counts.data() + size_t(W) * 5 * 3);
            w.close();
        }
        auto in = OIIO::ImageInput::open(file.string());
        ASSERT_TRUE(in) << OIIO::geterror();
        const OIIO::ImageSpec& spec = in->spec();
        EXPECT_EQ(spec.nchannels, 3);
        EXPECT_EQ(spec.format, bits == 16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8);
        EXPECT_EQ(spec.get_string_attribute("ImageDescription"), "display counts: detector cie1931 → sRGB, 5 nm²");
        EXPECT_EQ(spec.get_string_attribute("metamer:scene"), "spheres.json");
        EXPECT_EQ(spec.get_string_attribute("oiio:ColorSpace"), "sRGB");
        std::vector<uint16_t> back(counts.size());
        ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT16, back.data()));
        for (size_t i = 0; i < counts.size(); ++i) {
            // OpenImageIO scales 8-bit values to 16 bits (v · 257) when asked for UINT16.
            ASSERT_EQ(back[i], bits == 16 ? counts[i] : uint16_t(counts[i] * 257)) << i;
        }
        // And our own reader: counts, names, text.
        const RasterImage r = readPng(file, Where{file.string()});
        EXPECT_EQ(r.width, W);
        EXPECT_EQ(r.height, H);
        EXPECT_EQ(r.bits, bits);
        EXPECT_FALSE(r.floatingPoint);
        EXPECT_EQ(r.channels, (std::vector<std::string>{"R", "G", "B"}));
        EXPECT_EQ(r.attribute("ImageDescription"), "display counts: detector cie1931 → sRGB, 5 nm²");
        for (size_t i = 0; i < counts.size(); ++i) ASSERT_EQ(r.pixels[i], float(counts[i])) << i;
    }
}

TEST(PngFile, AnIccProfileGoesIntoTheIccpChunkThatOpenImageIOReads) {
    const fs::path file = scratch("icc") / "crt.png";
    const std::vector<uint8_t> icc = displayIccProfile(parseDisplay("crt", 8, Where{}), "test CRT");
    const std::vector<uint16_t> counts = pattern(4 * 3 * 3, 8);
    {
        PngWriter w(file, 4, 3, 3, 8, {{"metamer:scene", "spheres.json"}}, icc);
        w.writeRows(0, 3, counts.data());
        w.close();
    }
    // The chunk itself: "iCCP" is in the file, and no sRGB chunk beside it.
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(bytes.find("iCCP"), std::string::npos);
    EXPECT_EQ(bytes.find("sRGB"), std::string::npos);
    auto image = OIIO::ImageInput::open(file.string());
    ASSERT_TRUE(image) << OIIO::geterror();
    const OIIO::ParamValue* p = image->spec().find_attribute("ICCProfile");
    ASSERT_TRUE(p);
    ASSERT_EQ(size_t(p->type().size()), icc.size());
    const auto* stored = static_cast<const uint8_t*>(p->data());
    EXPECT_TRUE(std::equal(icc.begin(), icc.end(), stored));

    std::string message;
    try {
        PngWriter both(scratch("icc") / "both.png", 1, 1, 3, 8, {{"oiio:ColorSpace", "sRGB"}}, icc);
    } catch (const std::exception& e) {
        message = e.what();
    }
    EXPECT_NE(message.find("both.png"), std::string::npos) << message;
    EXPECT_NE(message.find("ICC profile"), std::string::npos) << message;
}

TEST(PngFile, ReadsGreyAndRgbaThatOpenImageIOWrites) {
    const fs::path dir = scratch("kinds");
    for (int channels : {1, 2, 4}) {
        SCOPED_TRACE(channels);
        const fs::path file = dir / fmt::format("k{}.png", channels);
        OIIO::ImageSpec spec(5, 3, channels, OIIO::TypeDesc::UINT8);
        spec.attribute("oiio:UnassociatedAlpha", 1);  // the values as given: no un-premultiplying
        std::vector<uint8_t> px(size_t(5) * 3 * channels);
        for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t(i * 7);
        auto out = OIIO::ImageOutput::create(file.string());
        ASSERT_TRUE(out && out->open(file.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, px.data()) &&
                    out->close());
        const RasterImage r = readPng(file, Where{});
        EXPECT_EQ(int(r.channels.size()), channels);
        EXPECT_EQ(r.channels.front(), channels <= 2 ? "Y" : "R");
        for (size_t i = 0; i < px.size(); ++i) ASSERT_EQ(r.pixels[i], float(px[i]));
        // From memory, as a glTF's embedded image.
        std::ifstream f(file, std::ios::binary);
        std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), {});
        EXPECT_EQ(readPng(bytes, Where{}).pixels, r.pixels);
    }
}

TEST(PngFile, RefusesBrokenFilesNamingThem) {
    const fs::path dir = scratch("broken");
    {
        PngWriter w(dir / "whole.png", 64, 64, 3, 8, {});
        std::vector<uint16_t> px(64 * 64 * 3, 100);
        w.writeRows(0, 64, px.data());
        w.close();
    }
    std::ifstream f(dir / "whole.png", std::ios::binary);
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), {});
    const std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + long(bytes.size() / 2));
    try {
        readPng(cut, Where{"cut.png"});
        ADD_FAILURE() << "a truncated PNG was read";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_EQ(e.where().file, "cut.png");
    }
    const std::vector<uint8_t> notPng = {'h', 'e', 'l', 'l', 'o', 0, 0, 0, 0, 0};
    EXPECT_THROW(readPng(notPng, Where{"x"}), Error);
    EXPECT_THROW(readPng(dir / "missing.png", Where{"missing.png"}), Error);
    // Writing: rows out of order, a bad depth.
    PngWriter w(dir / "order.png", 4, 4, 1, 8, {});
    std::vector<uint16_t> row(4, 1);
    EXPECT_THROW(w.writeRows(1, 1, row.data()), Error);
    EXPECT_THROW(PngWriter(dir / "deep.png", 4, 4, 3, 12, {}), Error);
}
