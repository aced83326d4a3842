#include "color/cie_xyz.h"

#include "color/srgb.h"

#include <gtest/gtest.h>

using namespace metamer;

namespace {
const SpectrumLibrary& library() {
    static const SpectrumLibrary lib;
    return lib;
}
}  // namespace

TEST(CieXyz, EqualEnergyGivesEqualXyz) {
    // Σ x̄, ȳ, z̄ over the 1 nm CIE 1931 table are 106.865, 106.857, 106.892: equal to 0.04%.
    Grid grid{360, 830, 5};
    ColorMatchingFunctions cmfs = loadCie1931(library(), grid);
    std::vector<float> ones(grid.bands(), 1.0f);
    glm::dvec3 xyz = spectrumToXyz(ones.data(), cmfs);
    EXPECT_NEAR(xyz.x, 106.865, 106.865 * 0.002);
    EXPECT_NEAR(xyz.y, 106.857, 106.857 * 0.002);
    EXPECT_NEAR(xyz.z, 106.892, 106.892 * 0.002);
    EXPECT_NEAR(xyz.x / xyz.y, 1.0, 0.01);
    EXPECT_NEAR(xyz.z / xyz.y, 1.0, 0.01);
}

TEST(CieXyz, DefaultGridCutsOnlyTheNegligibleTail) {
    // 300:740:5 misses 745–830 nm (Σȳ there ≈ 0.003) and adds nothing below 360 nm.
    Grid grid{300, 740, 5};
    ColorMatchingFunctions cmfs = loadCie1931(library(), grid);
    for (int i = 0; grid.wavelength(i) < 357.5; ++i) EXPECT_EQ(cmfs.y[i], 0.0) << grid.wavelength(i);
    std::vector<float> ones(grid.bands(), 1.0f);
    glm::dvec3 xyz = spectrumToXyz(ones.data(), cmfs);
    EXPECT_NEAR(xyz.x / xyz.y, 1.0, 0.01);
    EXPECT_NEAR(xyz.z / xyz.y, 1.0, 0.01);
}

TEST(CieXyz, Monochromatic555nmGivesYBar) {
    Grid grid{300, 740, 5};
    ColorMatchingFunctions cmfs = loadCie1931(library(), grid);
    SpectralCube cube(1, 1, grid);
    int band = static_cast<int>((555 - grid.start_nm) / grid.step_nm);
    ASSERT_EQ(grid.wavelength(band), 555.0);
    cube.at(0, 0, band) = 1.0f;
    glm::dvec3 xyz = cubeToXyz(cube, cmfs)[0];
    // ȳ(555) = 1; the band average over 552.5–557.5 nm is within 0.1% of it.
    EXPECT_NEAR(xyz.y / grid.step_nm, 1.0, 1e-3);
    EXPECT_NEAR(xyz.x / grid.step_nm, 0.5120501, 0.005);
    EXPECT_NEAR(xyz.z / grid.step_nm, 0.00575, 0.0005);
}

TEST(CieXyz, MissingObserverIsAnInputError) {
    try {
        loadObserver(library(), "observers/cie1931_2dge", Grid{});
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(e.message().find("cie1931_2deg"), std::string::npos) << e.message();
    }
}

TEST(CieXyz, GridMismatchIsRejected) {
    ColorMatchingFunctions cmfs = loadCie1931(library(), Grid{300, 740, 5});
    EXPECT_THROW(cubeToXyz(SpectralCube(1, 1, Grid{300, 740, 10}), cmfs), Error);
}

TEST(Srgb, D65WhiteMapsToOnes) {
    glm::dvec3 rgb = xyzToLinearSrgb(glm::dvec3(0.95047, 1.0, 1.08883));
    EXPECT_NEAR(rgb.r, 1.0, 1e-4);
    EXPECT_NEAR(rgb.g, 1.0, 1e-4);
    EXPECT_NEAR(rgb.b, 1.0, 1e-4);
}

TEST(Srgb, MatrixAgreesWithTheStandardsTable) {
    // IEC 61966-2-1 prints the matrix to 4 decimals.
    const double table[3][3] = {{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};
    const glm::dmat3& m = xyzToLinearSrgbMatrix();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(m[c][r], table[r][c], 6e-4) << r << "," << c;
}

TEST(Srgb, EncodingIsContinuousAndInvertible) {
    const double knee = 0.0031308;
    double below = 12.92 * knee;
    double above = 1.055 * std::pow(knee, 1.0 / 2.4) - 0.055;
    EXPECT_NEAR(below, above, 1e-7);
    EXPECT_NEAR(srgbEncode(knee), srgbEncode(std::nextafter(knee, 1.0)), 1e-7);
    EXPECT_DOUBLE_EQ(srgbEncode(0.0), 0.0);
    EXPECT_NEAR(srgbEncode(1.0), 1.0, 1e-12);
    EXPECT_NEAR(srgbEncode(0.18), 0.461356, 1e-6);
    for (double v : {0.0, 0.001, 0.0031308, 0.01, 0.18, 0.5, 1.0}) EXPECT_NEAR(srgbDecode(srgbEncode(v)), v, 1e-12);
}
