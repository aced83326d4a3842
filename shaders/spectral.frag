#version 450
// The spectral pass: single-scattering radiance (diffuse + Blinn–Phong specular + fluorescence,
// summed over the lights) for 4 bands per colour attachment, OUTPUT_COUNT attachments per pass.
// Physics and units: docs/physics.md. The CPU reference (engine/reference) computes the same
// quantities independently in double precision.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "interface.h"
#include "runtime_value.glsl"

// OUTPUT_COUNT (colour attachments of this pass, 1..8) is a compile-time define: the build makes
// one SPIR-V variant per count, so no variant declares an output its render pass lacks.
#ifndef OUTPUT_COUNT
#define OUTPUT_COUNT MAX_OUTPUTS
#endif
// The response pass through filters in two draws (render/spectral_pipelines.cpp): this build sums
// no band; where a pixel needs the per-band sums it writes its depth to one more attachment, and
// the FILTERED_RESPONSES build is then drawn over those pixels only (docs/color.md).
#ifdef RESPONSES_WITHOUT_BANDS
#define FILTERED_RESPONSES 1
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
// Coloured shadows: shadowing lights are filtered by the transparent objects on their way.
layout(constant_id = SPEC_FILTERED_SHADOWS) const bool FILTERED_SHADOWS = false;
layout(constant_id = SPEC_BAND_LAYERS) const int BAND_LAYERS = 1;
layout(constant_id = SPEC_DEPTH_CHANNELS) const int DEPTH_CHANNELS = 0;
layout(constant_id = SPEC_SLAB_CHANNELS) const int SLAB_CHANNELS = 0;
const int DEPTH_LAYERS = (DEPTH_CHANNELS + 2 * SLAB_CHANNELS + 3) / 4;
const int DEPTH_ARRAY = DEPTH_LAYERS > 0 ? 4 * DEPTH_LAYERS : 4;
layout(constant_id = SPEC_VIEW_CHANNELS) const int VIEW_CHANNELS = 0;
layout(constant_id = SPEC_FLAT_SLABS) const uint FLAT_SLABS = 0u;
layout(constant_id = SPEC_SLAB_LAYER_ROWS) const int SLAB_LAYER_ROWS = 0;
layout(constant_id = SPEC_VIEW_SLAB_CHANNEL) const int VIEW_SLAB_CHANNEL = -1;
// The response pass seen through transparent objects: τ per band inside the response sums. (A
// macro: glslang 11 emits a composite boolean specialization constant used in a branch before its
// definition, which spirv-val and lavapipe refuse.)
layout(constant_id = SPEC_RESPONSE_CHANNELS) const int RESPONSE_CHANNELS = 4 * MAX_OUTPUTS;
layout(constant_id = SPEC_RESPONSE_FIRST_LAYER) const int RESPONSE_FIRST_LAYER = 0;
layout(constant_id = SPEC_RESPONSE_END_LAYER) const int RESPONSE_END_LAYER = 1;
layout(constant_id = SPEC_CROSSING_HEADER) const int CROSSING_HEADER = -1;
layout(constant_id = SPEC_CROSSING_NODES) const int CROSSING_NODES = 0;
// The response pass through sheets, media and a slab: only in the FILTERED_RESPONSES builds
// (through_filters.glsl; render/spectral_pipelines.cpp picks them for those programs).
#ifdef FILTERED_RESPONSES
#define THROUGH_FILTERS (RESPONSES && (VIEW_CHANNELS > 0 || VIEW_SLAB_CHANNEL >= 0))
#define THROUGH_WITH_FILTERED_SHADOWS (RESPONSES && FILTERED_SHADOWS && (VIEW_CHANNELS > 0 || VIEW_SLAB_CHANNEL >= 0))
#else
#define THROUGH_FILTERS false
#endif
layout(constant_id = SPEC_EMITTER_TRIANGLES) const int EMITTER_TRIANGLES = 0;
layout(constant_id = SPEC_EMITTERS) const int EMITTERS = 0;
layout(constant_id = SPEC_HAS_EMITTERS) const bool HAS_EMITTERS = true;
// The ground truth's band passes (render/ground_truth.h): the illumination (ρd := 1, no specular,
// fluorescence or emission) or the reflectance, instead of the radiance.
layout(constant_id = SPEC_QUANTITY) const int QUANTITY = QUANTITY_RADIANCE;
const bool RADIANCE = QUANTITY == QUANTITY_RADIANCE;
const bool ILLUMINATION = QUANTITY == QUANTITY_ILLUMINATION;

