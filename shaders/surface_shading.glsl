// The shading a surface program shares — bilinear texture lookups, the normal map, the Blinn–Phong
// lobe, the hemisphere lights' lobe tables, shadow-map visibility — for the band, response and lobe
// programs (spectral.frag) and any later program that shades a surface point (a transmittance
// pass). Included after the including shader has declared what these read: the specialization
// constants (HAS_SPECULAR, SHADOWS, LOBE_MODE, the light counts, HEMISPHERE_PAIRED), the uniform
// blocks M, L and S, the samplers shadowMap, lobeWeights, lobeData and normalTexture, the inputs
// uv and worldTangent, and the globals shadowLayer and shadowTexel that visibility() sets
// (spectral.frag shows the declarations). Physics: docs/physics.md.

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
    // Where a coloured shadow's transmittance is looked up (the including shader declares these).
    shadowLayer = layer;
    shadowTexel = st * float(TRANSMITTANCE_MAP_SIZE) - 0.5;  // texel centres at integers
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
    float gloss = runtimeValue(M.params.x);
    vec3 up = L.lights[l].vector.xyz;
    vec2 integrals = vec2(0.0);
    if (HAS_SPECULAR && (runtimeValue(M.switches.x) & MATERIAL_SPECULAR) != 0u) {
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
    return (runtimeValue(M.switches.x) & MATERIAL_SPECULAR) != 0u ? lobe : 0.0;
}
