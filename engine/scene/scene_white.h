// The reference white of a scene: the light that defines "white" for exposure, adaptation and the
// ASTM E308 weighting (docs/color.md, "Reference white"). The display path takes the result as plain
// data (color/reference_white.h) and never sees the scene. Tests: tests/tonemap_test.cpp.
#pragma once

#include "color/reference_white.h"
#include "scene/scene.h"
#include "scene/scene_on_grid.h"
#include "spectral/library.h"

namespace metamer {

// The brightest (by CIE 1931 Y) non-ambient light at normal incidence: a directional light's E(λ);
// a point light's I(λ)/d² at the camera target's distance; a self-luminous material's L_e(λ)·Σ A·cos θ/d²
// over its triangles (each a small source) at the camera target. With only ambient lights, their sum;
// with none, an equal-energy white (and a warning).
ReferenceWhite referenceWhite(const Scene& scene, const SceneOnGrid& spectra, const SpectrumLibrary& library);

}  // namespace metamer
