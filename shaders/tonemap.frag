#version 450
// The tonemap pass: the display path of color/tonemap.h for one output pixel. Reads the spectral
// target (4 bands per layer), box-filters its SSAA×SSAA samples, integrates the detector
// responses, and turns them into relative XYZ, adapted XYZ and display counts. After the response
// pass (INPUT == TONEMAP_INPUT_RESPONSES) the target already holds the responses, 4 per layer. The CPU reference
// is color/tonemap_reference.cpp; docs/color.md has the formulas.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "interface.h"

layout(constant_id = TONEMAP_SPEC_CHANNELS) const int CHANNELS = 3;
layout(constant_id = TONEMAP_SPEC_LAYERS) const int LAYERS = 23;  // of the grid's bands: weights and film tables
layout(constant_id = TONEMAP_SPEC_SSAA) const int SSAA = 1;
layout(constant_id = TONEMAP_SPEC_MODE) const int MODE = TONEMAP_MODE_LINEAR;
layout(constant_id = TONEMAP_SPEC_DISPLAY) const int DISPLAY = TONEMAP_DISPLAY_SRGB;
layout(constant_id = TONEMAP_SPEC_INPUT) const int INPUT = TONEMAP_INPUT_BANDS;

layout(set = 0, binding = TONEMAP_BINDING_SPECTRAL) uniform sampler2DArray spectral;
layout(set = 0, binding = TONEMAP_BINDING_PARAMS, std140) uniform Params { TonemapParams P; };
layout(set = 0, binding = TONEMAP_BINDING_TABLES, std430) readonly buffer Tables { vec4 tables[]; };

layout(location = TONEMAP_OUT_COUNTS) out vec4 outCounts;
layout(location = TONEMAP_OUT_XYZ) out vec4 outXyz;
layout(location = TONEMAP_OUT_RESPONSES) out vec4 outResponses0;
layout(location = TONEMAP_OUT_RESPONSES + 1) out vec4 outResponses1;

const float LOG2_10 = 3.321928094887362;

vec3 rowsTimes(vec4 rows[3], vec3 v) { return vec3(dot(rows[0].xyz, v), dot(rows[1].xyz, v), dot(rows[2].xyz, v)); }

float softplus(float z) { return max(z, 0.0) + log(1.0 + exp(-abs(z))); }

// Film layer density at log10 relative exposure x (color/film.h, FilmCurve): a line of slope
// −gamma through (logH0, mid density) joined smoothly to dMin and dMax. Reversal: density falls
// with exposure.
float filmDensity(float x, vec4 curve, float toe) {
    float dMin = curve.x, dMax = curve.y, logH0 = curve.z, gamma = curve.w;
    float R = dMax - dMin;
    float slope = gamma / tanh(R / (4.0 * toe));
    float u = slope * (logH0 - x) + 0.5 * R;
    return dMin + toe * (softplus(u / toe) - softplus((u - R) / toe));
}

vec3 filmXyz(vec3 exposure) {
    vec3 x = log(max(exposure / P.filmWhite.xyz, vec3(1e-30))) / log(10.0);
    vec3 D = vec3(filmDensity(x.x, P.filmCurve[0], P.filmToe.x), filmDensity(x.y, P.filmCurve[1], P.filmToe.y),
                  filmDensity(x.z, P.filmCurve[2], P.filmToe.z));
    vec3 xyz = vec3(0.0);
    for (int l = 0; l < LAYERS; ++l) {
        vec4 density = D.x * tables[P.dyeOffset + l] + D.y * tables[P.dyeOffset + LAYERS + l] +
                       D.z * tables[P.dyeOffset + 2 * LAYERS + l] + tables[P.baseOffset + l];
        vec4 T = exp2(-LOG2_10 * density);
        xyz += vec3(dot(tables[P.projectionOffset + l], T), dot(tables[P.projectionOffset + LAYERS + l], T),
                    dot(tables[P.projectionOffset + 2 * LAYERS + l], T));
    }
    return xyz * P.filmWhite.w;
}

// IEC 61966-2-1 encoding.
vec3 srgbEncode(vec3 c) {
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    float r[TONEMAP_MAX_CHANNELS];
    [[unroll]] for (int c = 0; c < TONEMAP_MAX_CHANNELS; ++c) r[c] = 0.0;
    if (INPUT == TONEMAP_INPUT_RESPONSES) {
        // The response pass's channels: only the box filter is left to do.
        [[unroll]] for (int l = 0; l < RESPONSE_VEC4; ++l) {
            if (4 * l >= CHANNELS) break;
            vec4 R = vec4(0.0);
            [[unroll]] for (int sy = 0; sy < SSAA; ++sy)
                [[unroll]] for (int sx = 0; sx < SSAA; ++sx)
                    R += texelFetch(spectral, ivec3(px * SSAA + ivec2(sx, sy), l), 0);
            R *= P.scales.y;
            [[unroll]] for (int c = 0; c < 4; ++c) r[4 * l + c] = R[c];
        }
    } else {
        for (int l = 0; l < LAYERS; ++l) {
            vec4 L = vec4(0.0);
            [[unroll]] for (int sy = 0; sy < SSAA; ++sy)
                [[unroll]] for (int sx = 0; sx < SSAA; ++sx)
                    L += texelFetch(spectral, ivec3(px * SSAA + ivec2(sx, sy), l), 0);
            L *= P.scales.y;
            [[unroll]] for (int c = 0; c < CHANNELS; ++c) r[c] += dot(L, tables[P.weightsOffset + c * LAYERS + l]);
        }
    }
    outResponses0 = vec4(r[0], r[1], r[2], r[3]);
    outResponses1 = vec4(r[4], r[5], r[6], r[7]);
    if (MODE == TONEMAP_MODE_RESPONSES) {
        outCounts = vec4(0.0);
        outXyz = vec4(0.0);
        return;
    }
    vec3 response = vec3(r[0], r[1], r[2]);
    vec3 xyz = MODE == TONEMAP_MODE_FILM ? filmXyz(response) : rowsTimes(P.responseToXyz, response);
    outXyz = vec4(xyz * P.scales.x, 1.0);

    // Display: adapt, subtract the black, to linear RGB, clip (and flag), invert the transfer.
    vec3 rgb = rowsTimes(P.xyzToRgb, rowsTimes(P.adaptation, xyz) - P.blackXyz.xyz);
    bool clipped = any(lessThan(rgb, vec3(-1e-6))) || any(greaterThan(rgb, vec3(1.0 + 1e-6)));
    rgb = clamp(rgb, 0.0, 1.0);
    vec3 v = DISPLAY == TONEMAP_DISPLAY_SRGB ? srgbEncode(rgb)
                                             : (pow(rgb, 1.0 / P.gamma.xyz) - P.offset.xyz) / P.gain.xyz;
    vec3 counts = clamp(floor(v * P.blackXyz.w + 0.5), 0.0, P.blackXyz.w);
    // Every count below the GOG cutoff shows the same black; write it as 0 (color/display_model.h).
    counts = mix(counts, vec3(0.0), lessThanEqual(counts, P.cutoffCounts.xyz));
    outCounts = vec4(counts, clipped ? 1.0 : 0.0);
}
