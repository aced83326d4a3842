// Colour differences between two CIELAB colours (color/lab.h; both relative to the same white).
// docs/color.md, "CIELAB and ΔE2000".
#pragma once

#include <glm/vec3.hpp>

namespace metamer {

// CIEDE2000 (CIE 142:2001) with the parametric factors kL = kC = kH = 1, implemented as in
// Sharma, Wu & Dalal, "The CIEDE2000 color-difference formula: implementation notes, supplementary
// test data, and mathematical observations", Color Res. Appl. 30(1), 2005 — including their
// conventions for neutral colours (hue 0, mean hue h1' + h2') and hues 180° apart.
// Symmetric in its arguments; about 1 is a just-noticeable difference.
double deltaE2000(const glm::dvec3& lab1, const glm::dvec3& lab2);

// CIE 1976 ΔE*ab: the Euclidean distance in L*a*b*.
double deltaE76(const glm::dvec3& lab1, const glm::dvec3& lab2);

}  // namespace metamer
