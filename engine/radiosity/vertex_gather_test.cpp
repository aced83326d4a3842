// Gathering at points: the closed form over a refined polygon, the foot of a wall, occlusion,
// points buried in a solid.
#include "radiosity/vertex_gather.h"

#include "radiosity/element_mesh.h"
#include "radiosity/form_factor.h"

#include <gtest/gtest.h>

using namespace metamer;
using namespace metamer::radiosity;
using glm::dvec3;

namespace {

std::vector<std::array<dvec3, 3>> refined(const std::vector<dvec3>& p, const std::vector<uint32_t>& indices, double edge) {
    const ElementMesh m = refineMesh(p, indices, edge, 100000);
    std::vector<std::array<dvec3, 3>> out;
    for (size_t t = 0; t < m.triangles.size(); ++t) out.push_back(m.corners(t));
    return out;
}

}  // namespace

// The point factors to a polygon's elements add up to the polygon's (its inner edges cancel in
// Lambert's contour integral): Howell B-3 under the corner of a 2 × 3 rectangle, 0.2175752061 —
// to 1e-8, not to rounding: the elements 4 of their edges away take the rule on them
// (pointToTriangleByRule; 2.2e-9 relative here).
TEST(VertexGather, ElementsOfAPolygonSumToItsClosedForm) {
    const auto rectangle = refined({dvec3(0, 0, 1), dvec3(0, 3, 1), dvec3(2, 3, 1), dvec3(2, 0, 1)}, {0, 1, 2, 0, 2, 3}, 0.4);
    const GatherPoint x{dvec3(0), dvec3(0, 0, 1)};
    const Eigen::MatrixXd W = gatherFactors(std::span(&x, 1), rectangle, nullptr);
    EXPECT_NEAR(W.row(0).sum(), 0.217575206107758, 1e-8);
}

// A floor's vertex at the foot of a wall sees the wall as a point just in front of it does (the
// factor jumps to 0 in the wall's own plane): evaluated a hair towards the floor's elements.
TEST(VertexGather, AVertexAtTheFootOfAWallSeesItFromTheFloorsSide) {
    // A 2 × 2 wall in the plane y = 0 facing +y, standing on the floor z = 0.
    const auto wall = refined({dvec3(-1, 0, 0), dvec3(-1, 0, 2), dvec3(1, 0, 2), dvec3(1, 0, 0)}, {0, 1, 2, 0, 2, 3}, 0.3);
    const GatherPoint foot{dvec3(0), dvec3(0, 0, 1), dvec3(0, 0.1, 0)};
    const double atFoot = gatherFactors(std::span(&foot, 1), wall, nullptr).row(0).sum();
    double nearby = 0.0;
    for (const auto& e : wall) nearby += pointToPolygon(dvec3(0, 1e-6, 0), dvec3(0, 0, 1), e);
    EXPECT_GT(atFoot, 0.3);
    EXPECT_NEAR(atFoot, nearby, 1e-5);
    // Without the hair: in the wall's plane every element is edge-on and nothing is seen.
    const GatherPoint inPlane{dvec3(0), dvec3(0, 0, 1)};
    EXPECT_LT(gatherFactors(std::span(&inPlane, 1), wall, nullptr).row(0).sum(), 1e-3);
}

// A plate between a point and a square above hides the elements whose centroids it covers.
TEST(VertexGather, OccludersHideTheElementsBehindThem) {
    const auto square = refined({dvec3(-1, -1, 2), dvec3(-1, 1, 2), dvec3(1, 1, 2), dvec3(1, -1, 2)}, {0, 1, 2, 0, 2, 3}, 0.2);
    std::vector<BvhTriangle> scene;
    for (const auto& e : square) scene.push_back({e[0], e[1], e[2], 0, 0});
    // The plate at z = 1 over |x|, |y| < 0.25: from the origin it covers |x|, |y| < 0.5 at z = 2.
    scene.push_back({dvec3(-0.25, -0.25, 1), dvec3(0.25, -0.25, 1), dvec3(0.25, 0.25, 1), 1, 0});
    scene.push_back({dvec3(-0.25, -0.25, 1), dvec3(0.25, 0.25, 1), dvec3(-0.25, 0.25, 1), 1, 1});
    const Bvh bvh(scene);
    const GatherPoint x{dvec3(0), dvec3(0, 0, 1)};
    const Eigen::MatrixXd open = gatherFactors(std::span(&x, 1), square, nullptr);
    const Eigen::MatrixXd shaded = gatherFactors(std::span(&x, 1), square, &bvh);
    for (size_t j = 0; j < square.size(); ++j) {
        const dvec3 c = (square[j][0] + square[j][1] + square[j][2]) / 3.0;
        const bool behind = std::fabs(c.x) < 0.5 && std::fabs(c.y) < 0.5;
        EXPECT_EQ(shaded(0, Eigen::Index(j)), behind ? 0.0 : open(0, Eigen::Index(j))) << j;
    }
    // What is hidden is about the covered square's factor, 4 × Howell B-3 with X = Y = 0.25 at 2:
    // 0.0735 (the elements straddling its edge count whole or not at all).
    EXPECT_NEAR(open.row(0).sum() - shaded.row(0).sum(), 0.0735, 0.01);
}

// A floor's vertex under a closed box standing on it is buried: every ray of the fan leaves
// through the back of the box's faces. One beside the box, and one under an open shelf of the same
// faces (not a solid), is not.
TEST(VertexGather, APointUnderABoxOnTheFloorIsBuried) {
    // The box [0, 1]³ as 12 triangles counter-clockwise from outside, mesh 0 (closed) or 1 (open).
    auto box = [](uint32_t mesh) {
        std::vector<BvhTriangle> out;
        // Per face: a corner and two edges whose cross product points out.
        const std::array<std::array<dvec3, 3>, 6> faces{{{dvec3(0, 0, 0), dvec3(0, 1, 0), dvec3(1, 0, 0)},  // z = 0, −z
                                                         {dvec3(0, 0, 1), dvec3(1, 0, 0), dvec3(0, 1, 0)},  // z = 1, +z
                                                         {dvec3(0, 0, 0), dvec3(0, 0, 1), dvec3(0, 1, 0)},  // x = 0, −x
                                                         {dvec3(1, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, 1)},  // x = 1, +x
                                                         {dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(0, 0, 1)},  // y = 0, −y
                                                         {dvec3(0, 1, 0), dvec3(0, 0, 1), dvec3(1, 0, 0)}}};  // y = 1, +y
        for (const auto& [c, a, b] : faces) {
            out.push_back({c, c + a, c + a + b, mesh, 0});
            out.push_back({c, c + a + b, c + b, mesh, 0});
        }
        return out;
    };
    // The floor is the plane y = 0; the box stands on it.
    const GatherPoint under{dvec3(0.5, 0.0, 0.5), dvec3(0, 1, 0), dvec3(0.05, 0, 0)};
    const GatherPoint beside{dvec3(1.2, 0.0, 0.5), dvec3(0, 1, 0), dvec3(0.05, 0, 0)};
    const GatherPoint atItsFoot{dvec3(1.0, 0.0, 0.5), dvec3(0, 1, 0), dvec3(0.05, 0, 0)};  // towards outside
    const std::vector<GatherPoint> points{under, beside, atItsFoot};
    const Bvh closedBox(box(0)), openBox(box(1));
    EXPECT_EQ(buriedPoints(points, closedBox, {1, 0}), (std::vector<char>{1, 0, 0}));
    EXPECT_EQ(buriedPoints(points, openBox, {1, 0}), (std::vector<char>{0, 0, 0}));
}
