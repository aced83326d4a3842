// sRGB (IEC 61966-2-1): the XYZ -> linear RGB matrix for BT.709 primaries and a D65 white, and
// the piecewise transfer function. No chromatic adaptation anywhere: XYZ is taken as is.
// Tests: engine/color/display_model_test.cpp, engine/color/lab_test.cpp.
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace metamer {

// The D65 white the matrix is built for (CIE 1931 2°, Y = 1). It maps to linear RGB (1, 1, 1).
inline constexpr glm::dvec3 kD65WhiteXyz{0.95047, 1.0, 1.08883};

// XYZ -> linear sRGB, derived from the primaries' chromaticities (0.64,0.33), (0.30,0.60),
// (0.15,0.06) and kD65WhiteXyz at full double precision (the standard's 4-decimal table is off by
// ~2e-4 at white).
const glm::dmat3& xyzToLinearSrgbMatrix();
glm::dvec3 xyzToLinearSrgb(const glm::dvec3& xyz);

// The sRGB encoding (linear -> non-linear, "gamma"), for values in [0, 1]:
// 12.92·v below 0.0031308, else 1.055·v^(1/2.4) − 0.055. And its inverse.
double srgbEncode(double linear);
double srgbDecode(double encoded);

}  // namespace metamer
