// The specular reflection of a uniform hemisphere of radiance (a sky, a ground) off the
// energy-normalized Blinn–Phong lobe: the geometric integral
//
//     I(n, v, u, N) = ∫ (n·h)^N · (n·ω) dω   over directions ω with n·ω > 0 and u·ω > 0,
//
// h = normalize(ω + v), so that the reflected radiance is ρs·L·(N+8)/(8π)·I. N = 0 has the closed
// form π(1 + n·u)/2 (the irradiance factor of the hemisphere). Otherwise a deterministic rule:
// rings of directions around the mirror direction r of v, on each of which both horizons cut
// exact arcs; Gauss–Legendre along the arcs, and along the ring radius in s = cos(α/2)^(N+2)
// (where the lobe's weight is nearly uniform), piece by piece between the radii at which a ring
// touches a horizon, each piece mapped by a smoothstep so the square-root behaviour at those
// radii does not slow convergence. The GPU (shaders/hemisphere_lobe.glsl) runs the same rule in
// float. docs/physics.md, "Hemisphere lights", gives the derivation and the measured error.
// Tests: engine/reference/hemisphere_lobe_test.cpp.
#pragma once

#include "hemisphere_quadrature.h"

#include <glm/glm.hpp>

namespace metamer {

// n, v, u unit vectors (normal, towards the eye, towards the hemisphere's middle); gloss N ≥ 0.
// `subdivide` splits every radial piece and every arc into that many equal parts (1: the rule
// both renderers use; larger: the same rule refined, for measuring its error).
double hemisphereLobe(const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& u, double gloss,
                      int radialPanels = HEMISPHERE_RADIAL_PANELS, int ringSamples = HEMISPHERE_RING_SAMPLES);

// The lobe over the whole hemisphere above the surface (no hemisphere cut): the same rule without
// its hemisphere part, each ring integrated in closed form — far cheaper.
double unoccludedLobe(const glm::dvec3& n, const glm::dvec3& v, double gloss, int radialPanels = HEMISPHERE_RADIAL_PANELS);

// A hemisphere light whose up is exactly opposite the previous hemisphere light's (a ground after
// its sky): I(−u) = I_unoccluded − I(u), never below 0. Both renderers take this shortcut for such
// a pair, which halves the cost of a sky and a ground.
double oppositeHemisphereLobe(const glm::dvec3& n, const glm::dvec3& v, double gloss, double lobeOfOpposite);

}  // namespace metamer
