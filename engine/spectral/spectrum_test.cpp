#include "spectral/spectrum.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace metamer;

namespace {

Spectrum sampled(std::vector<double> nm, std::vector<double> v) {
    Spectrum s;
    s.wavelengths_nm = std::move(nm);
    s.values = std::move(v);
    s.source = "test";
    s.validate(Where{"test"});
    return s;
}

Spectrum triangle() { return sampled({400, 500, 600}, {0.0, 1.0, 0.0}); }

// A narrow emission line (FWHM ≈ 0.47 nm) sampled every 0.1 nm.
Spectrum line(double centre, double sigma = 0.2) {
    std::vector<double> nm, v;
    for (double l = centre - 5; l <= centre + 5 + 1e-9; l += 0.1) {
        nm.push_back(l);
        v.push_back(std::exp(-0.5 * std::pow((l - centre) / sigma, 2)));
    }
    return sampled(nm, v);
}

}  // namespace

TEST(Spectrum, LinearInterpolationAndZeroOutside) {
    Spectrum s = triangle();
    EXPECT_DOUBLE_EQ(s.at(450), 0.5);
    EXPECT_DOUBLE_EQ(s.at(500), 1.0);
    EXPECT_DOUBLE_EQ(s.at(399.9), 0.0);
    EXPECT_DOUBLE_EQ(s.at(600.1), 0.0);
}

TEST(Spectrum, IntegralOfTriangleIsHalfBaseTimesHeight) {
    EXPECT_DOUBLE_EQ(triangle().integral(), 100.0);
    EXPECT_DOUBLE_EQ(triangle().integrate(450, 550), 75.0);
    EXPECT_DOUBLE_EQ(triangle().integrate(100, 900), 100.0);
}

TEST(Spectrum, ValidateRejectsBadData) {
    Spectrum s;
    s.wavelengths_nm = {400, 400};
    s.values = {1, 2};
    EXPECT_THROW(s.validate(Where{"f.csv"}), Error);
    s.wavelengths_nm = {500, 400};
    EXPECT_THROW(s.validate(Where{"f.csv"}), Error);
    s.wavelengths_nm = {400, 500};
    s.values = {1, NAN};
    EXPECT_THROW(s.validate(Where{"f.csv"}), Error);
    s.values = {1};
    EXPECT_THROW(s.validate(Where{"f.csv"}), Error);
    try {
        s.validate(Where{"f.csv", "materials.a.diffuse"});
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("f.csv: materials.a.diffuse"), std::string::npos) << e.what();
    }
}

TEST(Resample, ConstantIsPreservedOnEveryGrid) {
    for (double step : {0.5, 1.0, 5.0, 50.0}) {
        auto v = resample(Spectrum::makeConstant(0.37), Grid{300, 700, step});
        for (double x : v) EXPECT_DOUBLE_EQ(x, 0.37);
    }
    auto flat = resample(sampled({200, 2500}, {2.0, 2.0}), Grid{300, 700, 10});
    for (double x : flat) EXPECT_NEAR(x, 2.0, 1e-12);
}

TEST(Resample, LinearDataAreReproducedExactly) {
    // Band averaging of a linear function is its value at the band centre.
    Spectrum ramp = sampled({300, 800}, {0.0, 1.0});
    Grid g{400, 700, 7.5};
    auto v = resample(ramp, g);
    for (int i = 0; i < g.bands(); ++i) EXPECT_NEAR(v[i], (g.wavelength(i) - 300) / 500, 1e-12);
}

TEST(Resample, FinerThanDataIsLinearInterpolationAwayFromKinks) {
    Spectrum s = triangle();
    Grid g{410, 490, 0.5};
    auto v = resample(s, g);
    for (int i = 0; i < g.bands(); ++i) EXPECT_NEAR(v[i], s.at(g.wavelength(i)), 1e-12);
}

TEST(Resample, NarrowLineKeepsItsEnergyOnCoarseGrids) {
    // The sum of band values × step equals the line's integral, whatever the step; point
    // sampling would miss the line or multiply it.
    Spectrum l = line(404.7);
    double area = l.integral();
    for (double step : {0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0}) {
        Grid g{300, 800, step};
        auto v = resample(l, g);
        double sum = 0;
        for (double x : v) sum += x * step;
        EXPECT_NEAR(sum, area, 1e-9 * area) << "step " << step;
    }
}

TEST(Resample, BandsOutsideTheDataAreZeroAndEdgeBandsHoldTheEndValue) {
    Spectrum s = sampled({380, 780}, {0.5, 0.5});
    Grid g{300, 740, 5};
    auto v = resample(s, g);
    EXPECT_EQ(v[0], 0.0);                        // 300 nm: outside
    EXPECT_EQ(v[(375 - 300) / 5], 0.0);          // 375 nm: band [372.5, 377.5] has no data
    EXPECT_DOUBLE_EQ(v[(380 - 300) / 5], 0.5);   // 380 nm: the end value held over the uncovered half
    EXPECT_DOUBLE_EQ(v[(740 - 300) / 5], 0.5);
}

TEST(Coverage, ReportsGapsAndMisses) {
    Spectrum s = sampled({380, 780}, {1, 1});
    EXPECT_TRUE(coverage(s, Grid{380, 780, 5}).covered);
    EXPECT_TRUE(coverage(s, Grid{400, 700, 1}).covered);
    CoverageGap gap = coverage(s, Grid{300, 740, 5});
    EXPECT_FALSE(gap.covered);
    EXPECT_TRUE(gap.overlaps);
    EXPECT_EQ(gap.data_lo, 380);
    EXPECT_FALSE(coverage(s, Grid{800, 1000, 10}).overlaps);
    EXPECT_TRUE(coverage(Spectrum::makeConstant(1), Grid{200, 2500, 50}).covered);
}
