// Demosaicing's own properties (issue 48, item 2); the comparison with colour-demosaicing is in
// tests/python/test_isp.py.
#include "isp/demosaic.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace metamer;

namespace {

// The mosaic of an image whose R, G, B are given functions of (x, y), behind `pattern`.
template <typename F>
std::vector<double> mosaicOf(int w, int h, const std::array<int, 4>& pattern, F rgb) {
    std::vector<double> m(size_t(w) * size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) m[size_t(y) * w + size_t(x)] = rgb(x, y)[pattern[size_t(y % 2) * 2 + size_t(x % 2)]];
    return m;
}

}  // namespace

TEST(Demosaic, AFlatColourComesBackExactlyByEitherMethodAndPattern) {
    for (const char* name : {"RGGB", "BGGR", "GRBG", "GBRG"})
        for (DemosaicMethod method : {DemosaicMethod::Bilinear, DemosaicMethod::Malvar2004}) {
            const auto p = bayerPattern(name, Where{"cfa"});
            const std::vector<double> rgb =
                demosaic(mosaicOf(12, 10, p, [](int, int) { return std::array<double, 3>{0.2, 0.5, 0.7}; }), 12, 10, p, method);
            // Away from the mirrored borders, where a tile's phase changes the neighbours' colours.
            for (int y = 2; y < 8; ++y)
                for (int x = 2; x < 10; ++x)
                    for (int c = 0; c < 3; ++c)
                        EXPECT_NEAR(rgb[(size_t(y) * 12 + size_t(x)) * 3 + size_t(c)], (std::array<double, 3>{0.2, 0.5, 0.7})[size_t(c)],
                                    1e-12)
                            << name << " " << x << "," << y;
        }
}

TEST(Demosaic, MirroredInTheCfasPhaseAFlatColourIsExactUpToTheEdgesAndColourDemosaicingsReflectIsNot) {
    const std::array<double, 3> flat{0.2, 0.5, 0.7};
    for (const char* name : {"RGGB", "BGGR", "GRBG", "GBRG"})
        for (DemosaicMethod method : {DemosaicMethod::Bilinear, DemosaicMethod::Malvar2004}) {
            const auto p = bayerPattern(name, Where{"cfa"});
            const std::vector<double> m = mosaicOf(7, 5, p, [&](int, int) { return flat; });
            const std::vector<double> mirrored = demosaic(m, 7, 5, p, method, DemosaicBorder::Mirror);
            for (size_t i = 0; i < mirrored.size(); ++i) EXPECT_NEAR(mirrored[i], flat[i % 3], 1e-12) << name << " " << i;
            // Reflect repeats the edge row, whose colours are the wrong ones for the phase beyond it.
            const std::vector<double> reflected = demosaic(m, 7, 5, p, method, DemosaicBorder::Reflect);
            double worst = 0.0;
            for (size_t i = 0; i < reflected.size(); ++i) worst = std::max(worst, std::abs(reflected[i] - flat[i % 3]));
            EXPECT_GT(worst, 0.05) << name;
        }
}

TEST(Demosaic, MalvarIsExactOnALinearRamp) {
    // Malvar's gradient corrections are Laplacians, 0 on a plane: its filters stay exact for images
    // linear in x and y whose colours differ by constants (as bilinear interpolation is).
    const auto p = bayerPattern("RGGB", Where{"cfa"});
    auto ramp = [](int x, int y) {
        const double v = 0.01 * x + 0.02 * y;
        return std::array<double, 3>{v + 0.1, v + 0.3, v + 0.2};
    };
    const std::vector<double> m = mosaicOf(16, 16, p, ramp);
    const std::vector<double> malvar = demosaic(m, 16, 16, p, DemosaicMethod::Malvar2004);
    for (int y = 3; y < 13; ++y)
        for (int x = 3; x < 13; ++x)
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(malvar[(size_t(y) * 16 + size_t(x)) * 3 + size_t(c)], ramp(x, y)[size_t(c)], 1e-12) << x << "," << y << "," << c;
}

TEST(Demosaic, NamesAreChecked) {
    EXPECT_THROW(bayerPattern("RGBG", Where{"cfa"}), Error);
    EXPECT_THROW(bayerPattern("RRGB", Where{"cfa"}), Error);
    EXPECT_THROW(parseDemosaicMethod("ahd", Where{"method"}), Error);
}
