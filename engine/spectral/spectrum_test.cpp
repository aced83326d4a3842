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

