#version 450
// The spectral pass: single-scattering radiance (diffuse + Blinn–Phong specular + fluorescence,
// summed over the lights) for 4 bands per colour attachment, up to 8 attachments per pass.
// Physics and units: docs/physics.md. The CPU reference (engine/reference) computes the same
// quantities independently in double precision.
#extension GL_GOOGLE_include_directive : require
#include "interface.h"

layout(constant_id = SPEC_LIGHT_COUNT) const int LIGHT_COUNT = 1;
// OUTPUT_COUNT (colour attachments of this pass, 1..8) is a compile-time define: the build makes
// one SPIR-V variant per count, so no variant declares an output its render pass lacks.
#ifndef OUTPUT_COUNT
#define OUTPUT_COUNT MAX_OUTPUTS
#endif
layout(constant_id = SPEC_BAND_COUNT) const int BAND_COUNT = 89;
layout(constant_id = SPEC_HAS_SPECULAR) const bool HAS_SPECULAR = true;
layout(constant_id = SPEC_HAS_FLUORESCENCE) const bool HAS_FLUORESCENCE = true;
const int LIGHT_SLOTS = LIGHT_COUNT > 0 ? LIGHT_COUNT : 1;  // arrays cannot be empty

layout(set = 0, binding = BINDING_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(set = 0, binding = BINDING_MATERIALS, std430) readonly buffer Materials { GpuMaterial materials[]; };
layout(set = 0, binding = BINDING_SPECTRA, std430) readonly buffer Spectra { float spectra[]; };

layout(push_constant) uniform Push { SpectralPushConstants pc; };

layout(location = 0) in vec3 worldPosition;
layout(location = 1) in vec3 worldNormal;

layout(location = 0) out vec4 out0;
#if OUTPUT_COUNT > 1
layout(location = 1) out vec4 out1;
#endif
#if OUTPUT_COUNT > 2
layout(location = 2) out vec4 out2;
#endif
#if OUTPUT_COUNT > 3
layout(location = 3) out vec4 out3;
#endif
#if OUTPUT_COUNT > 4
layout(location = 4) out vec4 out4;
#endif
#if OUTPUT_COUNT > 5
layout(location = 5) out vec4 out5;
#endif
#if OUTPUT_COUNT > 6
layout(location = 6) out vec4 out6;
#endif
#if OUTPUT_COUNT > 7
layout(location = 7) out vec4 out7;
#endif

const float INV_PI = 0.31830988618379067;

// Per-light geometric weights, computed once per fragment and shared by every band.
float diffuseWeight[LIGHT_SLOTS];   // g/π
float specularWeight[LIGHT_SLOTS];  // g·(N+8)/(8π)·(n·h)^N
float fluorescenceWeight;           // Σ_l g_l·coupling_l

float radiance(GpuMaterial m, int band) {
    if (band >= BAND_COUNT) return 0.0;
    float rd = spectra[m.diffuseOffset + band];
    float rs = HAS_SPECULAR ? spectra[m.specularOffset + band] : 0.0;
    float L = 0.0;
    for (int l = 0; l < LIGHT_COUNT; ++l) {
        float E = spectra[lights[l].spectrumOffset + band];
        L += E * (rd * diffuseWeight[l] + (HAS_SPECULAR ? rs * specularWeight[l] : 0.0));
    }
    if (HAS_FLUORESCENCE && m.fluorescent != 0u)
        L += fluorescenceWeight * spectra[m.emissionOffset + band];
    return L;
}

vec4 layerRadiance(GpuMaterial m, int layer) {
    int b = layer * 4;
    return vec4(radiance(m, b), radiance(m, b + 1), radiance(m, b + 2), radiance(m, b + 3));
}

void main() {
    GpuMaterial m = materials[pc.materialIndex];
    vec3 n = normalize(worldNormal);
    if (!gl_FrontFacing) n = -n;  // two-sided: a back face is shaded as seen from its front
    vec3 v = pc.cameraPosition.w > 0.5 ? normalize(pc.cameraPosition.xyz - worldPosition)
                                        : -pc.cameraForward.xyz;
    fluorescenceWeight = 0.0;
    for (int l = 0; l < LIGHT_COUNT; ++l) {
        GpuLight light = lights[l];
        float g;
        vec3 w = vec3(0.0);
        if (light.type == LIGHT_AMBIENT) {
            g = 1.0;  // irradiance on every surface, no cosine
        } else if (light.type == LIGHT_DIRECTIONAL) {
            w = light.vector.xyz;
            g = max(dot(n, w), 0.0);
        } else {
            vec3 d = light.vector.xyz - worldPosition;
            float d2 = dot(d, d);
            w = d * inversesqrt(d2);
            g = max(dot(n, w), 0.0) / d2;
        }
        diffuseWeight[l] = g * INV_PI;
        specularWeight[l] = 0.0;
        if (HAS_SPECULAR && m.hasSpecular != 0u && light.type != LIGHT_AMBIENT && g > 0.0) {
            vec3 h = normalize(w + v);
            float nh = max(dot(n, h), 0.0);
            float lobe = m.gloss == 0.0 ? 1.0 : pow(nh, m.gloss);  // x^0 = 1, also at x = 0
            specularWeight[l] = g * (m.gloss + 8.0) * (INV_PI / 8.0) * lobe;
        }
        if (HAS_FLUORESCENCE && m.fluorescent != 0u)
            fluorescenceWeight += g * spectra[m.couplingOffset + l];
    }

    int first = int(pc.firstLayer);
    out0 = layerRadiance(m, first + 0);
#if OUTPUT_COUNT > 1
    out1 = layerRadiance(m, first + 1);
#endif
#if OUTPUT_COUNT > 2
    out2 = layerRadiance(m, first + 2);
#endif
#if OUTPUT_COUNT > 3
    out3 = layerRadiance(m, first + 3);
#endif
#if OUTPUT_COUNT > 4
    out4 = layerRadiance(m, first + 4);
#endif
#if OUTPUT_COUNT > 5
    out5 = layerRadiance(m, first + 5);
#endif
#if OUTPUT_COUNT > 6
    out6 = layerRadiance(m, first + 6);
#endif
#if OUTPUT_COUNT > 7
    out7 = layerRadiance(m, first + 7);
#endif
}