layout(set = 0, binding = BINDING_LIGHTS, std140) uniform Lights { GpuLightBlock L; };
layout(set = 0, binding = BINDING_LIGHT_SPECTRA, std140) uniform LightSpectra { GpuLightSpectraBlock E; };
layout(set = 0, binding = BINDING_MATERIAL, std140) uniform Material { GpuMaterialBlock M; };
layout(set = 0, binding = BINDING_FLUORESCENCE, std140) uniform Fluorescence { GpuFluorescenceBlock F; };
layout(set = 0, binding = BINDING_RESPONSES, std140) uniform Responses { GpuResponseBlock R; };
layout(set = 0, binding = BINDING_SHADOW_MATRICES, std140) uniform Shadows { GpuShadowBlock S; };
layout(set = 0, binding = BINDING_SHADOW_MAP) uniform sampler2DArrayShadow shadowMap;
layout(set = 0, binding = BINDING_LOBE_WEIGHTS) uniform sampler2D lobeWeights;
layout(set = 0, binding = BINDING_LOBE_TABLES) uniform usamplerBuffer lobeData;
layout(set = 0, binding = BINDING_SHADOW_TRANSMITTANCE) uniform sampler2DArray shadowTransmittance;
layout(set = 0, binding = BINDING_SHADOW_EXCITATION) uniform samplerBuffer shadowExcitation;
layout(set = 0, binding = BINDING_DEPTH_SPECTRA) uniform samplerBuffer depthSpectra;
layout(set = 0, binding = BINDING_VIEW_CHANNELS) uniform sampler2DArray viewChannels;
layout(set = 0, binding = BINDING_OPAQUE_DISTANCE) uniform sampler2D opaqueDistance;
layout(set = 0, binding = BINDING_SLAB_DISTANCE) uniform sampler2D slabDistance;
#include "view_channels.glsl"
#include "slab_fresnel.glsl"

layout(set = 1, binding = TEXTURE_BINDING_DIFFUSE) uniform sampler2DArray diffuseTexture;
layout(set = 1, binding = TEXTURE_BINDING_SPECULAR) uniform sampler2DArray specularTexture;
layout(set = 1, binding = TEXTURE_BINDING_NORMAL) uniform sampler2DArray normalTexture;

layout(push_constant) uniform Push { SpectralPushConstants pc; };

layout(location = 0) in vec3 worldPosition;
layout(location = 1) in vec3 worldNormal;
layout(location = 2) in vec2 uv;
layout(location = 3) in vec4 worldTangent;

#ifdef INDIRECT
// Interreflection: this pass's bands of the indirect light here, interpolated from the element
// vertices, and each emitter's share of its direct light (interface.h, VERTEX_INDIRECT).
layout(location = VARYING_INDIRECT) in vec4 indirect[INDIRECT_RECORD_VEC4];

// The form factor from the point x (unit normal n) to triangle (a, b, c) seen from its front, in
// closed form (Lambert): the part of it above x's horizon, Σ over its edges of the angle each
// subtends times the cosine of its plane with n, over 2π (radiosity/form_factor.cpp, in double).
// One edge's term of Lambert's contour integral: the angle r0 and r1 subtend times the cosine of
// their plane with n.
float edgeTerm(vec3 r0, vec3 r1, vec3 n) {
    vec3 g = cross(r0, r1);
    float s = length(g);
    return s > 0.0 ? atan(s, dot(r0, r1)) * dot(n, g) / s : 0.0;
}

