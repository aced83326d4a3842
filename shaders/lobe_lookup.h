// The hemisphere lights' specular lobe from a precomputed table, one lookup shared by C++ and GLSL
// (the CPU reference evaluates it in double on the same float data; the GPU in float), so that both
// renderers compute the same quantity. The table is built once per gloss by
// engine/reference/lobe_table.cpp, which derives what follows; docs/physics.md, "Hemisphere lights",
// gives the definitions and the certified error.
//
//     I(n, v, u, N)  = ∫ (n·h)^N (n·ω) dω  over n·ω > 0 and u·ω > 0,   h = normalize(ω + v)
//     I_unoccluded   = the same over n·ω > 0 alone
//
// Coordinates that make the table small and smooth (lobe-centred, "whitened"): the view's
// elevation θe above the tangent plane (warped by x1 = ln(1 + kθe)/ln(1 + kπ/2), k = 0.5·√(N+1),
// so grazing views get nodes on the lobe's own scale); the lobe's centroid c, in the plane of
// incidence at the angle γ from the mirror direction r towards the surface normal, and its spreads
// σ1 (in that plane) and σ2 (across it), from the 1-D moment table; then u's hemisphere boundary
// seen from c in coordinates where the lobe is round: its direction β_w = atan2(σ2·q, σ1·p) ∈ [0, π]
// and its signed distance d = (u·c)/√(σ1²p² + σ2²q²), mapped to x2 = (2/π)·atan(d/2.5) ∈ [−1, 1].
// The table holds f = I/I_unoccluded at (x1, β_w, x2) nodes; the lookup is tricubic (Lagrange,
// 4 nodes an axis; one-sided at the ends of x1 and x2, mirrored at β_w = 0 and π, where f is even),
// the moments linear in x1 on a finer grid (ln I_unoccluded cubic Hermite). f is stored as 16-bit fixed point (steps of 1/65535,
// so rounding adds at most 7.6·10⁻⁶, inside the certified error), and each uvec4 entry holds, for
// two neighbouring β_w nodes, the four x2 values one cubic needs: 8 fetches for f, 2 for the
// moments, 1 for the early-out.
//
// The early-out is exact to LOBE_CONE_TAIL of I_unoccluded: a half vector at angle θh from n
// reflects v to within 2θh of r (two reflections make a rotation by 2θh), and the lobe's mass
// beyond θh > θ0 is at most LOBE_CONE_TAIL·I_unoccluded (measured per x1 interval when the table is
// built), so a hemisphere whose boundary is more than 2θ0 from r holds all the lobe or none of it.
#ifndef METAMER_SHADERS_LOBE_TABLE_H
#define METAMER_SHADERS_LOBE_TABLE_H

#define LOBE_MOMENT_NODES 513  // x1 nodes of (γ, σ1, σ2, ln I_unoccluded), as float bits
#define LOBE_X1_NODES 32
#define LOBE_BETA_NODES 65
#define LOBE_X2_NODES 128
#define LOBE_X1_WARP 0.5
#define LOBE_X2_SCALE 2.5
#define LOBE_NO_CONE 2.0  // the cone entry of an interval whose lobe reaches past the horizon
// One table, in uvec4s: the moments (float bits), per moment interval the early-out cone (x: the
// sine of its half-angle) and the slopes of ln I_unoccluded at its ends (y, z; per interval), as
// float bits, then the values: for x1 node i1, β_w pair b (nodes
// b − 1 and b, with the mirrored nodes −1 and LOBE_BETA_NODES at the ends) and x2 interval j, the
// 16-bit values of the two nodes' cubics, two to a uint.
#define LOBE_CONES_OFFSET LOBE_MOMENT_NODES
#define LOBE_VALUES_OFFSET (LOBE_CONES_OFFSET + LOBE_MOMENT_NODES - 1)
#define LOBE_BETA_PAIRS (LOBE_BETA_NODES + 1)
#define LOBE_TABLE_UVEC4 (LOBE_VALUES_OFFSET + LOBE_X1_NODES * LOBE_BETA_PAIRS * (LOBE_X2_NODES - 1))
#define LOBE_PI 3.14159265358979323846

