#version 450
// The spectral pass: single-scattering radiance (diffuse + Blinn–Phong specular + fluorescence,
// summed over the lights) for 4 bands per colour attachment, OUTPUT_COUNT attachments per pass.
// Physics and units: docs/physics.md. The CPU reference (engine/reference) computes the same
// quantities independently in double precision.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "interface.h"

// OUTPUT_COUNT (colour attachments of this pass, 1..8) is a compile-time define: the build makes
// one SPIR-V variant per count, so no variant declares an output its render pass lacks.
#ifndef OUTPUT_COUNT
#define OUTPUT_COUNT MAX_OUTPUTS
#endif

layout(constant_id = SPEC_AMBIENT_COUNT) const int AMBIENT_COUNT = 0;
layout(constant_id = SPEC_DIRECTIONAL_COUNT) const int DIRECTIONAL_COUNT = 0;
layout(constant_id = SPEC_POINT_COUNT) const int POINT_COUNT = 0;
layout(constant_id = SPEC_HAS_SPECULAR) const bool HAS_SPECULAR = true;
layout(constant_id = SPEC_HAS_FLUORESCENCE) const bool HAS_FLUORESCENCE = true;
layout(constant_id = SPEC_HAS_TEXTURES) const bool HAS_TEXTURES = false;
layout(constant_id = SPEC_HAS_NORMAL_MAPS) const bool HAS_NORMAL_MAPS = false;
layout(constant_id = SPEC_FLUORESCENCE_SPECTRA) const bool FLUORESCENCE_SPECTRA = false;
// The response pass: the outputs are a detector's channels (OUTPUT_COUNT ≤ RESPONSE_VEC4 vec4),
// summed from per-(material, light) responses instead of bands (interface.h, GpuResponseBlock).
layout(constant_id = SPEC_RESPONSES) const bool RESPONSES = false;
layout(constant_id = SPEC_HEMISPHERE_COUNT) const int HEMISPHERE_COUNT = 0;
// Any light casts shadows: the shadow maps are read (a scene without pays nothing).
layout(constant_id = SPEC_SHADOWS) const bool SHADOWS = false;
layout(constant_id = SPEC_LOBE_MODE) const int LOBE_MODE = LOBE_COMPUTE;
layout(constant_id = SPEC_SHADOWED_DIRECTIONAL) const int SHADOWED_DIRECTIONAL = 0;
layout(constant_id = SPEC_SHADOWED_POINT) const int SHADOWED_POINT = 0;
layout(constant_id = SPEC_HEMISPHERE_PAIRED) const uint HEMISPHERE_PAIRED = 0u;

layout(set = 0, binding = BINDING_LIGHTS, std140) uniform Lights { GpuLightBlock L; };
layout(set = 0, binding = BINDING_LIGHT_SPECTRA, std140) uniform LightSpectra { GpuLightSpectraBlock E; };
layout(set = 0, binding = BINDING_MATERIAL, std140) uniform Material { GpuMaterialBlock M; };
layout(set = 0, binding = BINDING_FLUORESCENCE, std140) uniform Fluorescence { GpuFluorescenceBlock F; };
layout(set = 0, binding = BINDING_RESPONSES, std140) uniform Responses { GpuResponseBlock R; };
layout(set = 0, binding = BINDING_SHADOW_MATRICES, std140) uniform Shadows { GpuShadowBlock S; };
layout(set = 0, binding = BINDING_SHADOW_MAP) uniform sampler2DArrayShadow shadowMap;
layout(set = 0, binding = BINDING_LOBE_WEIGHTS) uniform sampler2D lobeWeights;
layout(set = 0, binding = BINDING_LOBE_TABLES) uniform usamplerBuffer lobeData;

layout(set = 1, binding = TEXTURE_BINDING_DIFFUSE) uniform sampler2DArray diffuseTexture;
layout(set = 1, binding = TEXTURE_BINDING_SPECULAR) uniform sampler2DArray specularTexture;
layout(set = 1, binding = TEXTURE_BINDING_NORMAL) uniform sampler2DArray normalTexture;

layout(push_constant) uniform Push { SpectralPushConstants pc; };

layout(location = 0) in vec3 worldPosition;
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

const float INV_PI = 0.31830988618379067;
const float FLT_MIN_NORMAL = 1.17549435e-38;
const float FLT_MAX_FINITE = 3.40282347e38;

vec4 acc[OUTPUT_COUNT];  // this pass's bands, 4 per attachment
float fluorescence;      // rank-one form: Σ_l g_l·coupling_l, scales ê(λ)/λ

