// OpenEXR through the OpenEXR library (io/exr_file): what it writes is read back by OpenImageIO
// (an independent reader) and by itself, strip by strip, float and half; what it refuses.
#include "io/exr_file.h"

#include <Imath/half.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <fstream>
#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
    fs::path dir = fs::temp_directory_path() / fmt::format("metamer-exr-{}-{}", ::getpid(), name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::vector<float> ramp(size_t n, float scale) {
    std::vector<float> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = scale * float(i) + 0.25f;
    return v;
}

}  // namespace

TEST(ExrFile, StripsOfFloatChannelsReadBackByOpenImageIOAndByItself) {
    const fs::path file = scratch("strips") / "a.exr";
    const int W = 7, H = 11;
    const std::vector<std::string> channels = {"S0.500,000000nm", "S0.400,000000nm", "X"};
    const std::vector<float> pixels = ramp(size_t(W) * H * 3, 0.5f);
    {
        ExrWriter w(file, W, H, channels, false, "zip", {{"metamer:grid", "400:500:100"}, {"note", "é→λ"}});
        w.writeRows(0, 4, pixels.data());
        w.writeRows(4, 7, pixels.data() + size_t(W) * 4 * 3);
        w.close();
    }
    auto in = OIIO::ImageInput::open(file.string());
    ASSERT_TRUE(in) << OIIO::geterror();
    const OIIO::ImageSpec& spec = in->spec();
    EXPECT_EQ(spec.width, W);
    EXPECT_EQ(spec.height, H);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(spec.get_string_attribute("compression"), "zip");
    EXPECT_EQ(spec.get_string_attribute("metamer:grid"), "400:500:100");
    EXPECT_EQ(spec.get_string_attribute("note"), "é→λ");
    // OpenEXR sorts channels by name; each holds its values.
    std::vector<float> all(size_t(W) * H * 3);
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, all.data()));
    for (int c = 0; c < 3; ++c) {
        const int source = int(std::find(channels.begin(), channels.end(), spec.channelnames[c]) - channels.begin());
        ASSERT_LT(source, 3);
        for (size_t p = 0; p < size_t(W) * H; ++p) ASSERT_EQ(all[p * 3 + c], pixels[p * 3 + source]);
    }

    const ExrHeader h = readExrHeader(file, Where{file.string()});
    EXPECT_EQ(h.width, W);
    EXPECT_EQ(h.height, H);
    EXPECT_EQ(h.compression, "zip");
    EXPECT_EQ(h.channels.size(), 3u);
    EXPECT_EQ(h.halfChannels, std::vector<bool>(3, false));
    EXPECT_NE(std::find(h.attributes.begin(), h.attributes.end(), std::pair<std::string, std::string>{"note", "é→λ"}),
              h.attributes.end());
    EXPECT_EQ(readExrChannels(file, channels, Where{}), pixels);  // in the order asked for
}

TEST(ExrFile, HalfStoresHalvesAndEveryCompressionRoundTrips) {
    const fs::path dir = scratch("half");
    const int W = 33, H = 17;  // not a multiple of any block height
    const std::vector<float> pixels = ramp(size_t(W) * H * 2, 0.01f);
    for (const char* c : {"none", "rle", "zips", "zip", "zip:1", "piz", "pxr24", "b44", "b44a", "dwaa:45", "dwab"}) {
        SCOPED_TRACE(c);
        const fs::path file = dir / "h.exr";
        {
            ExrWriter w(file, W, H, {"A", "B"}, true, c, {});
            w.writeRows(0, H, pixels.data());
            w.close();
        }
        const ExrHeader h = readExrHeader(file, Where{});
        EXPECT_EQ(h.halfChannels, std::vector<bool>(2, true));
        const std::vector<float> back = readExrChannels(file, {"A", "B"}, Where{});
        ASSERT_EQ(back.size(), pixels.size());
        const bool lossless = std::string(c).rfind("dwa", 0) != 0 && std::string(c).rfind("b44", 0) != 0 &&
                              std::string(c) != "pxr24";
        for (size_t i = 0; i < pixels.size(); ++i) {
            const float want = float(Imath::half(pixels[i]));
            if (lossless) ASSERT_EQ(back[i], want) << i;
            else ASSERT_NEAR(back[i], want, 0.05f * std::max(1.0f, want)) << i;  // B44 keeps ~3%
        }
    }
}

// XYZ as OpenEXR's convention has it: in R, G, B with the XYZ chromaticities, which other readers
// (OpenImageIO) and ours read back; without the attribute, none is reported.
TEST(ExrFile, ChromaticitiesAreWrittenAndReadBack) {
    const fs::path dir = scratch("chroma");
    const std::vector<float> pixels = ramp(2 * 2 * 3, 0.5f);
    {
        ExrWriter w(dir / "xyz.exr", 2, 2, {"R", "G", "B"}, false, "piz", {}, {.chromaticities = xyzChromaticities()});
        w.writeRows(0, 2, pixels.data());
        w.close();
    }
    auto in = OIIO::ImageInput::open((dir / "xyz.exr").string());
    ASSERT_TRUE(in) << OIIO::geterror();
    const OIIO::ParamValue* c = in->spec().find_attribute("chromaticities");
    ASSERT_TRUE(c);
    const float* xy = static_cast<const float*>(c->data());
    const float expected[8] = {1, 0, 0, 1, 0, 0, 1.0f / 3, 1.0f / 3};
    for (int i = 0; i < 8; ++i) EXPECT_FLOAT_EQ(xy[i], expected[i]) << i;
    const ExrHeader h = readExrHeader(dir / "xyz.exr", Where{"xyz.exr"});
    ASSERT_TRUE(h.chromaticities);
    EXPECT_TRUE(isXyzChromaticities(*h.chromaticities));
    EXPECT_FALSE(isXyzChromaticities(ExrChromaticities{{0.64, 0.33}, {0.3, 0.6}, {0.15, 0.06}, {0.3127, 0.329}}));
    {
        ExrWriter w(dir / "plain.exr", 2, 2, {"R", "G", "B"}, false, "piz", {});
        w.writeRows(0, 2, pixels.data());
        w.close();
    }
    EXPECT_FALSE(readExrHeader(dir / "plain.exr", Where{"plain.exr"}).chromaticities);
}

