// The heat map (compare/heatmap.h): written whole, the size of the images, and its colours say
// which pixels are over the threshold.
#include "compare/heatmap.h"

#include "color/display_model.h"
#include "color/lab.h"
#include "compare/compare_test_util.h"
#include "support/png_chunks.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <limits>

using namespace metamer;
using metamer::test::smoothCube;

namespace {

class CompareHeatmap : public metamer::test::ScratchDir {};

// CIELAB L* of an 8-bit sRGB colour.
double lightness(const std::array<uint8_t, 3>& c) {
    static const DisplayModel srgb = parseDisplay("srgb", 8, Where{});
    return xyzToLab(decodeCounts(srgb, glm::dvec3(c[0], c[1], c[2])), srgb.whiteXyz).x;
}

}  // namespace

TEST_F(CompareHeatmap, WritesOnePixelPerImagePixelWithOverThresholdPixelsInWarmColours) {
    SpectralCube cb = smoothCube(4, 3, Grid{400, 700, 10}), ca = cb;
    ca.at(1, 0, 4) *= 1.02f;    // 2%: over 1e-3
    ca.at(2, 2, 4) *= 1.0002f;  // 2e-4: under
    ca.at(3, 1, 4) = std::numeric_limits<float>::quiet_NaN();
    CompareStats s = compareImages(fromCube(ca), fromCube(cb), {});
    auto path = dir / "heat.png";
    writeHeatmap(path, s, s.pixelThreshold);

    auto in = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    EXPECT_EQ(spec.width, 4);
    EXPECT_EQ(spec.height, 3);
    EXPECT_EQ(spec.nchannels, 3);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
    EXPECT_NE(spec.get_string_attribute("ImageDescription").find("2 of 12 pixels over"), std::string::npos)
        << spec.get_string_attribute("ImageDescription");
    std::vector<uint8_t> px(4 * 3 * 3);
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data()));
    in->close();
    auto at = [&](int x, int y) {
        const uint8_t* p = &px[size_t(y * 4 + x) * 3];
        return std::array<uint8_t, 3>{p[0], p[1], p[2]};
    };
    std::array<uint8_t, 3> same = at(0, 0), over = at(1, 0), under = at(2, 2), nan = at(3, 1);
    EXPECT_LT(lightness(same), 10) << "an exact match is near black";
    EXPECT_GT(over[0], over[2]) << "over the threshold: warm";
    EXPECT_GT(under[2], under[0]) << "under the threshold: blue";
    EXPECT_EQ(nan, (std::array<uint8_t, 3>{255, 0, 255}));
    EXPECT_TRUE(metamer::test::hasPngChunk(path, "sRGB")) << "its colours are sRGB counts, tagged so";
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()), 1);
}

TEST(CompareHeatmapScale, LightnessRisesWithErrorAndHueJumpsAtTheThreshold) {
    const double threshold = 1e-3;
    double previous = -1.0;
    for (int i = 0; i <= 40; ++i) {
        double e = threshold * std::pow(10.0, -2.0 + 0.1 * i);
        auto c = heatmapColor(e, threshold);
        EXPECT_GE(lightness(c), previous - 1.0) << "error " << e;
        previous = lightness(c);
        if (e <= threshold) EXPECT_GE(c[2], c[0]) << "error " << e;
        else EXPECT_GT(c[0], c[2]) << "error " << e;
    }
    // Beyond the ends the scale saturates.
    EXPECT_EQ(heatmapColor(threshold * 1e-6, threshold), heatmapColor(0.0, threshold));
    EXPECT_EQ(heatmapColor(threshold * 1e6, threshold), heatmapColor(threshold * 100, threshold));
    // A zero threshold: any difference is over.
    auto c = heatmapColor(1e-12, 0.0);
    EXPECT_GT(c[0], c[2]);
}
