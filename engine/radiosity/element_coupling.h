// The form-factor matrix of a set of elements with occlusion: F_ij, the irradiance element i
// receives from element j's unit radiosity (H_i = Σ_j F_ij B_j), for every pair.
// Each receiver's factor is averaged over a degree-5 rule of 7 points on it, each point's factor to
// the emitter in closed form (radiosity/form_factor.h), if the receiver's centroid sees the
// emitter's past the occluders (one ray through the scene's BVH). Pairs nearer than `nearRatio`
// times the larger element's size — neighbours sharing an edge, a box's side and the floor it stands
// on — are averaged by adaptive quadrature instead, to `tolerance`, where the point factor's slope
// is unbounded, and take the share of the rule's points that see the emitter's centroid (7 rays),
// where partial shadows matter most. Pairs farther than `farRatio` × that size, each wholly in
// front of the other, take the rule on both ends instead (pointToTriangleByRule: no arc tangent;
// most of a room's pairs). Pairs that cannot see each other (coplanar, behind one another) cost
// one test.
// Each pair is computed once, from the element listed first; the other direction follows by
// reciprocity (A_j F_ji = A_i F_ij, exactly). Computed once per scene, on every core; the same for every band and every spectrum of a sweep.
// Tests: engine/radiosity/element_coupling_test.cpp (a closed box's rows, reciprocity, occlusion by
// a plate against its closed form).
#pragma once

#include "radiosity/form_factor.h"
#include "reference/bvh.h"

#include <Eigen/Dense>

#include <array>
#include <span>

namespace metamer::radiosity {

struct CouplingOptions {
    // The adaptive quadrature's, for near pairs (absolute, on F). 1e-6 cost the Cornell box's 2302
    // elements twice the time (5.7 M rule evaluations against 1.8 M) for images within 4e-5 (median
    // 6e-8); a closed box's worst row sum is 1.5e-6 from 1 at 384 elements (element_coupling_test).
    double tolerance = 1e-5;
    double nearRatio = 2.0;   // a pair is near when its centroids are closer than this × the larger element's longest edge
    // A pair is far when they are farther apart than this × the larger's edge and each lies wholly in
    // front of the other: then the rule on both ends (no arc tangent), within ~1e-7 of the closed form's
    // average at 4 (its median over random pairs; ~1e-5 at worst, grazing).
    double farRatio = kRuleFarRatio;
};

struct Coupling {
    Eigen::MatrixXd formFactors;  // [receiver][emitter]
    size_t nearPairs = 0, rays = 0, blockedRays = 0;
    double seconds = 0.0;
};

// `occluders`: the scene's BVH (null: nothing occludes), whose triangles `elementSource` names
// for each element (its index in occluders->triangles(), which its own rays do not test against).
Coupling formFactorMatrix(std::span<const std::array<glm::dvec3, 3>> elements, const Bvh* occluders,
                          std::span<const uint32_t> elementSource, const CouplingOptions& options = {});

}  // namespace metamer::radiosity
