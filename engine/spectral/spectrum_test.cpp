#include "spectral/spectrum.h"

#include <gtest/gtest.h>

using namespace metamer;

namespace {
Spectrum ramp() {
    Spectrum s;
    s.wavelengths_nm = {400, 500, 600};
    s.values = {0.0, 1.0, 0.0};
    s.source = "test";
    return s;
}
}  // namespace

TEST(Spectrum, LinearInterpolationAndZeroOutside) {
    Spectrum s = ramp();
    EXPECT_DOUBLE_EQ(s.at(450), 0.5);
    EXPECT_DOUBLE_EQ(s.at(500), 1.0);
    EXPECT_DOUBLE_EQ(s.at(399.9), 0.0);
    EXPECT_DOUBLE_EQ(s.at(600.1), 0.0);
}

TEST(Spectrum, IntegralOfTriangleIsHalfBaseTimesHeight) {
    EXPECT_DOUBLE_EQ(ramp().integral(), 100.0);
    EXPECT_DOUBLE_EQ(ramp().integrate(450, 550), 75.0);
}