#endif  // METAMER_SHADERS_LOBE_TABLE_H

// The lookup, in the subset of C++ (with glm) and GLSL both compile. The includer defines
// LT_FLOAT, LT_VEC2, LT_VEC3, LT_VEC4 (float or double types), LOBE_FETCH(i) (uvec4 i of the
// tables' data), LOBE_FLOATS(u) (a uvec4's bits as LT_VEC4), LOBE_UNORM(x) (a uint's two 16-bit
// halves, low first, as an LT_VEC2 in [0, 1]), and LOBE_DATA_PARAM (an extra first parameter in
// C++, where the data is not global; empty in GLSL).
#if defined(LOBE_FETCH) && !defined(METAMER_SHADERS_LOBE_LOOKUP)
#define METAMER_SHADERS_LOBE_LOOKUP

// Lagrange weights of nodes 0, 1, 2, 3 at position t (in node units from node 0).
LT_VEC4 lobeCubicWeights(LT_FLOAT t) {
    LT_FLOAT a = t, b = t - 1.0, c = t - 2.0, d = t - 3.0;
    return LT_VEC4(-b * c * d / 6.0, a * c * d / 2.0, -a * b * d / 2.0, a * b * c / 6.0);
}

// The first of the four nodes around x on an axis of n nodes, one-sided at its ends.
int lobeStencil(LT_FLOAT x, int n) { return clamp(int(floor(x)) - 1, 0, n - 4); }

// The warp of a gloss's x1 axis, (k, 1/ln(1 + kπ/2)) with k = LOBE_X1_WARP·√(N + 1): x1 of a view
// at elevation θe ∈ [0, π/2] above the tangent plane is ln(1 + kθe)/ln(1 + kπ/2). Per material,
// not per fragment (the GPU gets it in the material block).
LT_VEC2 lobeWarp(LT_FLOAT gloss) {
    LT_FLOAT k = LOBE_X1_WARP * sqrt(gloss + 1.0);
    return LT_VEC2(k, 1.0 / log(1.0 + k * (0.5 * LOBE_PI)));
}

