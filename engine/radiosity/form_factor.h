// Form factors between diffuse surfaces, the geometric coupling of radiosity: how much of the
// light leaving one surface uniformly (Lambertian) arrives at another, independent of wavelength.
//   pointToPolygon: from a differential area at x (unit normal n) to a planar polygon, in closed
//     form (Lambert's contour integral: F = (1/2π) Σ_k γ_k n·ĝ_k over the polygon's edges, the
//     polygon clipped to x's hemisphere first) — exact for an unoccluded polygon;
//   triangleToPolygon: from a triangle, the point factor averaged over it by adaptive quadrature
//     (a degree-5 rule compared with the same rule on the triangle's four halves, subdivided where
//     they differ), which converges at shared edges where the integrand's slope is unbounded.
// A polygon is seen from its front only: its vertices counter-clockwise seen from the side its
// normal points to (the winding of scene/scene.h's meshes); from behind, or from its own plane, the
// factor is 0. Everything in double. Visibility is not here: these are the unoccluded factors
// (radiosity/element_coupling.h adds occlusion).
// Tests: engine/radiosity/form_factor_test.cpp (Howell's catalogue: parallel and perpendicular
// squares, coaxial disks; reciprocity; a closed cube's rows sum to 1).
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <span>

namespace metamer::radiosity {

// The degree-5, 7-point rule on a triangle (Strang & Fix; Dunavant's n = 5): barycentric points
// and weights summing to 1. triangleToPolygon's, and the rule element_coupling and scene_radiosity
// average over an element with.
struct TrianglePoint {
    double a, b, c, w;
    glm::dvec3 on(const std::array<glm::dvec3, 3>& t) const { return a * t[0] + b * t[1] + c * t[2]; }
};
namespace rule7 {
constexpr double kA1 = 0.059715871789769820, kB1 = 0.470142064105115090, kW1 = 0.132394152788506181;
constexpr double kA2 = 0.797426985353087322, kB2 = 0.101286507323456339, kW2 = 0.125939180544827153;
}  // namespace rule7
inline constexpr std::array<TrianglePoint, 7> kTriangleRule = {{{1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 0.225},
                                                                {rule7::kA1, rule7::kB1, rule7::kB1, rule7::kW1},
                                                                {rule7::kB1, rule7::kA1, rule7::kB1, rule7::kW1},
                                                                {rule7::kB1, rule7::kB1, rule7::kA1, rule7::kW1},
                                                                {rule7::kA2, rule7::kB2, rule7::kB2, rule7::kW2},
                                                                {rule7::kB2, rule7::kA2, rule7::kB2, rule7::kW2},
                                                                {rule7::kB2, rule7::kB2, rule7::kA2, rule7::kW2}}};

// F from the differential area at x (unit normal n) to the polygon's front side, in [0, 1].
double pointToPolygon(const glm::dvec3& x, const glm::dvec3& n, std::span<const glm::dvec3> polygon);

// The same for a triangle whose unit front normal is known, without allocating: the form factors
// of a scene's elements are billions of these.
double pointToTriangle(const glm::dvec3& x, const glm::dvec3& n, const std::array<glm::dvec3, 3>& triangle,
                       const glm::dvec3& front);

// The same by the rule on the triangle (its 7 points `rule`, area, front normal):
// area · Σ_k w_k cos θ_x cos θ_k / (π d_k²), no arc tangent. Only for a triangle far from x (several
// of its edges away: within ~1e-7 of the closed form at 4) that lies wholly above x's plane, with x
// in front of it — where nothing needs clipping; the callers check.
double pointToTriangleByRule(const glm::dvec3& x, const glm::dvec3& n, const std::array<glm::dvec3, 7>& rule,
                             const glm::dvec3& front, double area);
// From how many of a triangle's longest edges away its callers take the rule instead of the
// closed form (element_coupling's far pairs, vertex_gather's far elements).
inline constexpr double kRuleFarRatio = 4.0;
// The triangle's longest edge, m.
double longestEdge(const std::array<glm::dvec3, 3>& t);

// F from the triangle (a, b, c: its front side, counter-clockwise) to the polygon, to within
// `tolerance` (absolute; the adaptive quadrature stops refining a piece whose two estimates agree
// to its area's share of it). 0 when either faces away from the other.
double triangleToPolygon(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                         std::span<const glm::dvec3> polygon, double tolerance = 1e-10);

// The polygon's unit normal (Newell's method, robust for any planar polygon) and area.
glm::dvec3 polygonNormal(std::span<const glm::dvec3> polygon);
double polygonArea(std::span<const glm::dvec3> polygon);

}  // namespace metamer::radiosity
