// glTF metallic–roughness materials as Metamer materials (docs/scene-format.md, "glTF
// materials"). Metamer's surface model is Lambertian diffuse plus a normalized Blinn–Phong lobe,
// without Fresnel, so the mapping is an approximation, chosen to keep a dielectric's and a
// metal's look:
//   diffuse  ρd = baseColor · (1 − metallic)             (the base colour texture multiplies it)
//   specular ρs = mix(0.04, baseColorFactor, metallic)    (F0: 4 % for dielectrics, the colour for metals)
//   gloss    N  = 2/α² − 2 with α = roughness²            (Walter et al. 2007's Beckmann–Phong
//                                                           match), at most kMaxGltfGloss
// Colours become spectra by RGB up-sampling (color/rgb_upsampling.h).
// Tests: tests/textures_test.cpp, engine/scene/gltf_mesh_test.cpp.
#pragma once

#include "scene/gltf_mesh.h"
#include "scene/scene.h"
#include "color/rgb_upsampling.h"

namespace metamer {

// Roughness 0 (a mirror) would be an infinite exponent; 1e4 is a lobe of about 1° half-width.
constexpr double kMaxGltfGloss = 1e4;

double glossFromRoughness(double roughness);

// An up-sampled colour as a spectrum sampled every 5 nm over 200–2500 nm (the widest grid), so
// that it covers every render grid; the model holds its end values outside 360–830 nm.
Spectrum upsampledSpectrum(const RgbUpsampler& up, const glm::dvec3& linearRgb, double scale = 1.0);

// The material's spectra and gloss (textures are attached by the scene loader). `where` is the
// scene key the material is reported under.
Material materialFromGltf(const GltfMaterial& g, const RgbUpsampler& up, const Where& where);

}  // namespace metamer
