// The one image reader (io/raster_image): EXR and PNG by their own libraries, anything else
// through the OpenImageIO module, opened only then; a process that renders PNG and EXR never
// loads OpenImageIO (checked from outside, by the dynamic loader's own log).
#include "io/image_reader.h"

#include "io/oiio_module.h"
#include "io/png_file.h"
#include "support/cli.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <unistd.h>

using namespace metamer;
using namespace metamer::test;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
    fs::path dir = fs::temp_directory_path() / fmt::format("metamer-raster-{}-{}", ::getpid(), name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

void writeWithOiio(const fs::path& file, int channels, OIIO::TypeDesc type, const std::vector<float>& px) {
    OIIO::ImageSpec spec(4, 3, channels, type);
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out && out->open(file.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, px.data()) &&
                out->close())
        << OIIO::geterror();
}

}  // namespace

TEST(RasterImage, SignaturesDecideTheReader) {
    const fs::path dir = scratch("signatures");
    std::vector<float> px(4 * 3 * 3);
    for (size_t i = 0; i < px.size(); ++i) px[i] = float(i) / float(px.size());
    writeWithOiio(dir / "a.exr", 3, OIIO::TypeDesc::HALF, px);
    writeWithOiio(dir / "a.png", 3, OIIO::TypeDesc::UINT16, px);
    writeWithOiio(dir / "a.tif", 3, OIIO::TypeDesc::UINT8, px);
    writeWithOiio(dir / "a.jpg", 3, OIIO::TypeDesc::UINT8, px);
    EXPECT_EQ(imageSignature(dir / "a.exr"), "openexr");
    EXPECT_EQ(imageSignature(dir / "a.png"), "png");
    EXPECT_EQ(imageSignature(dir / "a.jpg"), "jpeg");
    EXPECT_EQ(imageSignature(dir / "a.tif"), "");

    const RasterImage exr = readRasterImage(dir / "a.exr", Where{});
    EXPECT_EQ(exr.format, "openexr");
    EXPECT_TRUE(exr.floatingPoint);
    EXPECT_EQ(exr.bits, 16);
    EXPECT_EQ(exr.channels, (std::vector<std::string>{"B", "G", "R"}));  // as OpenEXR stores them
    const RasterImage png = readRasterImage(dir / "a.png", Where{});
    EXPECT_EQ(png.format, "png");
    EXPECT_EQ(png.bits, 16);
    for (size_t i = 0; i < px.size(); ++i) EXPECT_NEAR(png.normalized(i), px[i], 1.0 / 65535);
    // TIFF: through OpenImageIO, as counts like every integer image.
    const RasterImage tif = readRasterImage(dir / "a.tif", Where{});
    EXPECT_EQ(tif.format, "tiff");
    EXPECT_EQ(tif.bits, 8);
    EXPECT_TRUE(oiioModuleLoaded());
    for (size_t i = 0; i < px.size(); ++i) {
        EXPECT_EQ(tif.pixels[i], std::round(tif.pixels[i]));
        EXPECT_NEAR(tif.normalized(i), px[i], 0.5 / 255 + 1e-6);
    }
    std::ifstream f(dir / "a.jpg", std::ios::binary);
    const std::vector<uint8_t> jpeg((std::istreambuf_iterator<char>(f)), {});
    const RasterImage j = readRasterImage(jpeg, "embedded", Where{});
    EXPECT_EQ(j.format, "jpeg");
    EXPECT_EQ(j.width, 4);
    std::ofstream(dir / "notes.txt") << "not an image";
    try {
        readRasterImage(dir / "notes.txt", Where{"notes.txt"});
        ADD_FAILURE() << "a text file was read as an image";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_EQ(e.where().file, "notes.txt");
    }
}

// Rendering a cube, a PNG and XYZ, and comparing two PNGs, load no OpenImageIO; comparing TIFFs
// does. The dynamic loader lists every library it initializes (LD_DEBUG=libs).
TEST(RasterImage, OpenImageIOIsLoadedOnlyForOtherFormats) {
    const fs::path dir = scratch("loads");
    const std::string scene = std::string(METAMER_SOURCE_DIR) + "/scenes/metamers.json";
    auto loadsOiio = [](const CliRun& r) { return r.output.find("libOpenImageIO.so") != std::string::npos; };
    const CliRun render = runMetamer("render " + scene + " --set camera.width=32 --set camera.height=16 --write cube,png,xyz --out " +
                                         dir.string(),
                                     {.env = "LD_DEBUG=libs"});
    ASSERT_EQ(render.code, 0) << render.output.substr(render.output.size() > 4000 ? render.output.size() - 4000 : 0);
    EXPECT_FALSE(loadsOiio(render));
    const CliRun same = runMetamer("compare " + (dir / "metamers.png").string() + " " + (dir / "metamers.png").string(),
                                   {.env = "LD_DEBUG=libs"});
    EXPECT_EQ(same.code, 0);
    EXPECT_FALSE(loadsOiio(same));
    std::vector<float> px(4 * 3 * 3, 0.5f);
    writeWithOiio(dir / "t.tif", 3, OIIO::TypeDesc::UINT8, px);
    const CliRun tiff = runMetamer("compare " + (dir / "t.tif").string() + " " + (dir / "t.tif").string(),
                                   {.env = "LD_DEBUG=libs"});
    EXPECT_EQ(tiff.code, 0);
    EXPECT_TRUE(loadsOiio(tiff));
    // Without the module, a TIFF cannot be read, and the error says where it was looked for.
    const CliRun missing = runMetamer("compare " + (dir / "t.tif").string() + " " + (dir / "t.tif").string(),
                                      {.env = "METAMER_OIIO_MODULE=/nonexistent/libmetamer_oiio.so"});
    EXPECT_NE(missing.code, 0);
    EXPECT_NE(missing.output.find("/nonexistent/libmetamer_oiio.so"), std::string::npos) << missing.output;
}

