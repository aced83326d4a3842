// The specular reflection of a uniform hemisphere of radiance, in float: the same rule as the CPU
// reference's engine/reference/hemisphere_lobe.cpp (whose header derives it), with the nodes of
// hemisphere_quadrature.h. Included by spectral.frag.
//
// hemisphereLobe(n, v, u, N) = ∫ (n·h)^N·(n·ω) dω over n·ω > 0, u·ω > 0; h = normalize(ω + v).
#include "hemisphere_quadrature.h"

const float HL_PI = 3.14159265358979;
const float HL_GAUSS_X[HEMISPHERE_GAUSS_HALF] = float[HEMISPHERE_GAUSS_HALF](HEMISPHERE_GAUSS_X);
const float HL_GAUSS_W[HEMISPHERE_GAUSS_HALF] = float[HEMISPHERE_GAUSS_HALF](HEMISPHERE_GAUSS_W);

// 1 − eˣ for x ≤ 0, keeping its relative precision as x → 0 (GLSL has no expm1).
float hlOneMinusExp(float x) {
    return x > -0.05 ? -x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x * (1.0 / 24.0 + x * (1.0 / 120.0))))) : 1.0 - exp(x);
}

// c^(N+1) for c ≤ 1: where a ring of half vectors at n·h = c lies in s.
float hlSAt(float c, float e) { return c <= 0.0 ? 0.0 : exp(e * log(min(c, 1.0))); }

// n·h along the hemisphere's horizon ω(ψ) = cos ψ·p + sin ψ·q.
float hlHorizonNh(vec3 n, vec3 v, vec3 p, vec3 q, float nv, float psi) {
    vec3 w = cos(psi) * p + sin(psi) * q;
    float len2 = 2.0 + 2.0 * dot(v, w);
    return len2 > 0.0 ? (dot(n, w) + nv) * inversesqrt(len2) : 0.0;
}

