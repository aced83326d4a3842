#version 450
// Transparent surfaces, in three uses. The channel passes (CHANNEL_OUTPUT, below): each crossing
// adds to its material's optical-depth channels — the camera's, once per frame, and the coloured
// shadows' maps from each light. The transmission pass (with slabs in the scene, or more channels
// than one pass holds): after a band pass has written the radiance of the opaque surfaces, every
// transparent surface in front of them multiplies it, band by band, by its factor (blend:
// destination × source); the depth pre-pass left the opaque surfaces' distance (opaque_distance.frag).
// Sheets and media only multiply, which commutes; slabs also add their reflection, so the draws
// go farthest first (render/spectral_recording.cpp). Physics: docs/physics.md, "Transparent
// objects"; the CPU reference follows the same straight rays in double (reference/cpu_renderer).
//
// - A thin sheet (MATERIAL_FILTER) in front of the opaque surface multiplies by T(λ).
// - A slab (MATERIAL_SLAB) multiplies by its Fresnel transmittance at this angle, then, in a
//   second draw (REFLECTION), adds its reflectance times the light from the mirror direction.
// - An absorbing medium (MATERIAL_MEDIUM) in a closed mesh multiplies by exp2(−k·ℓ), ℓ the path
//   inside it before the opaque surface. Along a ray, ℓ = Σ min(t_leave, t_o) − Σ min(t_enter, t_o)
//   (t_o the opaque surface's distance): each face the ray enters by (a front face) contributes
//   exp2(+k·s) and each it leaves by exp2(−k·s), s = min(t, t_o) − t_ref, whatever their order.
//   A face behind the opaque surface is clamped to it, so its pair cancels; t_ref (the nearest
//   point of the mesh's bounds) keeps s ≥ 0 and within the mesh's size. An entering face's factor
//   exceeds 1 and is capped at 2^ENTRY_LIMIT, so that the radiance times it stays finite before
//   the leaving face's factor brings it back: exact while the medium's absorbance across its
//   bounds stays below ENTRY_LIMIT·log10(2) ≈ 19 (docs/physics.md); deeper rays come out darker.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "interface.h"
#include "runtime_value.glsl"

#ifndef OUTPUT_COUNT
#define OUTPUT_COUNT MAX_OUTPUTS
#endif

// The coloured shadows' passes (drawn from a light, render/shadow_transmittance.cpp) write the
// optical-depth channels instead (interface.h), blended by addition: a sheet's crossing adds 1 to
// its material's channel, a medium's face ±its distance (the path ℓ, summed), a slab's 1 and cos θ
// to its pair — the same for every band, so a map holds ⌈channels / 4⌉ layers, not the bands.
// This pass's outputs are channels FIRST_CHANNEL … FIRST_CHANNEL + 4·OUTPUT_COUNT − 1.
layout(constant_id = TRANSMIT_SPEC_CHANNEL_OUTPUT) const bool CHANNEL_OUTPUT = false;
layout(constant_id = TRANSMIT_SPEC_FIRST_CHANNEL) const int FIRST_CHANNEL = 0;
// With slabs (interface.h): SPLIT — a crossing in front of the nearest slab goes to the second half
// of the outputs; FRONT — the nearest slab's second draw multiplies by τ of the crossings in front of
// it, from the channel pass's second set (VIEW_CHANNELS channels, rows in depthSpectra).
layout(constant_id = TRANSMIT_SPEC_SPLIT) const bool SPLIT = false;
layout(constant_id = TRANSMIT_SPEC_FRONT) const bool FRONT = false;
layout(constant_id = TRANSMIT_SPEC_VIEW_CHANNELS) const int VIEW_CHANNELS = 0;
layout(constant_id = TRANSMIT_SPEC_BAND_LAYERS) const int BAND_LAYERS = 1;
// The slabs' second draw: their reflection R·L(mirror direction), added (blend destination + source)
// after their transmittance has multiplied what is behind — draws go back to front.
layout(constant_id = TRANSMIT_SPEC_REFLECTION) const bool REFLECTION = false;
layout(constant_id = TRANSMIT_SPEC_AMBIENT_COUNT) const int AMBIENT_COUNT = 0;
layout(constant_id = TRANSMIT_SPEC_HEMISPHERE_FIRST) const int HEMISPHERE_FIRST = 0;
layout(constant_id = TRANSMIT_SPEC_HEMISPHERE_COUNT) const int HEMISPHERE_COUNT = 0;
// The response pass's slab reflection: REFLECTION's radiance summed against the detector over
// every band (GpuResponseBlock::spectra.y), × τ of what lies in front of the slab, into the
// response pass's channels (added).
layout(constant_id = TRANSMIT_SPEC_RESPONSES) const bool RESPONSES = false;
layout(constant_id = TRANSMIT_SPEC_RESPONSE_CHANNELS) const int RESPONSE_CHANNELS = 4 * MAX_OUTPUTS;
layout(constant_id = TRANSMIT_SPEC_RESPONSE_FIRST_LAYER) const int RESPONSE_FIRST_LAYER = 0;
layout(constant_id = TRANSMIT_SPEC_RESPONSE_END_LAYER) const int RESPONSE_END_LAYER = 1;

