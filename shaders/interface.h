// The one place that defines the spectral pass's interface: descriptor bindings, specialization
// constant ids, push constants and storage-buffer records. Included by C++ (engine/render) and
// by GLSL (shaders/*.vert, *.frag), so neither restates a binding number or a struct layout.
#ifndef METAMER_SHADERS_INTERFACE_H
#define METAMER_SHADERS_INTERFACE_H

#ifdef __cplusplus
#include <glm/glm.hpp>
#include <cstdint>
namespace metamer::gpu {
using uint = uint32_t;
using vec4 = glm::vec4;
using mat4 = glm::mat4;
#endif

// Descriptor set 0 of the spectral pass.
#define BINDING_LIGHTS 0     // GpuLight[LIGHT_COUNT]
#define BINDING_MATERIALS 1  // GpuMaterial[]
#define BINDING_SPECTRA 2    // float[]: every per-band table, addressed by the offsets below

// Specialization constants of spectral.frag: the shader is specialized to the scene.
#define SPEC_LIGHT_COUNT 0       // number of lights (≥ 0)
#define SPEC_BAND_COUNT 1        // bands in the grid; bands past it are written as 0
#define SPEC_HAS_SPECULAR 2      // any material with a specular lobe
#define SPEC_HAS_FLUORESCENCE 3  // any fluorescent material

// Colour attachments per pass (lavapipe's maxColorAttachments), 4 bands each. spectral.frag is
// built once per attachment count 1..MAX_OUTPUTS (define OUTPUT_COUNT).
#define MAX_OUTPUTS 8

#define LIGHT_AMBIENT 0u
#define LIGHT_DIRECTIONAL 1u
#define LIGHT_POINT 2u

struct GpuLight {
    vec4 vector;  // directional: xyz = unit vector towards the light; point: xyz = position (m)
    uint type;    // LIGHT_*
    uint spectrumOffset;  // BINDING_SPECTRA index of E(λ) (irradiance or intensity), per band
    uint pad0;
    uint pad1;
};

struct GpuMaterial {
    float gloss;            // Blinn–Phong exponent
    uint diffuseOffset;     // ρd per band
    uint specularOffset;    // ρs per band
    uint emissionOffset;    // ê(λ)/λ per band (nm⁻²), fluorescent materials only
    uint couplingOffset;    // (Φ/π)·Σ a·E_l·λ·Δλ per light, fluorescent materials only
    uint fluorescent;       // 0 or 1
    uint hasSpecular;       // 0 or 1
    uint pad0;
};

struct SpectralPushConstants {
    mat4 viewProjection;  // world → clip (Vulkan clip space, y down, depth 0..1)
    vec4 cameraPosition;  // xyz; w = 1 perspective, 0 orthographic
    vec4 cameraForward;   // xyz: unit view direction (orthographic view vector is -forward)
    uint materialIndex;
    uint firstLayer;      // first RGBA layer (4 bands each) written by this pass
    uint pad0;
    uint pad1;
};

#ifdef __cplusplus
static_assert(sizeof(GpuLight) == 32, "GpuLight must match std430");
static_assert(sizeof(GpuMaterial) == 32, "GpuMaterial must match std430");
static_assert(sizeof(SpectralPushConstants) == 112, "push constants must match GLSL");
}  // namespace metamer::gpu
#endif

#endif