float pointToTriangle(vec3 x, vec3 n, vec3 a, vec3 b, vec3 c) {
    vec3 front = cross(b - a, c - a);
    if (!(dot(front, x - a) > 0.0)) return 0.0;
    vec3 ra = a - x, rb = b - x, rc = c - x;
    float ha = dot(n, ra), hb = dot(n, rb), hc = dot(n, rc);
    float sum = 0.0;
    if (ha >= 0.0 && hb >= 0.0 && hc >= 0.0) {
        // Wholly above x's horizon (most pixels): three edges, no clipping, no arrays (which
        // lavapipe keeps in memory when indexed by a variable).
        sum = edgeTerm(ra, rb, n) + edgeTerm(rb, rc, n) + edgeTerm(rc, ra, n);
    } else {
        vec3 t[3] = vec3[3](ra, rb, rc);
        float h[3] = float[3](ha, hb, hc);
        vec3 v[4];
        int count = 0;
        for (int k = 0; k < 3; ++k) {  // clipped to x's hemisphere: at most 4 corners
            int k1 = (k + 1) % 3;
            if (h[k] >= 0.0) v[count++] = t[k];
            if ((h[k] >= 0.0) != (h[k1] >= 0.0)) v[count++] = t[k] + (t[k1] - t[k]) * (h[k] / (h[k] - h[k1]));
        }
        if (count < 3) return 0.0;
        for (int k = 0; k < count; ++k) sum += edgeTerm(v[k], v[(k + 1) % count], n);
    }
    return clamp(-sum * 0.15915494309189535, 0.0, 1.0);  // −Σ/2π
}
#endif

layout(location = 0) out vec4 out0;
#ifdef RESPONSES_WITHOUT_BANDS
layout(location = OUTPUT_COUNT) out float bandPassDepth;  // this fragment's depth where it needs bands, else 0
#endif
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

// Where visibility() looked light l up (surface_shading.glsl): the shadow-map layer, −1 when it
// did not, and the position in the transmittance maps there (texel centres at integers).
int shadowLayer;
vec2 shadowTexel;

vec4 acc[OUTPUT_COUNT];  // this pass's bands, 4 per attachment
float fluorescence;      // rank-one form: Σ_l g_l·coupling_l, scales ê(λ)/λ

float coupling(int l) { return M.coupling[l / 4][l % 4]; }

