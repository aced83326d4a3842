// Chromatic adaptation: the 3×3 that moves relative XYZ seen under one white (the scene's) to the
// corresponding colour under another (the display's), by a von Kries-type scaling of "cone"
// responses. docs/color.md, "Chromatic adaptation", has every matrix and its source.
#pragma once

#include "core/error.h"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <string>

namespace metamer {

enum class Adaptation {
    None,         // no adaptation: XYZ passes unchanged
    VonKriesXyz,  // von Kries scaling of X, Y, Z themselves ("XYZ scaling")
    VonKriesLms,  // von Kries in Hunt–Pointer–Estévez cone space, rows normalized to D65
    Bradford,     // Lam (1985), as used in ICC profiles
    Cat02,        // CIE 159:2004 (CIECAM02)
    Cat16,        // Li et al. (2017) (CAM16)
};

// The names the scene file and command line use: "none", "vonkries-xyz", "vonkries", "bradford",
// "cat02", "cat16". Anything else is an input error at `where` listing the choices.
Adaptation parseAdaptation(const std::string& name, const Where& where);
std::string adaptationName(Adaptation a);

// M of each transform: XYZ → its cone-like space (rows are cone responses). Identity for None and
// VonKriesXyz.
glm::dmat3 catConeMatrix(Adaptation a);

// Complete adaptation (degree D = 1): M⁻¹ · diag(ρd / ρs) · M, with ρs = M·sourceWhite and
// ρd = M·destinationWhite, so that XYZ' = matrix * XYZ and sourceWhite maps to destinationWhite.
// Both whites on the same relative scale (usually Y = 1). None gives the identity.
glm::dmat3 adaptationMatrix(Adaptation a, const glm::dvec3& sourceWhite, const glm::dvec3& destinationWhite);

}  // namespace metamer