// cut false: no hemisphere cut (u unused): the lobe over the whole hemisphere above the surface.
float hlLobeIntegral(vec3 n, vec3 v, vec3 u, bool cut, float gloss) {
    if (gloss == 0.0) return cut ? HL_PI * (1.0 + dot(n, u)) / 2.0 : HL_PI;
    float nv = clamp(dot(n, v), -1.0, 1.0);
    vec3 t = v - nv * n;
    float sv = length(t);
    if (sv > 1e-6) {
        t /= sv;
    } else {
        t = normalize(cross(abs(n.x) < 0.9 ? vec3(1, 0, 0) : vec3(0, 1, 0), n));
        sv = 0.0;
    }
    vec3 b = cross(n, t);
    float un = dot(u, n), ut = dot(u, t), ub = dot(u, b), uv = dot(u, v);
    float e = gloss + 1.0;

    // Cuts of the radial integral (see the C++ rule): its ends, the rings touching the surface's
    // horizon, the extrema of n·h along the hemisphere's horizon.
    float thetaV = acos(clamp(nv, 0.0, 1.0));
    float cuts[HEMISPHERE_MAX_CUTS];
    int cutCount = 4;
    cuts[0] = 0.0;
    cuts[1] = 1.0;
    cuts[2] = hlSAt(cos(0.5 * (0.5 * HL_PI + thetaV)), e);
    cuts[3] = hlSAt(cos(0.5 * (0.5 * HL_PI - thetaV)), e);
    if (cut) {
        vec3 p = normalize(cross(abs(u.x) < 0.9 ? vec3(1, 0, 0) : vec3(0, 1, 0), u)), q = cross(u, p);
        const float step = 2.0 * HL_PI / float(HEMISPHERE_HORIZON_SAMPLES);
        float f[HEMISPHERE_HORIZON_SAMPLES];
        for (int i = 0; i < HEMISPHERE_HORIZON_SAMPLES; ++i) f[i] = hlHorizonNh(n, v, p, q, nv, float(i) * step);
        for (int i = 0; i < HEMISPHERE_HORIZON_SAMPLES && cutCount < HEMISPHERE_MAX_CUTS; ++i) {
            float prev = f[(i + HEMISPHERE_HORIZON_SAMPLES - 1) % HEMISPHERE_HORIZON_SAMPLES];
            float next = f[(i + 1) % HEMISPHERE_HORIZON_SAMPLES];
            bool isMax = f[i] >= prev && f[i] > next, isMin = f[i] <= prev && f[i] < next;
            if (!isMax && !isMin) continue;
            float sgn = isMax ? 1.0 : -1.0, g = 0.5 * (sqrt(5.0) - 1.0);
            float lo = float(i - 1) * step, hi = float(i + 1) * step;
            float x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
            float f1 = sgn * hlHorizonNh(n, v, p, q, nv, x1), f2 = sgn * hlHorizonNh(n, v, p, q, nv, x2);
            for (int it = 0; it < HEMISPHERE_GOLDEN_STEPS; ++it) {
                if (f1 > f2) {
                    hi = x2; x2 = x1; f2 = f1; x1 = hi - g * (hi - lo); f1 = sgn * hlHorizonNh(n, v, p, q, nv, x1);
                } else {
                    lo = x1; x1 = x2; f1 = f2; x2 = lo + g * (hi - lo); f2 = sgn * hlHorizonNh(n, v, p, q, nv, x2);
                }
            }
            cuts[cutCount++] = hlSAt(hlHorizonNh(n, v, p, q, nv, 0.5 * (lo + hi)), e);
        }
    }
    for (int i = 1; i < cutCount; ++i) {  // insertion sort
        float x = cuts[i];
        int j = i - 1;
        while (j >= 0 && cuts[j] > x) { cuts[j + 1] = cuts[j]; --j; }
        cuts[j + 1] = x;
    }

    const float ringStep = 2.0 * HL_PI / float(HEMISPHERE_RING_SAMPLES);
    const float cosStep = cos(ringStep), sinStep = sin(ringStep);
    float total = 0.0;
    for (int piece = 0; piece + 1 < cutCount; ++piece) {
        float sLo = cuts[piece], sHi = cuts[piece + 1];
        if (!(sHi > sLo)) continue;
        for (int panel = 0; panel < HEMISPHERE_RADIAL_PANELS; ++panel)
            for (int i = 0; i < 2 * HEMISPHERE_GAUSS_HALF; ++i) {
                float x = ((i & 1) == 1 ? 1.0 : -1.0) * HL_GAUSS_X[i / 2];
                float tt = (float(panel) + 0.5 + 0.5 * x) / float(HEMISPHERE_RADIAL_PANELS);
                float s = sLo + (sHi - sLo) * tt * tt * (3.0 - 2.0 * tt);
                float ws = (sHi - sLo) * 6.0 * tt * (1.0 - tt) * 0.5 * HL_GAUSS_W[i / 2] / float(HEMISPHERE_RADIAL_PANELS);
                if (!(s > 0.0)) continue;
                float logC = log(s) / e, c = exp(logC);
                float st = sqrt(hlOneMinusExp(logC) * (1.0 + c));
                float A = nv * c, B = sv * st, C = un * c, D = ut * st, E = ub * st;
                float need = max(0.0, nv / (2.0 * c));
                float phiN = B <= 0.0 ? (A > need ? HL_PI : 0.0) : acos(clamp((need - A) / B, -1.0, 1.0));
                if (!(phiN > 0.0)) continue;
                float P0 = A * (2.0 * c * A - nv), P1 = B * (2.0 * c * A - nv) + 2.0 * c * A * B, P2 = 2.0 * c * B * B;
                if (!cut) {  // the whole arc |φ| < φn in closed form
                    total += ws * 4.0 * (P0 * 2.0 * phiN + P1 * 2.0 * sin(phiN) + P2 * (phiN + 0.5 * sin(2.0 * phiN)));
                    continue;
                }
                float ring = 0.0;
                float p0 = -HL_PI, cp0 = -1.0, sp0 = 0.0;
                float g0 = 2.0 * (A + B * cp0) * (C + D * cp0 + E * sp0) - uv;
                for (int k = 1; k <= HEMISPHERE_RING_SAMPLES; ++k) {
                    float p1 = -HL_PI + float(k) * ringStep;
                    float cp1 = cp0 * cosStep - sp0 * sinStep, sp1 = sp0 * cosStep + cp0 * sinStep;
                    float g1 = 2.0 * (A + B * cp1) * (C + D * cp1 + E * sp1) - uv;
                    float lo = p0, hi = p1;
                    bool use = g0 > 0.0 || g1 > 0.0;
                    if ((g0 > 0.0) != (g1 > 0.0)) {
                        // False position, Illinois variant (as the C++ rule).
                        float a = p0, fa = g0, z = p1, fz = g1;
                        for (int it = 0; it < HEMISPHERE_ROOT_STEPS && fz != fa; ++it) {
                            float x = z - fz * (z - a) / (fz - fa), cx = cos(x), sx = sin(x);
                            float fx = 2.0 * (A + B * cx) * (C + D * cx + E * sx) - uv;
                            if ((fx > 0.0) != (fz > 0.0)) { a = z; fa = fz; } else { fa *= 0.5; }
                            z = x;
                            fz = fx;
                        }
                        float root = z;
                        if (g0 > 0.0) hi = root; else lo = root;
                    }
                    lo = max(lo, -phiN);
                    hi = min(hi, phiN);
                    if (use && hi > lo)
                        ring += 4.0 * (P0 * (hi - lo) + P1 * (sin(hi) - sin(lo)) +
                                       P2 * (0.5 * (hi - lo) + 0.25 * (sin(2.0 * hi) - sin(2.0 * lo))));
                    p0 = p1; cp0 = cp1; sp0 = sp1; g0 = g1;
                }
                total += ws * ring;
            }
    }
    return total / e;
}

float hemisphereLobe(vec3 n, vec3 v, vec3 u, float gloss) { return hlLobeIntegral(n, v, u, true, gloss); }
float unoccludedLobe(vec3 n, vec3 v, float gloss) { return hlLobeIntegral(n, v, n, false, gloss); }