// Coloured shadows (FILTERED_SHADOWS): the current light's transmittance to this fragment for
// this pass's bands, from its transmittance map at the texel the shadow lookup used
// (visibility() leaves it in shadowTexel, shadowLayer); `filtered` false where the light arrives
// unfiltered (outside the map, or not a shadowing light).
vec4 lightFilter[OUTPUT_COUNT];
bool filtered;
bool filterDirectional;  // the filtered light is directional (a flat slab's T is then one spectrum)
// The maps hold optical-depth channels (interface.h), interpolated bilinearly between texel
// centres (by hand, in float, as the textures are): a texel holds the channels along the ray
// through its centre. log2 τ is linear in the sheets' and media's channels, so interpolating them
// is interpolating log2 τ band by band — exact along a slab-shaped medium's side, where the path
// grows linearly across the map and τ does not.
float depthChannel[DEPTH_ARRAY];
void fetchDepthChannels() {
    const vec2 p0 = floor(shadowTexel), f = shadowTexel - p0;
    const ivec2 i0 = ivec2(p0), last = ivec2(TRANSMITTANCE_MAP_SIZE - 1);
    const ivec2 t00 = clamp(i0, ivec2(0), last), t11 = clamp(i0 + ivec2(1), ivec2(0), last);
    const float w00 = (1.0 - f.x) * (1.0 - f.y), w10 = f.x * (1.0 - f.y), w01 = (1.0 - f.x) * f.y, w11 = f.x * f.y;
    [[unroll]] for (int j = 0; j < DEPTH_LAYERS; ++j) {
        const int layer = shadowLayer * DEPTH_LAYERS + j;
        const vec4 c = w00 * texelFetch(shadowTransmittance, ivec3(t00, layer), 0) +
                       w10 * texelFetch(shadowTransmittance, ivec3(t11.x, t00.y, layer), 0) +
                       w01 * texelFetch(shadowTransmittance, ivec3(t00.x, t11.y, layer), 0) +
                       w11 * texelFetch(shadowTransmittance, ivec3(t11, layer), 0);
        [[unroll]] for (int i = 0; i < 4; ++i) depthChannel[4 * j + i] = c[i];
    }
}
// A slab's T at cos θ for 4 bands of index n and attenuation a·d·log2(10) (slab_fresnel.glsl, as
// transmit.frag draws it), and its log2.
vec4 slabTransmittance(float cosI, vec4 n, vec4 attenuation) {
    vec4 T, reflectance;
    slabFresnel(cosI, n, attenuation, T, reflectance);
    return T;
}
vec4 slabLog2Transmittance(float cosI, vec4 n, vec4 attenuation) {
    return max(log2(slabTransmittance(cosI, n, attenuation)), vec4(-149.0));
}
// log2 τ of band layer `layer` of the grid (4 bands) from the fetched channels: Σ channel × its row;
// `directional`: of a directional light (a flat slab's row then holds its log2 T).
vec4 log2TransmittanceAt(int layer, bool directional) {
    vec4 depth = vec4(0.0);
    [[unroll]] for (int c = 0; c < DEPTH_CHANNELS; ++c)
        depth += depthChannel[c] * texelFetch(depthSpectra, c * BAND_LAYERS + layer);
    [[unroll]] for (int i = 0; i < SLAB_CHANNELS; ++i) {
        const int c = DEPTH_CHANNELS + 2 * i;
        const float crossings = depthChannel[c];
        // A flat slab under a directional light: one angle, its log2 T computed once per scene.
        if (directional && i < 32 && ((FLAT_SLABS >> uint(i)) & 1u) != 0u)
            depth += crossings * texelFetch(depthSpectra, SLAB_LAYER_ROWS + (shadowLayer * SLAB_CHANNELS + i) * BAND_LAYERS + layer);
        else if (crossings > 0.0)
            depth += crossings * slabLog2Transmittance(min(depthChannel[c + 1] / crossings, 1.0),
                                                       texelFetch(depthSpectra, c * BAND_LAYERS + layer),
                                                       texelFetch(depthSpectra, (c + 1) * BAND_LAYERS + layer));
    }
    return depth;
}
vec4 transmittanceAt(int layer) { return exp2(log2TransmittanceAt(layer, filterDirectional)); }
#ifdef FILTERED_RESPONSES
#include "through_filters.glsl"
#endif
void filterLight(bool directional) {
    filterDirectional = directional;
    filtered = FILTERED_SHADOWS && shadowLayer >= 0;
#ifdef FILTERED_RESPONSES
    if (THROUGH_FILTERS) {
        classifyFilteredLight();
        return;
    }
#endif
    if (!filtered) return;
    fetchDepthChannels();
    const int first = int(M.params.y);
    [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) lightFilter[k] = transmittanceAt(first + k);
}
// The rank-one coupling of light l under its filter: Σ over every band (all passes) of the
// excitation integrand × τ, in place of the unfiltered M.coupling.
float filteredCoupling(int l) {
    const int record = int(M.params.z) + l * BAND_LAYERS;
    float sum = 0.0;
    for (int j = 0; j < BAND_LAYERS; ++j) sum += dot(texelFetch(shadowExcitation, record + j), transmittanceAt(j));
    return sum;
}

// Textured reflectance at this fragment (HAS_TEXTURES only): the material's spectra times the
// textures' bands.
vec4 texturedDiffuse[OUTPUT_COUNT];
vec4 texturedSpecular[OUTPUT_COUNT];
vec4 diffuseAt(int k) { return HAS_TEXTURES ? texturedDiffuse[k] : M.diffuse[k]; }
vec4 specularAt(int k) { return HAS_TEXTURES ? texturedSpecular[k] : M.specular[k]; }

#include "surface_shading.glsl"

// Response pass: where this fragment reads the material's response textures, if it has them.
bool diffuseResponseTexture, specularResponseTexture;
Bilinear diffuseTexel, specularTexel;

