// The scene's spectra resampled onto the render grid, with the coverage policy applied.
// Shared by the GPU path and the CPU reference (both take their spectra from here; neither
// shares any shading code).
#pragma once

#include "scene/scene.h"

#include <vector>

namespace metamer {

enum class CoveragePolicy {
    ZeroWithWarning,  // bands outside a spectrum's data are 0, with one warning per spectrum
    Error,            // --strict-coverage: any band outside a spectrum's data is an input error
};

struct MaterialOnGrid {
    std::vector<double> diffuse;   // ρd per band
    std::vector<double> specular;  // ρs per band
    double gloss = 0.0;
    bool fluorescent = false;
    std::vector<double> excitation;  // a per band (absorptance)
    // ê(λ): the emission shape divided by its integral over its own data (nm⁻¹), per band, so
    // Σ ê·Δλ = 1 when the grid covers the emission.
    std::vector<double> emission;
    double quantum_yield = 0.0;
};

struct SceneOnGrid {
    Grid grid;
    std::vector<double> wavelengths_nm;
    std::vector<std::vector<double>> lights;  // spectrum × scale per band, per light
    std::vector<MaterialOnGrid> materials;
};

// Resamples every spectrum of `scene` onto `grid`. A spectrum whose data miss the grid entirely
// is always an error (it is surely a mistake); a partial miss follows `policy`.
SceneOnGrid resampleScene(const Scene& scene, const Grid& grid,
                          CoveragePolicy policy = CoveragePolicy::ZeroWithWarning);

}  // namespace metamer
