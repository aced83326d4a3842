// The scene's spectra resampled onto the render grid, with the coverage policy applied.
// Shared by the GPU path and the CPU reference (both take their spectra from here; neither
// shares any shading code).
// Tests: engine/scene/scene_on_grid_test.cpp, engine/scene/scene_json_test.cpp, engine/scene/scene_donaldson_test.cpp,
// tests/sampling_test.cpp.
#pragma once

#include "scene/scene.h"

#include <cstdint>
#include <vector>

namespace metamer {

enum class CoveragePolicy {
    ZeroWithWarning,  // bands outside a spectrum's data are 0, with one warning per spectrum
    Error,            // --strict-coverage: any band outside a spectrum's data is an input error
};

// A texture on the render grid: reflectance per band (spectral and RGB textures; RGB ones
// up-sampled per texel) or unit tangent-space normals (3 channels). [row][column][channel], row 0
// the top of the image.
struct TextureOnGrid {
    int width = 0, height = 0, channels = 0;
    bool normals = false;
    std::vector<float> data;
    const float* texel(int x, int y) const { return &data[(size_t(y) * width + x) * channels]; }
    // Every channel at texture coordinates uv, bilinearly between the four nearest texels' centres,
    // repeating outside [0, 1] (the GPU's sampler in double): into out[channels].
    void bilinear(const glm::dvec2& uv, double* out) const;
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
    // Indices into SceneOnGrid::textures, -1 for none (scene/scene.h, MaterialTextures).
    int diffuseTexture = -1, specularTexture = -1, normalTexture = -1;
    // A matrix material (Fluorescence::matrix): the Donaldson matrix on the grid, the mean of
    // scale·D over band i of λin × band o of λout at donaldson[i·N + o] (N bands), nm⁻¹. Empty for
    // the rank-one form above, which is the matrix D = Φ·a(λin)·ê(λout)·λin/λout
    // (docs/physics.md, "Fluorescence"); excitation and emission are then empty instead.
    std::vector<double> donaldson;
    bool isMatrix() const { return !donaldson.empty(); }
    // A transparent material (scene/scene.h): a thin sheet's transmittance per crossing, per band,
    // or an absorbing medium's decadic absorbance per metre (m⁻¹, the dyes' ε·c·100 included), per
    // band. Empty when the material is not one.
    std::vector<double> transmittance;
    std::vector<double> absorbance;
    // A slab (scene/scene.h, Material::Slab): n at each band's centre, its glass's decadic
    // absorbance per metre per band (zeros for clear glass), and its thickness in metres.
    std::vector<double> ior;
    std::vector<double> slabAbsorbance;
    double slabThickness = 0.0;
    // A self-luminous surface's radiance L_e per band (× its scale), W·sr⁻¹·m⁻²·nm⁻¹; empty else.
    std::vector<double> emitted;
    bool isEmitter() const { return !emitted.empty(); }
    bool isFilter() const { return !transmittance.empty(); }
    bool isMedium() const { return !absorbance.empty(); }
    bool isSlab() const { return !ior.empty(); }
    bool isTransparent() const { return isFilter() || isMedium() || isSlab(); }
};

// What a per-band array of a material holds, for code that transforms every one of them (the
// representation modes, represent/representation.cpp).
enum class MaterialSpectrum {
    Reflectance,  // ρd, ρs: 0..1 per band, multiplies a light
    Absorptance,  // a(λ) of the rank-one fluorescence
    Emission,     // ê(λ) of the rank-one fluorescence, nm⁻¹
    Matrix,       // the Donaldson matrix, N × N bands, nm⁻¹
    Transmittance,  // a sheet's T(λ): 0..1 per band, multiplies what is seen through it
    Absorbance,     // a medium's or a slab's a(λ), m⁻¹ per band, decadic
    Index,          // a slab's refractive index n(λ) per band
    Radiance,       // a surface's emitted radiance, W·sr⁻¹·m⁻²·nm⁻¹ per band: transforms as a light
};

// The one seam for a material's spectra: calls f(array, kind, name) for every per-band array of
// `m` (MaterialOnGrid or const MaterialOnGrid). A spectral field added to MaterialOnGrid must be
// visited here; scene/scene_on_grid_test.cpp counts MaterialOnGrid's fields and fails until the
// count there (and this visitor) are updated, so that no mode can drop a field silently.
template <typename Material, typename F>
void forEachSpectrum(Material& m, F&& f) {
    f(m.diffuse, MaterialSpectrum::Reflectance, "diffuse");
    f(m.specular, MaterialSpectrum::Reflectance, "specular");
    f(m.excitation, MaterialSpectrum::Absorptance, "excitation");
    f(m.emission, MaterialSpectrum::Emission, "emission");
    f(m.donaldson, MaterialSpectrum::Matrix, "donaldson");
    f(m.transmittance, MaterialSpectrum::Transmittance, "transmittance");
    f(m.absorbance, MaterialSpectrum::Absorbance, "absorbance");
    f(m.ior, MaterialSpectrum::Index, "ior");
    f(m.slabAbsorbance, MaterialSpectrum::Absorbance, "slabAbsorbance");
    f(m.emitted, MaterialSpectrum::Radiance, "emitted");
}

struct SceneOnGrid {
    Grid grid;
    std::vector<double> wavelengths_nm;
    std::vector<std::vector<double>> lights;  // spectrum × scale per band, per light
    std::vector<MaterialOnGrid> materials;
    std::vector<TextureOnGrid> textures;  // one per Scene::textures entry
};

// Bytes the scene's textures take on `grid` (float per band per texel; normals 3 floats).
uint64_t textureMemory(const Scene& scene, const Grid& grid);

// Resamples every spectrum of `scene` onto `grid`. A spectrum whose data miss the grid entirely
// is always an error (it is surely a mistake); a partial miss follows `policy`.
SceneOnGrid resampleScene(const Scene& scene, const Grid& grid,
                          CoveragePolicy policy = CoveragePolicy::ZeroWithWarning);

}  // namespace metamer