// (I(n, v, u, N), I_unoccluded) from the table at `base` (in uvec4s) with its gloss's warp. n, v, u
// unit; a view below the tangent plane (an interpolated normal turned away at a silhouette) is taken
// at the horizon.
LT_VEC2 lobeIntegrals(LOBE_DATA_PARAM int base, LT_VEC2 warp, LT_VEC3 n, LT_VEC3 v, LT_VEC3 u) {
    LT_FLOAT nv0 = dot(n, v);
    LT_VEC3 tangential = v - nv0 * n;
    LT_FLOAT sv = length(tangential);
    LT_VEC3 t = tangential / max(sv, 1e-30);
    if (!(sv > 1e-6)) t = normalize(cross(abs(n.x) < 0.9 ? LT_VEC3(1.0, 0.0, 0.0) : LT_VEC3(0.0, 1.0, 0.0), n));
    LT_FLOAT thetaE = sv > 1e-6 ? atan(max(nv0, 0.0), sv) : (nv0 > 0.0 ? 0.5 * LOBE_PI : 0.0);
    LT_FLOAT nv = sin(thetaE), cv = cos(thetaE);
    LT_VEC3 r = nv * n - cv * t;   // the mirror direction
    LT_VEC3 e1 = cv * n + nv * t;  // ⊥ r, in the plane of incidence, towards n
    LT_VEC3 e2 = cross(n, t);      // ⊥ the plane of incidence

    LT_FLOAT x1 = log(1.0 + warp.x * thetaE) * warp.y;
    LT_FLOAT xm = x1 * LT_FLOAT(LOBE_MOMENT_NODES - 1);
    int m0 = clamp(int(floor(xm)), 0, LOBE_MOMENT_NODES - 2);
    LT_FLOAT fm = xm - LT_FLOAT(m0);
    LT_VEC4 m0Moments = LOBE_FLOATS(LOBE_FETCH(base + m0)), m1Moments = LOBE_FLOATS(LOBE_FETCH(base + m0 + 1));
    LT_VEC4 moments = (1.0 - fm) * m0Moments + fm * m1Moments;  // γ, σ1, σ2: coordinates, linear
    LT_VEC4 interval = LOBE_FLOATS(LOBE_FETCH(base + LOBE_CONES_OFFSET + m0));
    // ln I_unoccluded: cubic Hermite between the nodes, with the slopes the interval entry holds.
    LT_FLOAT fm2 = fm * fm, fm3 = fm2 * fm;
    LT_FLOAT unoccluded = exp((2.0 * fm3 - 3.0 * fm2 + 1.0) * m0Moments.w + (fm3 - 2.0 * fm2 + fm) * interval.y +
                              (3.0 * fm2 - 2.0 * fm3) * m1Moments.w + (fm3 - fm2) * interval.z);

    LT_FLOAT ur = dot(u, r);
    if (abs(ur) > interval.x) return LT_VEC2(ur > 0.0 ? unoccluded : 0.0, unoccluded);

    LT_FLOAT gamma = moments.x, sigma1 = moments.y, sigma2 = moments.z;
    LT_VEC3 c = cos(gamma) * r + sin(gamma) * e1;
    LT_VEC3 e1c = cos(gamma) * e1 - sin(gamma) * r;
    LT_FLOAT a = sigma1 * dot(u, e1c), b = sigma2 * abs(dot(u, e2));
    LT_FLOAT across = sqrt(a * a + b * b);
    LT_FLOAT betaW = across > 0.0 ? atan(b, a) : 0.0;
    LT_FLOAT x2 = atan(dot(u, c), LOBE_X2_SCALE * across) * (2.0 / LOBE_PI);

    LT_FLOAT xx1 = x1 * LT_FLOAT(LOBE_X1_NODES - 1);
    LT_FLOAT xb = betaW * (LT_FLOAT(LOBE_BETA_NODES - 1) / LOBE_PI);
    LT_FLOAT xx2 = (x2 + 1.0) * (0.5 * LT_FLOAT(LOBE_X2_NODES - 1));
    int i1 = lobeStencil(xx1, LOBE_X1_NODES);
    int ib = clamp(int(floor(xb)), 0, LOBE_BETA_NODES - 2);  // the β_w stencil: nodes ib − 1 … ib + 2
    int j = clamp(int(floor(xx2)), 0, LOBE_X2_NODES - 2);
    LT_VEC4 w1 = lobeCubicWeights(xx1 - LT_FLOAT(i1));
    LT_VEC4 wb = lobeCubicWeights(xb - LT_FLOAT(ib - 1));
    LT_VEC4 w2 = lobeCubicWeights(xx2 - LT_FLOAT(lobeStencil(xx2, LOBE_X2_NODES)));
    LT_FLOAT f = 0.0;
    for (int p = 0; p < 4; ++p) {
        // Pair b holds nodes b − 1 and b: pairs ib and ib + 2 are the stencil's four.
        int entry = base + LOBE_VALUES_OFFSET + ((i1 + p) * LOBE_BETA_PAIRS + ib) * (LOBE_X2_NODES - 1) + j;
        uvec4 low = LOBE_FETCH(entry), high = LOBE_FETCH(entry + 2 * (LOBE_X2_NODES - 1));
        LT_VEC4 alongBeta = LT_VEC4(dot(w2, LT_VEC4(LOBE_UNORM(low.x), LOBE_UNORM(low.y))),
                                    dot(w2, LT_VEC4(LOBE_UNORM(low.z), LOBE_UNORM(low.w))),
                                    dot(w2, LT_VEC4(LOBE_UNORM(high.x), LOBE_UNORM(high.y))),
                                    dot(w2, LT_VEC4(LOBE_UNORM(high.z), LOBE_UNORM(high.w))));
        f += w1[p] * dot(wb, alongBeta);
    }
    return LT_VEC2(clamp(f, 0.0, 1.0) * unoccluded, unoccluded);
}

#endif  // LOBE_FETCH