void sampleTextures() {
    if (RESPONSES) {
        diffuseResponseTexture = (runtimeValue(M.switches.x) & MATERIAL_DIFFUSE_TEXTURE) != 0u;
        specularResponseTexture = HAS_SPECULAR && (runtimeValue(M.switches.x) & MATERIAL_SPECULAR_TEXTURE) != 0u;
        if (diffuseResponseTexture) diffuseTexel = bilinearAt(vec2(textureSize(diffuseTexture, 0).xy));
        if (specularResponseTexture) specularTexel = bilinearAt(vec2(textureSize(specularTexture, 0).xy));
        return;
    }
    int layer0 = int(M.params.y);
    if ((runtimeValue(M.switches.x) & MATERIAL_DIFFUSE_TEXTURE) != 0u) {
        Bilinear b = bilinearAt(vec2(textureSize(diffuseTexture, 0).xy));
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k)
            texturedDiffuse[k] = M.diffuse[k] * fetchBilinear(diffuseTexture, b, layer0 + k);
    } else {
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) texturedDiffuse[k] = M.diffuse[k];
    }
    if (HAS_SPECULAR && (runtimeValue(M.switches.x) & MATERIAL_SPECULAR_TEXTURE) != 0u) {
        Bilinear b = bilinearAt(vec2(textureSize(specularTexture, 0).xy));
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k)
            texturedSpecular[k] = M.specular[k] * fetchBilinear(specularTexture, b, layer0 + k);
    } else {
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) texturedSpecular[k] = M.specular[k];
    }
}

// Adds light l's reflected radiance with geometric weights: diffuse g/π, specular lobe weight
// (in the response pass, the detector's response to it).
void addLight(int l, float diffuseWeight, float specularWeight) {
#ifdef FILTERED_RESPONSES
    if (THROUGH_FILTERS) {
        respondThroughView(l, diffuseWeight, specularWeight);
        return;
    }
#endif
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
        vec4 reflectance = ILLUMINATION ? vec4(diffuseWeight) : diffuseAt(k) * diffuseWeight;
        if (HAS_SPECULAR && RADIANCE) reflectance += specularAt(k) * specularWeight;
        vec4 e = E.lightBands[l * MAX_OUTPUTS + k];
        if (FILTERED_SHADOWS && filtered) e *= lightFilter[k];
        acc[k] += e * reflectance;
    }
}

// With a Donaldson matrix in the scene, light l's emission under its filter: Σ over every input
// band of τ × that band's row of (1/π)·D·E·Δλ, this pass's output bands (a matrix–vector
// product per fragment: 4·BAND_LAYERS rows of OUTPUT_COUNT fetches).
void addFilteredEmission(int l, float g) {
    const int base = int(M.params.z) + l * 4 * BAND_LAYERS * BAND_LAYERS;
    const int outFirst = int(M.params.y);
    for (int j = 0; j < BAND_LAYERS; ++j) {
        const vec4 tau = transmittanceAt(j);
        for (int c = 0; c < 4; ++c) {
            const float w = g * tau[c];
            const int row = base + (4 * j + c) * BAND_LAYERS + outFirst;
            [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] += w * texelFetch(shadowExcitation, row + k);
        }
    }
}

// Light l's fluorescence with geometric factor g: the rank-one form sums g·coupling_l (times ê/λ
// at the end); with a Donaldson matrix in the scene, every fluorescent material adds g·F_l(λ).
void addFluorescence(int l, float g) {
    if (!HAS_FLUORESCENCE || !RADIANCE) return;
    // (Through filters, the response pass sums the rank-one coupling as the band passes do, and
    // takes ê/λ's response band by band at the end. Nested ifs, not `RESPONSES && !THROUGH_FILTERS`:
    // glslang 11 emits that composite specialization constant's negation before its definition.)
    if (RESPONSES) {
        if (THROUGH_FILTERS)
            fluorescence += g * (FILTERED_SHADOWS && filtered && g > 0.0 && runtimeValue(M.params.z) >= 0.0 ? filteredCoupling(l)
                                                                                                           : coupling(l));
        else
            [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] += g * R.fluorescence[l * RESPONSE_VEC4 + k];
        return;
    }
    if (FLUORESCENCE_SPECTRA && FILTERED_SHADOWS && filtered && g > 0.0 && runtimeValue(M.params.z) >= 0.0)
        addFilteredEmission(l, g);
    else if (FLUORESCENCE_SPECTRA)
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] += g * F.emitted[l * MAX_OUTPUTS + k];
    else if (FILTERED_SHADOWS && filtered && g > 0.0 && runtimeValue(M.params.z) >= 0.0)
        fluorescence += g * filteredCoupling(l);
    else
        fluorescence += g * coupling(l);
}

