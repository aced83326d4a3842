#include "render/quicklook_png.h"
#include "spectral/resampling.h"

#include "color/cie_xyz.h"
#include "color/srgb.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

class QuickLookPng : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::temp_directory_path() /
              fmt::format("metamer-quicklook-{}-{}", ::getpid(),
                          ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }

    struct Png {
        int width = 0, height = 0, channels = 0;
        std::vector<uint8_t> pixels;
        std::string description;
    };
    static Png readPng(const fs::path& p) {
        Png png;
        auto in = OIIO::ImageInput::open(p.string());
        EXPECT_TRUE(in) << OIIO::geterror();
        if (!in) return png;
        EXPECT_STREQ(in->format_name(), "png");
        png.width = in->spec().width;
        png.height = in->spec().height;
        png.channels = in->spec().nchannels;
        png.description = in->spec().get_string_attribute("ImageDescription");
        png.pixels.resize(static_cast<size_t>(png.width) * png.height * png.channels);
        EXPECT_TRUE(in->read_image(0, 0, 0, png.channels, OIIO::TypeDesc::UINT8, png.pixels.data()));
        return png;
    }

    const SpectrumLibrary library;
    fs::path dir;
};

// The D65 spectrum on the grid: CIE D65 has the chromaticity of the sRGB white, so it renders grey.
std::vector<float> d65On(const SpectrumLibrary& lib, const Grid& grid) {
    std::vector<double> d = resample(lib.get("illuminants/D65", Where{}), grid);
    return std::vector<float>(d.begin(), d.end());
}

}  // namespace

TEST_F(QuickLookPng, FlatGreyCubeGivesEqualRgb) {
    Grid grid{360, 830, 5};
    std::vector<float> d65 = d65On(library, grid);
    SpectralCube cube(8, 8, grid);
    // Row 0 is the brightest (12.5% of the pixels, so it sets the 99th percentile); the others are
    // darker greys.
    const double levels[8] = {1.0, 0.5, 0.18, 0.05, 0.01, 0.002, 0.7, 0.3};
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            for (int b = 0; b < grid.bands(); ++b) cube.at(x, y, b) = static_cast<float>(levels[y] * d65[b]);
    fs::path file = dir / "grey.png";
    QuickLookReport report = writeQuickLookPng(file, cube, library);
    EXPECT_EQ(report.clippedPixels, 0u);
    EXPECT_EQ(report.nonFinitePixels, 0u);
    Png png = readPng(file);
    ASSERT_EQ(png.channels, 3);
    ASSERT_EQ(png.width, 8);
    for (int y = 0; y < 8; ++y) {
        int expected = static_cast<int>(std::lround(srgbEncode(levels[y]) * 255));
        for (int x = 0; x < 8; ++x) {
            const uint8_t* p = &png.pixels[(y * 8 + x) * 3];
            EXPECT_EQ(p[0], p[1]) << x << "," << y;
            EXPECT_EQ(p[1], p[2]) << x << "," << y;
            EXPECT_NEAR(p[1], expected, 1) << "level " << levels[y];
        }
    }
    EXPECT_EQ(png.pixels[0], 255);
}

TEST_F(QuickLookPng, ExposureMapsThe99thPercentileToWhiteAndIsRecorded) {
    Grid grid{300, 740, 5};
    std::vector<float> d65 = d65On(library, grid);
    SpectralCube cube(100, 2, grid);  // 200 pixels: the 99th percentile is the 198th darkest
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 100; ++x) {
            double level = 1.0 + x + 100 * y;  // 1..200
            for (int b = 0; b < grid.bands(); ++b) cube.at(x, y, b) = static_cast<float>(level * d65[b]);
        }
    ColorMatchingFunctions cmfs = loadCie1931(library, grid);
    double yUnit = spectrumToXyz(d65.data(), cmfs).y;
    fs::path file = dir / "ramp.png";
    QuickLookReport report = writeQuickLookPng(file, cube, library);
    EXPECT_NEAR(report.yPercentile99, 198 * yUnit, 1e-6 * report.yPercentile99);
    EXPECT_NEAR(report.yScale, 1.0 / report.yPercentile99, 1e-15);
    EXPECT_EQ(report.clippedPixels, 2u);  // the two pixels brighter than the percentile
    Png png = readPng(file);
    EXPECT_EQ(png.description, report.description);
    EXPECT_NE(png.description.find("CIE 1931 XYZ -> sRGB (D65), no chromatic adaptation, Y scale 1/"),
              std::string::npos)
        << png.description;
    EXPECT_NE(png.description.find(fmt::format("{:.6g}", report.yPercentile99)), std::string::npos);
}

TEST_F(QuickLookPng, BlackCubeGivesBlackImage) {
    SpectralCube cube(4, 3, Grid{300, 740, 5});
    fs::path file = dir / "black.png";
    QuickLookReport report = writeQuickLookPng(file, cube, library);
    EXPECT_EQ(report.yPercentile99, 0.0);
    EXPECT_EQ(report.yScale, 1.0);
    EXPECT_EQ(report.clippedPixels, 0u);
    Png png = readPng(file);
    for (uint8_t v : png.pixels) EXPECT_EQ(v, 0);
}

TEST_F(QuickLookPng, NonFinitePixelsAreBlackAndCounted) {
    Grid grid{400, 700, 10};
    SpectralCube cube(3, 1, grid);
    for (int x = 0; x < 3; ++x)
        for (int b = 0; b < grid.bands(); ++b) cube.at(x, 0, b) = 1.0f;
    cube.at(1, 0, 5) = NAN;
    fs::path file = dir / "nan.png";
    QuickLookReport report = writeQuickLookPng(file, cube, library);
    EXPECT_EQ(report.nonFinitePixels, 1u);
    Png png = readPng(file);
    EXPECT_EQ(png.pixels[3] + png.pixels[4] + png.pixels[5], 0);
    EXPECT_GT(png.pixels[1], 200);
}

TEST_F(QuickLookPng, WriteFailureLeavesNoFile) {
    fs::path file = dir / "x.png";
    fs::create_directories(file);  // a folder where the file should go: rename must fail
    SpectralCube cube(2, 2, Grid{400, 700, 10});
    EXPECT_THROW(writeQuickLookPng(file, cube, library), Error);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}
