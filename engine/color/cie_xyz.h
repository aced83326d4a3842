// CIE XYZ from spectral radiance: the observer's colour-matching functions resampled onto the
// cube's grid and integrated per pixel by a Riemann sum, X = Σ L(λi) x̄(λi) Δλ.
//
// No 683 lm/W factor: this is radiometric XYZ in W·sr⁻¹·m⁻² (Y is the ȳ-weighted radiance, not
// luminance in cd/m²). The quick-look only needs relative values, and callers that want
// photometric units multiply by 683.
#pragma once

#include "spectral/cube.h"
#include "spectral/library.h"

#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace metamer {

// The CIE 1931 2° standard observer in the library: wavelength_nm,x_bar,y_bar,z_bar.
inline constexpr const char* kCie1931Observer = "observers/cie1931_2deg";

// Colour-matching functions as band averages on a grid (docs/physics.md, "Resampling"); bands
// outside the observer's data (360–830 nm for CIE 1931) are 0.
struct ColorMatchingFunctions {
    Grid grid;
    std::vector<double> x, y, z;
    std::string source;  // library name, for messages
};

// Loads a 3-column observer table from the library and resamples it onto `grid`. Throws an input
// error naming the observer (and the library root) when it is missing or malformed.
ColorMatchingFunctions loadObserver(const SpectrumLibrary& library, const std::string& name,
                                    const Grid& grid);
inline ColorMatchingFunctions loadCie1931(const SpectrumLibrary& library, const Grid& grid) {
    return loadObserver(library, kCie1931Observer, grid);
}

// XYZ of one spectrum given as band values on cmfs.grid (radiometric, see above).
glm::dvec3 spectrumToXyz(const float* bands, const ColorMatchingFunctions& cmfs);

// XYZ of every pixel, [y][x] row-major like the cube. cmfs.grid must equal cube.grid.
std::vector<glm::dvec3> cubeToXyz(const SpectralCube& cube, const ColorMatchingFunctions& cmfs);

}  // namespace metamer
