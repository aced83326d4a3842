// Conforming refinement of meshes into elements: no T-junctions, areas and windings kept, edges as
// short as asked, shapes kept, attributes interpolated.
#include "radiosity/element_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

using namespace metamer::radiosity;
using glm::dvec3;

namespace {

// Every edge of the elements with the triangles using it.
std::map<std::pair<uint32_t, uint32_t>, int> edgeUse(const ElementMesh& m) {
    std::map<std::pair<uint32_t, uint32_t>, int> use;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
            ++use[{std::min(a, b), std::max(a, b)}];
        }
    return use;
}

// No vertex of the mesh lies inside an edge it is not an end of (a T-junction), checked by brute force.
int tJunctions(const ElementMesh& m) {
    int found = 0;
    for (const auto& [edge, count] : edgeUse(m)) {
        const dvec3 a = m.vertices[edge.first], b = m.vertices[edge.second];
        const double l2 = glm::dot(b - a, b - a);
        for (uint32_t v = 0; v < m.vertices.size(); ++v) {
            if (v == edge.first || v == edge.second) continue;
            const double s = glm::dot(m.vertices[v] - a, b - a) / l2;
            if (s <= 1e-9 || s >= 1 - 1e-9) continue;
            const dvec3 closest = a + s * (b - a);
            if (glm::length(m.vertices[v] - closest) < 1e-12) ++found;
        }
    }
    return found;
}

double smallestAngleDegrees(const ElementMesh& m) {
    double smallest = 180.0;
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        const auto c = m.corners(t);
        for (int k = 0; k < 3; ++k) {
            const dvec3 u = glm::normalize(c[size_t((k + 1) % 3)] - c[size_t(k)]), v = glm::normalize(c[size_t((k + 2) % 3)] - c[size_t(k)]);
            smallest = std::min(smallest, std::acos(std::clamp(glm::dot(u, v), -1.0, 1.0)) * 180.0 / 3.14159265358979323846);
        }
    }
    return smallest;
}

}  // namespace

// A unit square of two triangles, refined to edges of at most 0.1: the elements cover it exactly,
// face the same way, meet edge to edge, and keep Rivara's bound on their angles (at least half the
// input's smallest, 45°).
TEST(ElementMesh, ASquareRefinesConforminglyKeepingAreaWindingAndShape) {
    const std::vector<dvec3> square{dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(1, 1, 0), dvec3(0, 1, 0)};
    const std::vector<uint32_t> indices{0, 1, 2, 0, 2, 3};
    const ElementMesh m = refineMesh(square, indices, 0.1, 100000);
    EXPECT_GT(m.triangles.size(), 200u);
    double area = 0.0;
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        area += m.area(t);
        EXPECT_NEAR(m.normal(t).z, 1.0, 1e-12);
        for (int k = 0; k < 3; ++k) {
            const dvec3 d = m.vertices[m.triangles[t][size_t(k)]] - m.vertices[m.triangles[t][size_t((k + 1) % 3)]];
            EXPECT_LE(glm::length(d), 0.1 + 1e-12);
        }
        EXPECT_LT(m.inputTriangle[t], 2u);
    }
    EXPECT_NEAR(area, 1.0, 1e-12);
    EXPECT_EQ(tJunctions(m), 0);
    // Interior edges have two triangles; edges used once lie on the square's boundary.
    for (const auto& [edge, count] : edgeUse(m)) {
        ASSERT_LE(count, 2);
        if (count == 1) {
            const dvec3 a = m.vertices[edge.first], b = m.vertices[edge.second];
            const bool boundary = (a.x == b.x && (a.x == 0 || a.x == 1)) || (a.y == b.y && (a.y == 0 || a.y == 1));
            EXPECT_TRUE(boundary) << a.x << "," << a.y << " – " << b.x << "," << b.y;
        }
    }
    EXPECT_GE(smallestAngleDegrees(m), 22.5 - 1e-9);
}

// Two triangles folded along their shared edge (a floor meeting a wall): refinement on one side
// splits the shared edge on the other too.
TEST(ElementMesh, AFoldedMeshStaysConformingAcrossTheFold) {
    const std::vector<dvec3> p{dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, 3)};
    const std::vector<uint32_t> indices{0, 1, 2, 1, 0, 3};  // the floor, and a tall wall sharing edge 0–1
    const ElementMesh m = refineMesh(p, indices, 0.3, 100000);
    EXPECT_EQ(tJunctions(m), 0);
    for (const auto& [edge, count] : edgeUse(m)) EXPECT_LE(count, 2);
    double floor = 0.0, wall = 0.0;
    for (size_t t = 0; t < m.triangles.size(); ++t) (m.inputTriangle[t] == 0 ? floor : wall) += m.area(t);
    EXPECT_NEAR(floor, 0.5, 1e-12);
    EXPECT_NEAR(wall, 1.5, 1e-12);
}

// An attribute linear over the input (here a position's coordinates) interpolates exactly onto every
// element vertex, as the rasterizer would across the input triangle.
TEST(ElementMesh, AttributesInterpolateOntoTheElementVertices) {
    const std::vector<dvec3> p{dvec3(0, 0, 0), dvec3(2, 0, 0), dvec3(0, 3, 0)};
    const std::vector<uint32_t> indices{0, 1, 2};
    const ElementMesh m = refineMesh(p, indices, 0.4, 100000);
    const std::vector<dvec3> attribute = interpolate<dvec3>(m, p);
    ASSERT_EQ(attribute.size(), m.vertices.size());
    for (size_t v = 0; v < m.vertices.size(); ++v) EXPECT_LT(glm::length(attribute[v] - m.vertices[v]), 1e-12);
}

// Refining chosen edges splits them and keeps the mesh conforming; refinement past the triangle
// limit stops there, conforming, and says so.
TEST(ElementMesh, ChosenEdgesRefineConforminglyAndRefinementStopsAtTheLimit) {
    const std::vector<dvec3> square{dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(1, 1, 0), dvec3(0, 1, 0)};
    const std::vector<uint32_t> indices{0, 1, 2, 0, 2, 3};
    ElementMesh m = refineMesh(square, indices, 0.5, 1000);
    const size_t before = m.triangles.size();
    // An edge on the square's bottom boundary.
    std::pair<uint32_t, uint32_t> bottom{0, 0};
    for (const auto& [edge, count] : edgeUse(m))
        if (count == 1 && m.vertices[edge.first].y == 0 && m.vertices[edge.second].y == 0) bottom = edge;
    ASSERT_NE(bottom.first, bottom.second);
    const size_t added = refineEdges(m, std::vector<std::pair<uint32_t, uint32_t>>{bottom}, 1000);
    EXPECT_GT(added, 0u);
    EXPECT_EQ(m.triangles.size(), before + added);
    EXPECT_EQ(edgeUse(m).count(bottom), 0u);
    EXPECT_EQ(tJunctions(m), 0);
    const ElementMesh capped = refineMesh(square, indices, 0.001, 5000);
    EXPECT_TRUE(capped.truncated);
    EXPECT_LE(capped.triangles.size(), 5000u);
    EXPECT_GT(capped.triangles.size(), 4000u);
    EXPECT_EQ(tJunctions(capped), 0);  // stopped between bisections, still conforming
    EXPECT_FALSE(m.truncated);
}