float coupling(int l) { return M.coupling[l / 4][l % 4]; }

// Textured reflectance at this fragment (HAS_TEXTURES only): the material's spectra times the
// textures' bands.
vec4 texturedDiffuse[OUTPUT_COUNT];
vec4 texturedSpecular[OUTPUT_COUNT];
vec4 diffuseAt(int k) { return HAS_TEXTURES ? texturedDiffuse[k] : M.diffuse[k]; }
vec4 specularAt(int k) { return HAS_TEXTURES ? texturedSpecular[k] : M.specular[k]; }

// Bilinear filtering by hand, so that it is float arithmetic the CPU reference can match (the
// sampler's own filtering uses the device's sub-texel precision, 8 bits on lavapipe). Texel
// centres lie at (i + ½)/W; coordinates repeat. docs/physics.md, "Textures".
struct Bilinear {
    ivec2 x, y;  // the two columns and rows
    vec2 f;      // weights of the second column and row
};
Bilinear bilinearAt(vec2 size) {
    vec2 p = fract(uv) * size - 0.5;
    vec2 p0 = floor(p);
    Bilinear b;
    b.f = p - p0;
    ivec2 i0 = ivec2(p0), n = ivec2(size);
    ivec2 a = (i0 % n + n) % n, c = (i0 + 1) % n;
    b.x = ivec2(a.x, c.x);
    b.y = ivec2(a.y, c.y);
    return b;
}
vec4 fetchBilinear(sampler2DArray t, Bilinear b, int layer) {
    vec4 t00 = texelFetch(t, ivec3(b.x[0], b.y[0], layer), 0), t10 = texelFetch(t, ivec3(b.x[1], b.y[0], layer), 0);
    vec4 t01 = texelFetch(t, ivec3(b.x[0], b.y[1], layer), 0), t11 = texelFetch(t, ivec3(b.x[1], b.y[1], layer), 0);
    return mix(mix(t00, t10, b.f.x), mix(t01, t11, b.f.x), b.f.y);
}

// Response pass: where this fragment reads the material's response textures, if it has them.
bool diffuseResponseTexture, specularResponseTexture;
Bilinear diffuseTexel, specularTexel;

void sampleTextures() {
    if (RESPONSES) {
        diffuseResponseTexture = (M.switches.x & MATERIAL_DIFFUSE_TEXTURE) != 0u;
        specularResponseTexture = HAS_SPECULAR && (M.switches.x & MATERIAL_SPECULAR_TEXTURE) != 0u;
        if (diffuseResponseTexture) diffuseTexel = bilinearAt(vec2(textureSize(diffuseTexture, 0).xy));
        if (specularResponseTexture) specularTexel = bilinearAt(vec2(textureSize(specularTexture, 0).xy));
        return;
    }
    int layer0 = int(M.params.y);
    if ((M.switches.x & MATERIAL_DIFFUSE_TEXTURE) != 0u) {
        Bilinear b = bilinearAt(vec2(textureSize(diffuseTexture, 0).xy));
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k)
            texturedDiffuse[k] = M.diffuse[k] * fetchBilinear(diffuseTexture, b, layer0 + k);
    } else {
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) texturedDiffuse[k] = M.diffuse[k];
    }
    if (HAS_SPECULAR && (M.switches.x & MATERIAL_SPECULAR_TEXTURE) != 0u) {
        Bilinear b = bilinearAt(vec2(textureSize(specularTexture, 0).xy));
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k)
            texturedSpecular[k] = M.specular[k] * fetchBilinear(specularTexture, b, layer0 + k);
    } else {
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) texturedSpecular[k] = M.specular[k];
    }
}

// The shading normal perturbed by the normal map: m (bilinear, renormalized) in the frame
// (t, b, n) with t the tangent made perpendicular to n and b = cross(n, t)·w. Where the tangent
// is missing (zero) or parallel to n, n is kept.
vec3 normalMapped(vec3 n) {
    vec3 t = worldTangent.xyz - n * dot(n, worldTangent.xyz);
    if (!(dot(t, t) > 1e-12)) return n;
    t = normalize(t);
    vec3 b = cross(n, t) * (worldTangent.w < 0.0 ? -1.0 : 1.0);
    vec3 m = fetchBilinear(normalTexture, bilinearAt(vec2(textureSize(normalTexture, 0).xy)), 0).xyz;
    if (!(dot(m, m) > 1e-12)) return n;
    m = normalize(m);
    return normalize(t * m.x + b * m.y + n * m.z);
}

