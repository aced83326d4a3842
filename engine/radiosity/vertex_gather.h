// The indirect irradiance at points — the element mesh's vertices, where the renderer
// interpolates it across each element — gathered from the elements' radiosity:
// H(x) = Σ_j F(x → j)·V(x, j)·B_j, F the closed-form point-to-polygon factor (exact for what
// is unoccluded; for an element 4 of its edges away, wholly above x's plane, the rule on it, within
// ~1e-7), V whether x sees element j's centroid past the occluders. The factors W_xj =
// F·V depend on the geometry only: computed once per scene, they turn any band's B into the
// points' H by one product (H = W·B), for every spectrum of a sweep.
//
// A vertex on the boundary of an element of another surface (a floor's vertex at the foot of a
// wall) is where the point factor jumps (0.5 from the floor side, 0 in the wall's plane); each point
// is evaluated a hair inside its own surface (towards `inside`), on the side the renderer shades.
// Tests: engine/radiosity/vertex_gather_test.cpp (closed forms at points, the foot of a wall,
// occlusion).
#pragma once

#include "reference/bvh.h"

#include <Eigen/Dense>

#include <array>
#include <span>
#include <vector>

namespace metamer::radiosity {

struct GatherPoint {
    glm::dvec3 position, normal;  // normal: unit, the side that receives
    glm::dvec3 inside{0.0};      // towards the middle of the point's own elements, about an element long (zero: none needed)
    uint32_t source = ~0u;       // its triangle in the occluders' BVH, which its rays skip
};

// W [point][element]. `occluders` null: nothing occludes.
// `side` 0: each element's visibility is whether the point sees its centroid; else the share of
// side × side stratified points on it that the point sees — for the emitters whose direct light
// the renderer draws per pixel, whose shadows' edges the vertices must sample smoothly.
Eigen::MatrixXd gatherFactors(std::span<const GatherPoint> points, std::span<const std::array<glm::dvec3, 3>> elements,
                              const Bvh* occluders, int side = 0);

// Whether each point lies inside a closed solid — a floor's vertex under a box standing on it: every
// one of a fan of rays over its hemisphere leaves through the back of a closed mesh's triangle.
// Such a point sees nothing; what it gathers is no value for the pixels beside it to interpolate.
// `closed`: per mesh of the occluders' triangles, whether it bounds a solid (Mesh::closed).
std::vector<char> buriedPoints(std::span<const GatherPoint> points, const Bvh& occluders, const std::vector<char>& closed);

}  // namespace metamer::radiosity
