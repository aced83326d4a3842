// The specular reflection of a uniform hemisphere of radiance (a sky, a ground) off the
// energy-normalized Blinn–Phong lobe: the geometric integral
//
//     I(n, v, u, N) = ∫ (n·h)^N · (n·ω) dω   over directions ω with n·ω > 0 and u·ω > 0,
//
// h = normalize(ω + v), so that the reflected radiance is ρs·L·(N+8)/(8π)·I. N = 0 has the closed
// form π(1 + n·u)/2 (the irradiance factor of the hemisphere). Otherwise a deterministic rule:
// half vectors on rings of constant n·h, with s = (n·h)^(N+1) as the radial variable (the lobe's
// weight is uniform in s); on a ring the surface's horizon is one arc and the integrand
// 4(v·h)(n·ω) a quadratic in cos φ, both in closed form, while the hemisphere's horizon is found
// by sampling the ring and refining each change of sign; along s, Gauss–Legendre piece by piece
// between the rings that touch either horizon, each piece mapped by a smoothstep so the
// square-root behaviour there does not slow convergence. The GPU (shaders/hemisphere_lobe.glsl)
// runs the same rule in float. docs/physics.md, "Hemisphere lights", gives the derivation and the measured error.
// Tests: engine/reference/hemisphere_lobe_test.cpp.
#pragma once

#include "hemisphere_quadrature.h"

#include "scene/scene.h"

#include <glm/glm.hpp>

#include <vector>

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

// Per light of `lights`: whether it is a hemisphere light whose up is exactly opposite that of the
// hemisphere light before it (in this order, which both renderers keep for hemisphere lights) —
// the lights that take oppositeHemisphereLobe.
std::vector<bool> pairedWithPreviousHemisphere(const std::vector<Light>& lights);

}  // namespace metamer