// Adds light l's reflected radiance with geometric weights: diffuse g/π, specular lobe weight
// (in the response pass, the detector's response to it).
void addLight(int l, float diffuseWeight, float specularWeight) {
    if (RESPONSES) {
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) {
            const int r = l * RESPONSE_VEC4 + k;
            bool dt = HAS_TEXTURES && diffuseResponseTexture;
            vec4 d = dt ? fetchBilinear(diffuseTexture, diffuseTexel, r) : R.diffuse[r];
            acc[k] += d * diffuseWeight;
            if (HAS_SPECULAR) {
                bool st = HAS_TEXTURES && specularResponseTexture;
                vec4 sp = st ? fetchBilinear(specularTexture, specularTexel, r) : R.specular[r];
                acc[k] += sp * specularWeight;
            }
        }
        return;
    }
    [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) {
        vec4 reflectance = diffuseAt(k) * diffuseWeight;
        if (HAS_SPECULAR) reflectance += specularAt(k) * specularWeight;
        acc[k] += E.lightBands[l * MAX_OUTPUTS + k] * reflectance;
    }
}

// Light l's fluorescence with geometric factor g: the rank-one form sums g·coupling_l (times ê/λ
// at the end); with a Donaldson matrix in the scene, every fluorescent material adds g·F_l(λ).
void addFluorescence(int l, float g) {
    if (!HAS_FLUORESCENCE) return;
    if (RESPONSES) {
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] += g * R.fluorescence[l * RESPONSE_VEC4 + k];
        return;
    }
    if (FLUORESCENCE_SPECTRA)
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] += g * F.emitted[l * MAX_OUTPUTS + k];
    else
        fluorescence += g * coupling(l);
}

// (n·h)^N for unit n and h, with x^0 = 1 (also at x = 0). Near the lobe's peak n·h rounds to
// within 2^-24 of 1, and pow() turns that into a relative error of N·2^-24 (1e-2 at N = 1e5,
// 8e-2 at N = 1e6). For unit vectors 1 − n·h = |n − h|²/2, which keeps its relative precision as
// h → n; so there ln(n·h) = ln(1 − s) is taken from its series, −(s + s²/2 + … + s⁶/6), whose
// truncation (below s⁶/7 relative, 9e-9 at s = 1/16) is negligible. Docs: docs/numerics.md.
// Written with selects rather than early returns, which cost lavapipe 12% of the shading time of
// a glossy scene; this form costs about what pow() alone did.
float blinnPhongLobe(vec3 n, vec3 wPlusV, float gloss) {
    vec3 h = normalize(wPlusV);
    float nh = dot(n, h);
    vec3 d = n - h;
    float s = 0.5 * dot(d, d);
    float series = -s * (1.0 + s * (1.0 / 2.0 + s * (1.0 / 3.0 + s * (1.0 / 4.0 + s * (1.0 / 5.0 + s * (1.0 / 6.0))))));
    float logNh = log(nh);
    float lobe = exp(gloss * (s < 0.0625 ? series : logNh));
    // No lobe behind the surface, nor for a light exactly opposite the eye (w + v = 0: no half
    // vector, and h above is NaN), as in the reference; x^0 = 1 everywhere.
    lobe = nh > 0.0 && dot(wPlusV, wPlusV) > 0.0 ? lobe : 0.0;
    return gloss == 0.0 ? 1.0 : lobe;
}

// The hemisphere lights' lobe tables (shaders/lobe_lookup.h), the same lookup the CPU reference runs.
#define LT_FLOAT float
#define LT_VEC2 vec2
#define LT_VEC3 vec3
#define LT_VEC4 vec4
#define LOBE_DATA_PARAM
#define LOBE_FETCH(i) texelFetch(lobeData, (i))
#define LOBE_FLOATS(u) uintBitsToFloat(u)
#define LOBE_UNORM(x) unpackUnorm2x16(x)
#include "lobe_lookup.h"

