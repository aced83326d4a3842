// CIE 1976 L*a*b* (CIELAB), the space the ΔE formulas (color/delta_e.h) are defined in.
//
// Relative colorimetry: only the ratios X/Xn, Y/Yn, Z/Zn enter, so XYZ and the white may be on any
// scale (Y = 1, Y = 100, cd/m²) as long as both are on the same one. L* is 0..100 for colours
// between black and the white; a* and b* are unbounded. docs/color.md, "CIELAB and ΔE2000".
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace metamer {

// XYZ → L*a*b* relative to `whiteXyz` (the white maps to (100, 0, 0)). Below the knee
// t = X/Xn ≤ 216/24389 the cube root is replaced by the CIE's linear segment, so dark and
// slightly negative values (out-of-gamut camera colours) stay finite and invertible.
glm::dvec3 xyzToLab(const glm::dvec3& xyz, const glm::dvec3& whiteXyz);

// The exact inverse of xyzToLab, on the scale of `whiteXyz`.
glm::dvec3 labToXyz(const glm::dvec3& lab, const glm::dvec3& whiteXyz);

// d(L*, a*, b*)/d(X, Y, Z) at xyz (for solvers that fit a colour in CIELAB). glm matrices are
// column-major: column j is the derivative with respect to X, Y or Z.
glm::dmat3 xyzToLabJacobian(const glm::dvec3& xyz, const glm::dvec3& whiteXyz);

}  // namespace metamer