namespace {

// A PNG whose header says `width` × `height` 16-bit RGBA, with one byte of pixel data: what a
// reader learns from the header alone.
std::vector<uint8_t> pngClaiming(uint32_t width, uint32_t height) {
    auto be = [](std::vector<uint8_t>& v, uint32_t x) {
        for (int s = 24; s >= 0; s -= 8) v.push_back(uint8_t(x >> s));
    };
    std::vector<uint8_t> f = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    auto chunk = [&](const char* type, const std::vector<uint8_t>& data) {
        std::vector<uint8_t> body(type, type + 4);
        body.insert(body.end(), data.begin(), data.end());
        uint32_t crc = 0xffffffffu;  // CRC-32 of type and data, so that libpng reads on
        for (uint8_t b : body) {
            crc ^= b;
            for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
        }
        be(f, uint32_t(data.size()));
        f.insert(f.end(), body.begin(), body.end());
        be(f, ~crc);
    };
    std::vector<uint8_t> ihdr;
    be(ihdr, width);
    be(ihdr, height);
    for (int b : {16, 6, 0, 0, 0}) ihdr.push_back(uint8_t(b));
    chunk("IHDR", ihdr);
    chunk("IDAT", {0x78, 0x01, 0x63, 0x00, 0x00, 0x00, 0x01, 0x00, 0x01});  // zlib of one zero byte
    chunk("IEND", {});
    return f;
}

std::string inputErrorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput) << e.text();
        return e.text();
    }
    ADD_FAILURE() << "no error";
    return "";
}

}  // namespace

// Issue 19, class 8: a valid header that claims more than the machine can decode is refused
// before a pixel is allocated (60000² RGBA16: 54 GiB of floats plus 27 GiB of samples).
TEST(RasterImage, AnImageTooLargeToDecodeIsRefusedFromItsHeader) {
    const fs::path dir = scratch("huge");
    const std::vector<uint8_t> bytes = pngClaiming(60000, 60000);
    std::ofstream(dir / "huge.png", std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                            std::streamsize(bytes.size()));
    for (const std::string& e : {inputErrorOf([&] { readRasterImage(dir / "huge.png", Where{"huge.png"}); }),
                                 inputErrorOf([&] { readRasterImage(bytes, "embedded", Where{"embedded"}); })}) {
        EXPECT_NE(e.find("the png image is 60000×60000 with 4 channels: decoded it would take 80.5 GiB"),
                  std::string::npos) << e;
        EXPECT_NE(e.find("a quarter of this machine's memory"), std::string::npos) << e;
    }
    // The caller's own check sees the header first, before the pixels are read.
    const std::vector<uint8_t> small = pngClaiming(3, 2);
    int seen = 0;
    const std::string e = inputErrorOf([&] {
        readRasterImage(small, "small", Where{"small"}, [&](const RasterImage& h) {
            ++seen;
            EXPECT_EQ(h.width, 3);
            EXPECT_EQ(h.height, 2);
            EXPECT_TRUE(h.pixels.empty());
        });
    });
    EXPECT_EQ(seen, 1);
    EXPECT_NE(e.find("cannot read pixels"), std::string::npos) << e;  // no data after the header
    fs::remove_all(dir);
}

// Issue 19, class 4: a JPEG cut short decodes with libjpeg's grey fill and a warning; that is
// damage, an input error on one line.
TEST(RasterImage, ATruncatedJpegIsAnInputErrorOnOneLine) {
    const fs::path files = fs::path(METAMER_SOURCE_DIR) / "tests/bad-inputs/files";
    const RasterImage whole = readRasterImage(files / "tile.jpg", Where{"tile.jpg"});
    EXPECT_EQ(whole.width, 64);
    const std::string e = inputErrorOf([&] { readRasterImage(files / "truncated.jpg", Where{"truncated.jpg"}); });
    EXPECT_NE(e.find("damaged image data"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}