// Whether light l reaches p (1) or is blocked (0), from its shadow map: the layer (a point light's
// cube face by the major axis of p − light), p pushed SHADOW_NORMAL_OFFSET texels along the face
// normal ng (towards the light) so that a surface does not shadow itself, one depth comparison (no
// filtering: the boundary is where the reference's is, to within a texel). Outside the map: lit.
float visibility(int l, vec3 p, vec3 ng, vec3 w, bool point) {
    if (!SHADOWS) return 1.0;
    vec4 info = L.lights[l].shadow;
    int layer = int(info.x);
    float texel = info.y;
    if (point) {
        vec3 a = abs(p - L.lights[l].vector.xyz);
        texel *= max(a.x, max(a.y, a.z));
    }
    if (dot(ng, w) < 0.0) ng = -ng;
    vec3 o = p + ng * (SHADOW_NORMAL_OFFSET * texel);
    if (point) {  // the cube face of the offset point, so the lookup never leaves its face
        vec3 d = o - L.lights[l].vector.xyz, a = abs(d);
        layer += a.x >= a.y && a.x >= a.z ? (d.x >= 0.0 ? 0 : 1) : a.y >= a.z ? (d.y >= 0.0 ? 2 : 3) : (d.z >= 0.0 ? 4 : 5);
    }
    vec4 c = S.layers[layer] * vec4(o, 1.0);
    vec3 q = c.xyz / c.w;
    vec2 st = q.xy * 0.5 + 0.5;
    if (any(lessThan(st, vec2(0.0))) || any(greaterThan(st, vec2(1.0))) || q.z > 1.0) return 1.0;
    // On a cube face's edge st reaches 1 (the edge of the last texel), which the sampler would
    // read as its border: keep the lookup on the face's outermost texels.
    st = clamp(st, vec2(0.5 / float(SHADOW_MAP_SIZE)), vec2(1.0 - 0.5 / float(SHADOW_MAP_SIZE)));
    // Explicit zero gradients: the lookup sits in non-uniform control flow, and the map has one level.
    return textureGrad(shadowMap, vec4(st, float(layer), q.z), vec2(0.0), vec2(0.0));
}

// Hemisphere light i's lobe integral I and the unoccluded lobe's, (I, I_unoccluded): from the
// material's lobe table, in closed form at gloss 0 (π(1 + n·u)/2 and π); a ground right after its
// sky takes the rest of the whole lobe. `previous` carries the last light's.
float hemisphereIntegral(int i, vec3 n, vec3 v, inout vec2 previous) {
    int l = AMBIENT_COUNT + DIRECTIONAL_COUNT + POINT_COUNT + i;
    float gloss = M.params.x;
    vec3 up = L.lights[l].vector.xyz;
    vec2 integrals = vec2(0.0);
    if (HAS_SPECULAR && (M.switches.x & MATERIAL_SPECULAR) != 0u) {
        if (LOBE_MODE == LOBE_READ)
            integrals.x = texelFetch(lobeWeights, ivec2(gl_FragCoord.xy), 0)[i];
        else if (((HEMISPHERE_PAIRED >> uint(i)) & 1u) != 0u)
            integrals = vec2(max(0.0, previous.y - previous.x), previous.y);
        else if (gloss == 0.0)
            integrals = vec2(0.5 * LOBE_PI * (1.0 + dot(n, up)), LOBE_PI);
        else
            integrals = lobeIntegrals(int(M.lobe.x), M.lobe.yz, n, v, up);
    }
    previous = integrals;
    return integrals.x;
}

// Blinn–Phong, energy-normalized: g·(N+8)/(8π)·(n·h)^N.
float specularWeight(vec3 n, vec3 w, vec3 v, float g) {
    if (!HAS_SPECULAR || g <= 0.0) return 0.0;
    float gloss = M.params.x;
    float lobe = g * (gloss + 8.0) * (INV_PI / 8.0) * blinnPhongLobe(n, w + v, gloss);
    return (M.switches.x & MATERIAL_SPECULAR) != 0u ? lobe : 0.0;
}