layout(set = 0, binding = BINDING_LIGHTS, std140) uniform Lights { GpuLightBlock L; };
layout(set = 0, binding = BINDING_LIGHT_SPECTRA, std140) uniform LightSpectra { GpuLightSpectraBlock E; };
layout(set = 0, binding = BINDING_MATERIAL, std140) uniform Material { GpuMaterialBlock M; };
layout(set = 0, binding = BINDING_RESPONSES, std140) uniform Responses { GpuResponseBlock R; };
layout(set = 0, binding = BINDING_OPAQUE_DISTANCE) uniform sampler2D opaqueDistance;
layout(set = 0, binding = BINDING_SLAB_DISTANCE) uniform sampler2D slabDistance;
layout(set = 0, binding = BINDING_VIEW_CHANNELS) uniform sampler2DArray viewChannels;
layout(set = 0, binding = BINDING_DEPTH_SPECTRA) uniform samplerBuffer depthSpectra;
#include "view_channels.glsl"
#include "slab_fresnel.glsl"
layout(push_constant) uniform Push { SpectralPushConstants pc; };

layout(location = 0) in vec3 worldPosition;
// The rest of spectral.vert's outputs, declared so that the interfaces match; not read.
layout(location = 1) in vec3 worldNormal;
layout(location = 2) in vec2 uv;
layout(location = 3) in vec4 worldTangent;

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

// An entering face's factor is at most 2^ENTRY_LIMIT: radiances up to ~10¹⁹ times it stay finite.
const float ENTRY_LIMIT = 64.0;
const float INV_PI = 0.31830988618379067;

vec4 factor[OUTPUT_COUNT];

void writeOutputs();  // factor to the attachments (after main)
bool inFront = false;  // SPLIT: this crossing lies in front of the nearest slab

// CHANNEL_OUTPUT: `value` into this material's first channel (params.w) and, for a slab's pair,
// `second` into the next; 0 in the other channels of this pass. SPLIT: into the set in front of
// the nearest slab or behind it (inFront), or — a medium's face, whose path may straddle the slab —
// `value` behind it and `frontValue` in front.
void writeChannels(float value, float second, bool pair, float frontValue) {
    const int first = int(runtimeValue(M.params.w)) - FIRST_CHANNEL;
    const int frontFirst = 4 * (OUTPUT_COUNT / 2);
    for (int k = 0; k < OUTPUT_COUNT; ++k)
        for (int j = 0; j < 4; ++j) {
            int c = 4 * k + j;
            float v = 0.0;
            if (SPLIT && c >= frontFirst) {  // the front set
                c -= frontFirst;
                v = c == first ? frontValue : 0.0;
            } else {
                v = c == first ? value : pair && c == first + 1 ? second : 0.0;
            }
            factor[k][j] = v;
        }
}
void writeChannels(float value, float second, bool pair) {
    if (SPLIT && inFront)
        writeChannels(0.0, 0.0, false, value);  // a sheet's crossing in front of the nearest slab
    else
        writeChannels(value, second, pair, 0.0);
}

