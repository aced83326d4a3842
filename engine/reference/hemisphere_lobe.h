// The specular reflection of a uniform hemisphere of radiance (a sky, a ground) off the
// energy-normalized Blinn–Phong lobe: the geometric integral
//
//     I(n, v, u, N) = ∫ (n·h)^N · (n·ω) dω   over directions ω with n·ω > 0 and u·ω > 0,
//
// h = normalize(ω + v), so that the reflected radiance is ρs·L·(N+8)/(8π)·I. N = 0 has the closed
// form π(1 + n·u)/2 (the irradiance factor of the hemisphere); any other gloss comes from its lobe
// table (reference/lobe_table.h, the lookup both renderers share). docs/physics.md, "Hemisphere
// lights". Tests: reference/lobe_table_test.cpp.
#pragma once

#include "reference/lobe_table.h"
#include "scene/scene.h"

#include <glm/glm.hpp>

#include <vector>

namespace metamer {

// (I(n, v, u, N), I_unoccluded) with N the table's gloss, or 0 when `table` is null.
glm::dvec2 hemisphereLobe(const LobeTable* table, const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& u);

// A hemisphere light whose up is exactly opposite the previous hemisphere light's (a ground after
// its sky) takes the rest of the whole lobe: I(−u) = I_unoccluded − I(u), never below 0. Both
// renderers take this shortcut; it makes a sky and its ground sum to the unoccluded lobe exactly.
// Per light of `lights`: whether it is such a light (in this order, which both renderers keep for
// hemisphere lights).
std::vector<bool> pairedWithPreviousHemisphere(const std::vector<Light>& lights);

}  // namespace metamer