// Each kind of light's loop is unrolled for its first UNROLLED_LIGHTS lights and a plain loop after
// that: a scene of a few lights keeps the unrolled shader (the tail loop has no iterations and is
// compiled away), and one of 128 lights compiles one loop body instead of 128 copies — its cold
// compile went from minutes to seconds (docs/performance.md, "Many lights"). The light counts stay
// specialization constants: a loop bound read from a uniform made lavapipe recompile per frame.
const int UNROLLED_LIGHTS = 4;

// Ambient: irradiance on every surface, no cosine, no specular.
void ambientLight(int i) {
    int l = i;
    addLight(l, INV_PI, 0.0);
    addFluorescence(l, 1.0);
}

void directionalLight(int i, vec3 n, vec3 v, vec3 ng) {
    int l = AMBIENT_COUNT + i;
    vec3 w = L.lights[l].vector.xyz;
    float g = max(dot(n, w), 0.0);
    shadowLayer = -1;
    if (i < SHADOWED_DIRECTIONAL && g > 0.0) g *= visibility(l, worldPosition, ng, w, false);
    if (FILTERED_SHADOWS) filterLight(true);
#ifdef FILTERED_RESPONSES
    if (THROUGH_WITH_FILTERED_SHADOWS)
        respondThroughViewAndLight(l, g * INV_PI, specularWeight(n, w, v, g), true);
    else
#endif
        addLight(l, g * INV_PI, specularWeight(n, w, v, g));
    addFluorescence(l, g);
}

// Point: E = I·cosθ/d², d in the frame's units (vector.w turns 1/d² into m⁻²). A light on the
// surface (d = 0, or d² below float32's normal range) has no direction and contributes nothing,
// as in the reference (docs/physics.md); the clamp keeps g finite beside it, so that a lobe of
// 0 never meets an infinite g (Inf × 0 = NaN).
void pointLight(int i, vec3 n, vec3 v, vec3 ng) {
    int l = AMBIENT_COUNT + DIRECTIONAL_COUNT + i;
    vec3 d = L.lights[l].vector.xyz - worldPosition;
    float d2 = dot(d, d);
    bool apart = d2 >= FLT_MIN_NORMAL;
    vec3 w = apart ? d * inversesqrt(d2) : n;
    float g = apart ? min(max(dot(n, w), 0.0) / d2 * L.lights[l].vector.w, FLT_MAX_FINITE) : 0.0;
    shadowLayer = -1;
    if (i < SHADOWED_POINT && g > 0.0) g *= visibility(l, worldPosition, ng, w, true);
    if (FILTERED_SHADOWS) filterLight(false);
#ifdef FILTERED_RESPONSES
    if (THROUGH_WITH_FILTERED_SHADOWS)
        respondThroughViewAndLight(l, g * INV_PI, specularWeight(n, w, v, g), false);
    else
#endif
        addLight(l, g * INV_PI, specularWeight(n, w, v, g));
    addFluorescence(l, g);
}

void writeOutputs();  // acc to the attachments (after main)

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
        if (HAS_NORMAL_MAPS && (runtimeValue(M.switches.x) & MATERIAL_NORMAL_TEXTURE) != 0u) n = normalMapped(n);
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
    if (QUANTITY == QUANTITY_REFLECTANCE) {  // ρd of the surface seen, textures included
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] = diffuseAt(k);
        writeOutputs();
        return;
    }

    filtered = false;
#ifdef FILTERED_RESPONSES
    if (THROUGH_FILTERS) classifyView(v);  // τ inside the response sums
