// The integrals a hemisphere light's lobe table is built from, in double (docs/physics.md,
// "Hemisphere lights"; shaders/lobe_lookup.h for the coordinates):
//
//     I(n, v, u, N) = ∫ (n·h)^N (n·ω) dω  over n·ω > 0 and u·ω > 0,   h = normalize(ω + v).
//
// Everything here is in the frame of one view: n = z, v in the x–z plane at elevation θe above
// the surface, so v = (cos θe, 0, sin θe), the mirror direction r = (−cos θe, 0, sin θe),
// e1 = (sin θe, 0, cos θe) (⊥ r, towards n) and e2 = y.
//
// - lobeMoments: the unoccluded lobe I_unoccluded, its centroid direction (the angle γ from r
//   towards e1) and its spreads σ1, σ2 (rms of ω's components along e1 turned by γ, and along e2),
//   and the early-out cone: the smallest half-angle 2θ0 about r holding all but `tail` of the lobe.
//   Computed over rings of half vectors at n·h = c, s = c^(N+1) (the lobe's weight is uniform in s):
//   each ring's arc n·ω > 0 in closed form, Gauss–Legendre along it, adaptive Gauss–Kronrod in s.
// - hemisphereFractions: I/I_unoccluded for a family of hemispheres sharing one boundary axis
//   (u = sin ε·c + cos ε·m, m = cos β·e1c + sin β·e2, c the centroid): all from one profile of the
//   lobe around that axis, P(ψ) = ∫ L dζ (the lobe integrated along great semicircles through the
//   axis), cumulated in ψ, since each hemisphere is the interval |ψ − (π/2 − ε)| < π/2. The 2-D
//   integral is adaptive Gauss–Kronrod in ψ and in ζ, started from pieces laid out by the lobe's
//   own size and shape (its centroid, σ1 and σ2 along the axis, its conditional centre line, where
//   the surface horizon crosses, the point −v where a grazing lobe ends), so that no part of a
//   thin lobe falls between the first nodes.
//
// Tests: reference/lobe_table_test.cpp (against two independent quadratures, tests/support/
// lobe_oracles.h).
#pragma once

#include <vector>

namespace metamer {

struct LobeMoments {
    double unoccluded = 0.0;       // I_unoccluded, sr
    double gamma = 0.0;            // the centroid's angle from r towards n, rad
    double sigma1 = 0.0, sigma2 = 0.0;
    double coneHalfAngle = 0.0;    // 2θ0, rad (≥ π/2: the lobe reaches the whole sky)
};

// thetaE ∈ [0, π/2], gloss > 0; tail: the share of the lobe allowed outside the cone.
LobeMoments lobeMoments(double thetaE, double gloss, double tail);

// I/I_unoccluded for each ε of `epsilons` (|ε| ≤ π/2), hemispheres u = sin ε·c + cos ε·m about the
// centroid c at γ with m at the angle β (from e1c towards e2); and I_unoccluded as the profile's total.
struct HemisphereFractions {
    std::vector<double> fractions;
    double unoccluded = 0.0;
};
HemisphereFractions hemisphereFractions(double thetaE, double gloss, double gamma, double sigma1, double sigma2,
                                        double beta, const std::vector<double>& epsilons, double relTol);

}  // namespace metamer
