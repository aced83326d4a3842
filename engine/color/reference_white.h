// The reference white: the light that defines "white" for exposure, adaptation and the ASTM E308
// weighting. Chosen from a scene by color/tonemap.h's referenceWhite(); plain data here so that
// the display path's parts (detectors, the E308 weights) need no scene.
// Tests: tests/tonemap_test.cpp, engine/color/astm_e308_test.cpp.
#pragma once

#include "spectral/spectrum.h"

#include <string>
#include <utility>
#include <vector>

namespace metamer {

struct ReferenceWhite {
    std::string source;             // "lights.1 (illuminants/D65)"
    std::vector<double> irradiance; // E(λ) at normal incidence, W·m⁻²·nm⁻¹, per band of the grid
    std::vector<double> radiance;   // of a perfect white diffuser under it: E/π, W·sr⁻¹·m⁻²·nm⁻¹
    // The same irradiance as spectra before resampling: E = Σ factor · spectrum (a light's
    // spectrum × its scale, over d² for a point light), so that a method that needs it on another
    // grid (ASTM E308's 1 nm table) can resample it there.
    std::vector<std::pair<Spectrum, double>> terms;
};

}  // namespace metamer