void main() {
    // Distances along the ray, in units: from the eye (perspective) or the camera's plane
    // (orthographic), as opaque_distance.frag measures the opaque surface's, tO.
    const bool perspective = pc.cameraPosition.w > 0.5;
    const vec3 p = worldPosition, c = pc.cameraPosition.xyz;
    const float t = perspective ? length(p - c) : dot(p - c, pc.cameraForward.xyz);
    const float tO = texelFetch(opaqueDistance, ivec2(gl_FragCoord.xy), 0).r;
    // The nearest slab's distance (none: the largest float); SPLIT: what lies in front of it, where
    // it lies in front of the opaque surface (elsewhere nothing is: the band passes apply it all).
    const float tS = SPLIT || FRONT ? texelFetch(slabDistance, ivec2(gl_FragCoord.xy), 0).r : 0.0;
    const bool slabSeen = tS < tO;
    if (SPLIT) inFront = slabSeen && t < tS;
    if ((runtimeValue(M.switches.x) & MATERIAL_SLAB) != 0u) {
        // A slab (docs/physics.md, "Transparent objects"): slabFresnel for n(λ) at this angle.
        // Hidden behind the opaque surface.
        if (t >= tO) discard;
        if (FRONT) {
            // Only the nearest slab multiplies, once: by τ of the sheets and media in front of it.
            if (t > tS) discard;
            fetchViewChannels(1);
            const int first = int(runtimeValue(M.params.y));
            for (int k = 0; k < OUTPUT_COUNT; ++k) factor[k] = viewTransmittance(first + k);
            writeOutputs();
            return;
        }
        vec3 nrm = dot(worldNormal, worldNormal) > 1e-24 ? normalize(worldNormal) : vec3(0.0, 0.0, 1.0);
        const vec3 v = perspective ? normalize(c - p) : -pc.cameraForward.xyz;
        if (dot(nrm, v) < 0.0) nrm = -nrm;
        const float cosI = min(dot(nrm, v), 1.0);
        if (CHANNEL_OUTPUT) {
            writeChannels(1.0, cosI, true);
            writeOutputs();
            return;
        }
        const vec3 mirror = reflect(-v, nrm);
        if (RESPONSES) {
            // Σ over every band layer j of R_j·τ_front,j against the environment's detector-weighted
            // spectra: ambient lights' E/π, hemisphere lights' L where the mirror direction is in
            // their hemisphere (C = 4·OUTPUT_COUNT channels, interface.h GpuResponseBlock::spectra.y).
            // Only the detector's channels and the band layers it sees (the rest are zero); τ_front
            // only where something lies in front (a loop bound: lavapipe runs both sides of a branch).
            fetchViewChannels(1);
            bool frontClear = true;
            [[unroll]] for (int i = 0; i < VIEW_ARRAY; ++i) frontClear = frontClear && viewChannel[i] == 0.0;
            const int frontPasses = frontClear ? 0 : 1;
            const int C = 4 * OUTPUT_COUNT, channel = int(runtimeValue(M.params.w));
            for (int k = 0; k < OUTPUT_COUNT; ++k) factor[k] = vec4(0.0);
            for (int j = RESPONSE_FIRST_LAYER; j < RESPONSE_END_LAYER; ++j) {
                vec4 T, Rj;
                slabFresnel(cosI, texelFetch(depthSpectra, channel * BAND_LAYERS + j),
                            texelFetch(depthSpectra, (channel + 1) * BAND_LAYERS + j), T, Rj);
                vec4 front = vec4(1.0);
                for (int pass = 0; pass < frontPasses; ++pass) front = viewTransmittance(j);
                Rj *= front;
                [[unroll]] for (int c = 0; c < C && c < RESPONSE_CHANNELS; ++c) {
                    vec4 environment = vec4(0.0);
                    for (int i = 0; i < AMBIENT_COUNT; ++i)
                        environment += texelFetch(depthSpectra, R.spectra.y + (i * C + c) * BAND_LAYERS + j) * INV_PI;
                    for (int i = 0; i < HEMISPHERE_COUNT; ++i) {
                        const int l = HEMISPHERE_FIRST + i;
                        if (dot(mirror, L.lights[l].vector.xyz) > 0.0)
                            environment += texelFetch(depthSpectra, R.spectra.y + (l * C + c) * BAND_LAYERS + j);
                    }
                    factor[c / 4][c % 4] += dot(Rj, environment);
                }
            }
            writeOutputs();
            return;
        }
        for (int k = 0; k < OUTPUT_COUNT; ++k) {
            vec4 T, Rk;
            slabFresnel(cosI, M.ior[k], M.attenuation[k], T, Rk);
            if (!REFLECTION) {
                factor[k] = T;
                continue;
            }
            // The environment the mirror direction sees: ambient E/π, a hemisphere light's L.
            vec4 environment = vec4(0.0);
            for (int i = 0; i < AMBIENT_COUNT; ++i) environment += E.lightBands[i * MAX_OUTPUTS + k] * INV_PI;
            for (int i = 0; i < HEMISPHERE_COUNT; ++i) {
                const int l = HEMISPHERE_FIRST + i;
                if (dot(mirror, L.lights[l].vector.xyz) > 0.0) environment += E.lightBands[l * MAX_OUTPUTS + k];
            }
            factor[k] = Rk * environment;
        }
    } else if ((runtimeValue(M.switches.x) & MATERIAL_MEDIUM) == 0u) {
        // A sheet on or behind the opaque surface is hidden by it.
        if (t >= tO) discard;
        if (CHANNEL_OUTPUT) {
            writeChannels(1.0, 0.0, false);
            writeOutputs();
            return;
        }
        for (int k = 0; k < OUTPUT_COUNT; ++k) factor[k] = M.transmittance[k];
    } else {
        // s = t − t_ref, the distance along the ray past the mesh's nearest point q (pc.draw.xyz), from
        // differences of nearby points rather than of two distances from the camera, which would
        // lose the path's precision when the camera is far (t ≫ the mesh): for a perspective camera
        // |p − c| − |q − c| = (p − q)·((p − c) + (q − c)) / (|p − c| + |q − c|); orthographic, (p − q)·f.
        const vec3 q = pc.draw.xyz;
        float s = perspective ? dot(p - q, (p - c) + (q - c)) / (t + length(q - c)) : dot(p - q, pc.cameraForward.xyz);
        if (t > tO) s -= t - tO;  // behind the opaque surface: the path ends there
        if (CHANNEL_OUTPUT) {
            // The path: + where the ray leaves, − where it enters. SPLIT: the part up to the nearest
            // slab in front, the rest behind (ℓ_front = Σ ±(min(t, tS) − t_ref)).
            const float sign = gl_FrontFacing ? -1.0 : 1.0;
            const float sFront = SPLIT && slabSeen ? s - max(min(t, tO) - tS, 0.0) : 0.0;
            if (SPLIT)
                writeChannels(sign * (s - sFront), 0.0, false, sign * sFront);
            else
                writeChannels(sign * s, 0.0, false);
            writeOutputs();
            return;
        }
        if (!gl_FrontFacing) s = -s;
        for (int k = 0; k < OUTPUT_COUNT; ++k) factor[k] = exp2(min(M.attenuation[k] * s, vec4(ENTRY_LIMIT)));
    }
    writeOutputs();
}

void writeOutputs() {
    out0 = factor[0];
#if OUTPUT_COUNT > 1
    out1 = factor[1];
#endif
#if OUTPUT_COUNT > 2
    out2 = factor[2];
#endif
#if OUTPUT_COUNT > 3
    out3 = factor[3];
#endif
#if OUTPUT_COUNT > 4
    out4 = factor[4];
#endif
#if OUTPUT_COUNT > 5
    out5 = factor[5];
#endif
#if OUTPUT_COUNT > 6
    out6 = factor[6];
#endif
#if OUTPUT_COUNT > 7
    out7 = factor[7];
#endif
}