// A second buffer of channels: each channel holds its own buffer's values; a strip without them,
// or a name given twice, is a runtime error naming the file.
TEST(ExrFile, ExtraChannelsComeFromTheirOwnBuffer) {
    const fs::path dir = scratch("extra");
    const std::vector<float> main = ramp(3 * 2 * 2, 1.0f), extra = ramp(3 * 2 * 1, -2.0f);
    {
        ExrWriter w(dir / "e.exr", 3, 2, {"S0.500,000000nm", "S0.600,000000nm"}, false, "zip", {},
                    {.extraChannels = {"Y"}});
        EXPECT_THROW(w.writeRows(0, 1, main.data()), Error);
        w.writeRows(0, 2, main.data(), extra.data());
        w.close();
    }
    const std::vector<float> back = readExrChannels(dir / "e.exr", {"S0.600,000000nm", "Y"}, Where{"e.exr"});
    for (size_t p = 0; p < 6; ++p) {
        EXPECT_EQ(back[2 * p], main[2 * p + 1]) << p;
        EXPECT_EQ(back[2 * p + 1], extra[p]) << p;
    }
    EXPECT_THROW(ExrWriter(dir / "twice.exr", 1, 1, {"R"}, false, "zip", {}, {.extraChannels = {"R"}}), Error);
}

TEST(ExrFile, CompressionNamesAndLevels) {
    for (const char* ok : {"none", "rle", "zips", "zip", "zip:1", "zip:9", "zips:4", "piz", "pxr24", "b44", "b44a",
                           "dwaa", "dwab", "dwaa:45", "dwab:200.5"})
        EXPECT_TRUE(knownExrCompression(ok)) << ok;
    for (const char* bad : {"", "lzma", "zip:0", "zip:10", "zip:4.5", "zip:", "piz:3", "dwaa:-1", "dwaa:x", "ZIP"})
        EXPECT_FALSE(knownExrCompression(bad)) << bad;
    try {
        ExrWriter w(scratch("names") / "x.exr", 2, 2, {"A"}, false, "lzma", {});
        ADD_FAILURE() << "lzma accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.where().key, "compression");
        EXPECT_NE(e.message().find("piz"), std::string::npos) << e.message();
    }
}

TEST(ExrFile, ReadsADataWindowThatDoesNotStartAtTheOrigin) {
    const fs::path file = scratch("window") / "w.exr";
    OIIO::ImageSpec spec(3, 2, 1, OIIO::TypeDesc::FLOAT);
    spec.x = 5;
    spec.y = -4;
    spec.channelnames = {"Y"};
    const float px[6] = {1, 2, 3, 4, 5, 6};
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out && out->open(file.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, px) && out->close());
    const ExrHeader h = readExrHeader(file, Where{});
    EXPECT_EQ(h.width, 3);
    EXPECT_EQ(h.height, 2);
    EXPECT_EQ(readExrChannels(file, {"Y"}, Where{}), std::vector<float>(px, px + 6));
}

TEST(ExrFile, RefusesWhatIsNotAFlatSinglePartFileNamingIt) {
    const fs::path dir = scratch("bad");
    auto message = [](const fs::path& p) {
        try {
            readExrHeader(p, Where{p.string()});
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput);
            EXPECT_EQ(e.where().file, p.string());
            return e.message();
        }
        return std::string("accepted");
    };
    EXPECT_NE(message(dir / "missing.exr").find("not found"), std::string::npos);
    EXPECT_NE(message(dir).find("folder"), std::string::npos);
    std::ofstream(dir / "text.exr") << "not an image";
    EXPECT_NE(message(dir / "text.exr").find("not a readable OpenEXR file"), std::string::npos);
    // A truncated file: the header says more than there is.
    {
        ExrWriter w(dir / "whole.exr", 64, 64, {"A"}, false, "none", {});
        std::vector<float> px(64 * 64, 1.0f);
        w.writeRows(0, 64, px.data());
        w.close();
    }
    std::string bytes;
    {
        std::ifstream f(dir / "whole.exr", std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(f), {});
    }
    std::ofstream(dir / "cut.exr", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    EXPECT_THROW(readExrChannels(dir / "cut.exr", {"A"}, Where{"cut.exr"}), Error);
    EXPECT_THROW(readExrChannels(dir / "whole.exr", {"B"}, Where{"whole.exr"}), Error);  // no such channel
}