#endif
    [[unroll]] for (int i = 0; i < min(AMBIENT_COUNT, UNROLLED_LIGHTS); ++i) ambientLight(i);
    [[dont_unroll]] for (int i = UNROLLED_LIGHTS; i < AMBIENT_COUNT; ++i) ambientLight(i);
    vec3 ng = dot(faceNormal, faceNormal) > 0.0 ? normalize(faceNormal) : n;
    filtered = false;
    [[unroll]] for (int i = 0; i < min(DIRECTIONAL_COUNT, UNROLLED_LIGHTS); ++i) directionalLight(i, n, v, ng);
    [[dont_unroll]] for (int i = UNROLLED_LIGHTS; i < DIRECTIONAL_COUNT; ++i) directionalLight(i, n, v, ng);
    [[unroll]] for (int i = 0; i < min(POINT_COUNT, UNROLLED_LIGHTS); ++i) pointLight(i, n, v, ng);
    [[dont_unroll]] for (int i = UNROLLED_LIGHTS; i < POINT_COUNT; ++i) pointLight(i, n, v, ng);
    filtered = false;  // the hemisphere lights are not shadowed, nor filtered
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
    if (HAS_FLUORESCENCE && !FLUORESCENCE_SPECTRA && !RESPONSES && RADIANCE)
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] += fluorescence * M.emissionOverLambda[k];
#ifdef FILTERED_RESPONSES
    if (THROUGH_FILTERS) respondEmissionThroughView();
#endif
    // A self-luminous surface's own radiance, on its front (the side its winding faces).
    if (HAS_EMITTERS && !RESPONSES && RADIANCE && gl_FrontFacing && (runtimeValue(M.switches.x) & MATERIAL_EMITTER) != 0u)
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] += M.emitted[k];
#ifdef INDIRECT
    // The indirect light, on the side the elements were solved for (an open surface's other side is
    // drawn as its own copy; a closed mesh's inside receives none). H/π is reflected by the
    // surface's own ρd here, textures included; a fluorescent surface's comes whole.
    if (gl_FrontFacing) {
        const bool whole = (runtimeValue(M.switches.x) & MATERIAL_FLUORESCENT) != 0u;
        // The illumination map takes H/π itself (a fluorescent surface's vertices carry its
        // radiance whole, so there the map holds that: the mask flags it).
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] += (whole || ILLUMINATION ? vec4(1.0) : diffuseAt(k)) * indirect[k];
        // The emitters' direct light, per pixel: L_e × the unoccluded form factor here (closed
        // form) × the share that reaches past the occluders, interpolated from the vertices (0 on
        // a fluorescent surface, whose vertices carry it whole).
        vec4 factor = vec4(0.0);
        for (int t = 0; t < EMITTER_TRIANGLES; ++t) {
            vec4 a = L.emitterCorners[3 * t];
            factor[int(a.w)] += pointToTriangle(worldPosition, n, a.xyz, L.emitterCorners[3 * t + 1].xyz,
                                                L.emitterCorners[3 * t + 2].xyz);
        }
        factor *= indirect[INDIRECT_SHARE];
        for (int e = 0; e < EMITTERS; ++e) {
            const int first = (AMBIENT_COUNT + DIRECTIONAL_COUNT + POINT_COUNT + HEMISPHERE_COUNT + e) * MAX_OUTPUTS;
            [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k)
                acc[k] += (ILLUMINATION ? vec4(1.0) : diffuseAt(k)) * factor[e] * E.lightBands[first + k];
        }
    }
#endif
    // What the camera sees through: the sheets and media in front of this surface, as their
    // optical-depth channels at this pixel (the channel pass), τ = 2^(Σ c·k) band by band.
    if (VIEW_CHANNELS > 0 && RADIANCE && !RESPONSES) {
        fetchViewChannels(0);
        const int first = int(M.params.y);
        [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] *= viewTransmittance(first + k);
    }
    writeOutputs();
}

void writeOutputs() {
    out0 = acc[0];
#ifdef RESPONSES_WITHOUT_BANDS
    bandPassDepth = needsBands ? gl_FragCoord.z : 0.0;
#endif
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
