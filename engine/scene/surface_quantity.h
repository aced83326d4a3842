// What a render computes at the surface each pixel sees: the radiance (the cube), or one of the
// ground-truth maps beside it (docs/io.md, "Ground truth"). Both renderers take it: the CPU
// reference (reference/cpu_renderer.h, ReferenceOptions) and the GPU's band passes
// (render/spectral_plan.h, SpectralPassOptions; shaders/spectral.frag, SPEC_QUANTITY).
// Tests: tests/ground_truth_test.cpp.
#pragma once

namespace metamer {

enum class SurfaceQuantity {
    // Spectral radiance towards the camera, W·sr⁻¹·m⁻²·nm⁻¹: everything the scene models.
    Radiance = 0,
    // The spectral irradiance reaching the surface point divided by π, W·sr⁻¹·m⁻²·nm⁻¹: the
    // radiance a perfect white Lambertian diffuser would send there. Every light with its
    // geometric factor, shadow and filter (coloured shadows), the hemisphere and ambient lights,
    // the indirect light; no specular lobe, no fluorescence, no emission, and nothing transparent
    // between the camera and the surface. Where the surface is Lambertian, not fluorescent, not
    // self-luminous and seen directly, radiance = reflectance × illumination band by band.
    Illumination = 1,
    // The diffuse reflectance factor ρd of the surface seen, per band (relative, 0..1 for a
    // physical surface): the material's spectrum times its diffuse texture's bands.
    Reflectance = 2,
};

// "radiance", "illumination", "reflectance".
inline const char* surfaceQuantityName(SurfaceQuantity q) {
    return q == SurfaceQuantity::Illumination ? "illumination" : q == SurfaceQuantity::Reflectance ? "reflectance" : "radiance";
}

}  // namespace metamer