void main() {
    // The face normal, from the position's screen-space derivatives: taken here, in uniform
    // control flow, because derivatives are undefined inside a branch.
    vec3 faceNormal = cross(dFdx(worldPosition), dFdy(worldPosition));
    vec3 v = pc.cameraPosition.w > 0.5 ? normalize(pc.cameraPosition.xyz - worldPosition)
                                        : -pc.cameraForward.xyz;
    vec3 n;
    if (dot(worldNormal, worldNormal) > 1e-24) {
        n = normalize(worldNormal);
        // The map perturbs the front side's normal; a back face then sees it mirrored, whole.
        if (HAS_NORMAL_MAPS && (M.switches.x & MATERIAL_NORMAL_TEXTURE) != 0u) n = normalMapped(n);
        if (!gl_FrontFacing) n = -n;  // two-sided: a back face is shaded as seen from its front
    } else {
        // The vertex normals cancel here (opposite ones, or a zero-length one at its corner;
        // triangles with no usable normal at all carry their face normal, see pack()), and
        // normalize() would give NaN. As the reference does (docs/physics.md, "Two-sided
        // shading"), shade with the face normal turned towards the eye; a face seen exactly
        // edge-on has none, and takes v.
        n = dot(faceNormal, faceNormal) > 0.0 ? normalize(faceNormal) : v;
        if (dot(n, v) < 0.0) n = -n;
    }
    if (LOBE_MODE == LOBE_WRITE) {  // the lobe pass: only the hemisphere lights' integrals
        vec4 integrals = vec4(0.0);
        vec2 previous = vec2(0.0);
        [[unroll]] for (int i = 0; i < min(HEMISPHERE_COUNT, MAX_LOBE_LIGHTS); ++i)
            integrals[i] = hemisphereIntegral(i, n, v, previous);
        out0 = integrals;
        return;
    }
    [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] = vec4(0.0);
    fluorescence = 0.0;
    if (HAS_TEXTURES) sampleTextures();

    // Ambient: irradiance on every surface, no cosine, no specular.
    [[unroll]] for (int i = 0; i < AMBIENT_COUNT; ++i) {
        int l = i;
        addLight(l, INV_PI, 0.0);
        addFluorescence(l, 1.0);
    }
    vec3 ng = dot(faceNormal, faceNormal) > 0.0 ? normalize(faceNormal) : n;
    [[unroll]] for (int i = 0; i < DIRECTIONAL_COUNT; ++i) {
        int l = AMBIENT_COUNT + i;
        vec3 w = L.lights[l].vector.xyz;
        float g = max(dot(n, w), 0.0);
        if (i < SHADOWED_DIRECTIONAL && g > 0.0) g *= visibility(l, worldPosition, ng, w, false);
        addLight(l, g * INV_PI, specularWeight(n, w, v, g));
        addFluorescence(l, g);
    }
    // Point: E = I·cosθ/d², d in the frame's units (vector.w turns 1/d² into m⁻²). A light on the
    // surface (d = 0, or d² below float32's normal range) has no direction and contributes nothing,
    // as in the reference (docs/physics.md); the clamp keeps g finite beside it, so that a lobe of
    // 0 never meets an infinite g (Inf × 0 = NaN).
    [[unroll]] for (int i = 0; i < POINT_COUNT; ++i) {
        int l = AMBIENT_COUNT + DIRECTIONAL_COUNT + i;
        vec3 d = L.lights[l].vector.xyz - worldPosition;
        float d2 = dot(d, d);
        bool apart = d2 >= FLT_MIN_NORMAL;
        vec3 w = apart ? d * inversesqrt(d2) : n;
        float g = apart ? min(max(dot(n, w), 0.0) / d2 * L.lights[l].vector.w, FLT_MAX_FINITE) : 0.0;
        if (i < SHADOWED_POINT && g > 0.0) g *= visibility(l, worldPosition, ng, w, true);
        addLight(l, g * INV_PI, specularWeight(n, w, v, g));
        addFluorescence(l, g);
    }
    // Hemisphere: radiance L from every ω with ω·u > 0, not occluded. Irradiance π·L·(1 + n·u)/2
    // exactly; the lobe's integral over the lune from the material's lobe table (lobe_lookup.h).
    vec2 previousLobe = vec2(0.0);
    [[unroll]] for (int i = 0; i < HEMISPHERE_COUNT; ++i) {
        int l = AMBIENT_COUNT + DIRECTIONAL_COUNT + POINT_COUNT + i;
        vec3 up = L.lights[l].vector.xyz;
        float g = 0.5 * (1.0 + dot(n, up));
        float gloss = M.params.x;
        float lobe = (gloss + 8.0) * (INV_PI / 8.0) * hemisphereIntegral(i, n, v, previousLobe);
        addLight(l, g, lobe);
        addFluorescence(l, 3.14159265358979 * g);
    }
    // ê/λ and the couplings come scaled by reciprocal powers of two (pack() in spectral_pass.cpp)
    // so that neither overflows before their product does.
    if (HAS_FLUORESCENCE && !FLUORESCENCE_SPECTRA && !RESPONSES)
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] += fluorescence * M.emissionOverLambda[k];

    out0 = acc[0];
#if OUTPUT_COUNT > 1
    out1 = acc[1];
#endif
#if OUTPUT_COUNT > 2
    out2 = acc[2];
#endif
#if OUTPUT_COUNT > 3
    out3 = acc[3];
#endif
#if OUTPUT_COUNT > 4
    out4 = acc[4];
#endif
#if OUTPUT_COUNT > 5
    out5 = acc[5];
#endif
#if OUTPUT_COUNT > 6
    out6 = acc[6];
#endif
#if OUTPUT_COUNT > 7
    out7 = acc[7];
#endif
}
