#include "scene/shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

using namespace metamer;

namespace {

glm::dvec3 faceNormal(const Mesh& m, size_t t) {
    const auto& p = m.positions;
    const auto* i = &m.indices[3 * t];
    return glm::cross(p[i[1]] - p[i[0]], p[i[2]] - p[i[0]]);
}

// Every triangle's winding (right-hand rule) agrees with its vertex normals.
void expectWindingFollowsNormals(const Mesh& m) {
    for (size_t t = 0; t < m.indices.size() / 3; ++t) {
        glm::dvec3 avg = m.normals[m.indices[3 * t]] + m.normals[m.indices[3 * t + 1]] + m.normals[m.indices[3 * t + 2]];
        EXPECT_GT(glm::dot(faceNormal(m, t), avg), 0.0) << "triangle " << t;
    }
}

// Signed volume by the divergence theorem; positive when the mesh is closed and wound CCW seen
// from outside.
double enclosedVolume(const Mesh& m) {
    double v = 0.0;
    for (size_t t = 0; t < m.indices.size() / 3; ++t) {
        const auto* i = &m.indices[3 * t];
        v += glm::dot(m.positions[i[0]], glm::cross(m.positions[i[1]], m.positions[i[2]])) / 6.0;
    }
    return v;
}

double area(const Mesh& m) {
    double a = 0.0;
    for (size_t t = 0; t < m.indices.size() / 3; ++t) a += 0.5 * glm::length(faceNormal(m, t));
    return a;
}

}  // namespace

TEST(Sphere, VerticesOnTheSphereWithRadialUnitNormals) {
    glm::dvec3 c(1, 2, 3);
    double r = 0.7;
    Mesh m = makeSphere(c, r, 32);
    EXPECT_EQ(m.positions.size(), 2u + 15u * 32u);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (size_t i = 0; i < m.positions.size(); ++i) {
        EXPECT_NEAR(glm::distance(m.positions[i], c), r, 1e-12);
        EXPECT_NEAR(glm::length(m.normals[i]), 1.0, 1e-12);
        EXPECT_NEAR(glm::distance(m.normals[i], (m.positions[i] - c) / r), 0.0, 1e-12);
    }
}

TEST(Sphere, TriangleCountAndOutwardWinding) {
    glm::dvec3 c(1, 2, 3);
    Mesh m = makeSphere(c, 0.7, 32);
    ASSERT_EQ(m.indices.size() / 3, size_t(2 * 32 * 15));
    for (uint32_t i : m.indices) ASSERT_LT(i, m.positions.size());
    expectWindingFollowsNormals(m);
    for (size_t t = 0; t < m.indices.size() / 3; ++t) {
        glm::dvec3 centroid = (m.positions[m.indices[3 * t]] + m.positions[m.indices[3 * t + 1]] +
                               m.positions[m.indices[3 * t + 2]]) / 3.0;
        EXPECT_GT(glm::dot(faceNormal(m, t), centroid - c), 0.0);
    }
}

TEST(Sphere, ClosedWithConsistentOrientation) {
    // Each directed edge appears once and its reverse once: no holes, no flipped triangles.
    Mesh m = makeSphere({0, 0, 0}, 1.0, 12);
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (size_t t = 0; t < m.indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) ++edges[{m.indices[t + k], m.indices[t + (k + 1) % 3]}];
    for (const auto& [e, n] : edges) {
        EXPECT_EQ(n, 1);
        EXPECT_EQ(edges.count({e.second, e.first}), 1u);
    }
}

TEST(Sphere, VolumeApproachesTheBall) {
    double r = 1.3;
    Mesh m = makeSphere({0.5, -1, 2}, r, 128);
    double ball = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    double v = enclosedVolume(m);
    EXPECT_LT(v, ball);  // inscribed
    EXPECT_NEAR(v / ball, 1.0, 2e-3);
}

TEST(Sphere, MinimumSegments) {
    Mesh m = makeSphere({0, 0, 0}, 1.0, kMinSphereSegments);
    EXPECT_EQ(m.indices.size() / 3, 8u);  // an octahedron
    EXPECT_GT(enclosedVolume(m), 0.0);
}

TEST(Quad, AreaNormalAndWinding) {
    glm::dvec3 n = glm::normalize(glm::dvec3(1, 2, 3));
    Mesh m = makeQuad({1, 1, 1}, 5.0 * n, {3, 2});
    ASSERT_EQ(m.indices.size(), 6u);
    EXPECT_NEAR(area(m), 6.0, 1e-12);
    for (const auto& v : m.normals) EXPECT_NEAR(glm::distance(v, n), 0.0, 1e-12);
    for (size_t t = 0; t < 2; ++t) EXPECT_NEAR(glm::distance(glm::normalize(faceNormal(m, t)), n), 0.0, 1e-12);
    for (const auto& p : m.positions) EXPECT_NEAR(glm::dot(p - glm::dvec3(1, 1, 1), n), 0.0, 1e-12);
}

TEST(Quad, DefaultAxes) {
    // A wall facing +z: width along +x, height along +y.
    Mesh wall = makeQuad({0, 0, 0}, {0, 0, 1}, {4, 2});
    EXPECT_EQ(wall.positions[0], glm::dvec3(-2, -1, 0));
    EXPECT_EQ(wall.positions[2], glm::dvec3(2, 1, 0));
    // A floor facing +y: "up" is -z, so width along +x and height along z.
    Mesh floor = makeQuad({0, 0, 0}, {0, 1, 0}, {4, 2});
    EXPECT_NEAR(glm::distance(floor.positions[0], glm::dvec3(-2, 0, 1)), 0.0, 1e-12);
    EXPECT_NEAR(glm::distance(floor.positions[2], glm::dvec3(2, 0, -1)), 0.0, 1e-12);
}

TEST(Quad, UpHint) {
    // Hint +x on a wall facing +z: height along x, width along up × normal = x × z = -y.
    Mesh m = makeQuad({0, 0, 0}, {0, 0, 1}, {4, 2}, glm::dvec3(1, 0, 0.5));
    EXPECT_NEAR(glm::distance(m.positions[0], glm::dvec3(-1, 2, 0)), 0.0, 1e-12);
    EXPECT_NEAR(glm::distance(m.positions[2], glm::dvec3(1, -2, 0)), 0.0, 1e-12);
    EXPECT_FALSE(quadAxes({0, 0, 1}, glm::dvec3(0, 0.01, -1)));
    EXPECT_TRUE(quadAxes({0, 0, 1}, glm::dvec3(0, 0.1, -1)));
}

TEST(ObjectTransform, ScaleThenRotateXYZThenTranslate) {
    glm::dmat4 m = objectTransform({0, 0, 1}, {0, 0, 90}, {2, 1, 1});
    glm::dvec3 p(m * glm::dvec4(1, 0, 0, 1));
    EXPECT_NEAR(glm::distance(p, glm::dvec3(0, 2, 1)), 0.0, 1e-12);
    // x first, then y: (0,1,0) -Rx90-> (0,0,1) -Ry90-> (1,0,0).
    glm::dmat4 r = objectTransform({0, 0, 0}, {90, 90, 0}, {1, 1, 1});
    glm::dvec3 q(r * glm::dvec4(0, 1, 0, 1));
    EXPECT_NEAR(glm::distance(q, glm::dvec3(1, 0, 0)), 0.0, 1e-12);
}

TEST(TransformMesh, NormalsUseTheInverseTransposeAndMirrorsKeepWinding) {
    // A tilted quad under non-uniform scale: the transformed normal must stay perpendicular.
    Mesh m = makeQuad({0, 0, 0}, {1, 1, 0}, {1, 1});
    transformMesh(m, objectTransform({0, 0, 0}, {0, 0, 0}, {3, 1, 1}));
    glm::dvec3 geometric = glm::normalize(faceNormal(m, 0));
    EXPECT_NEAR(glm::distance(m.normals[0], geometric), 0.0, 1e-12);
    // Mirror in x: winding is reversed so it still follows the (mirrored) normals.
    Mesh s = makeSphere({0, 0, 0}, 1.0, 8);
    transformMesh(s, glm::dmat4(glm::dvec4(-1, 0, 0, 0), glm::dvec4(0, 1, 0, 0), glm::dvec4(0, 0, 1, 0),
                                glm::dvec4(0, 0, 0, 1)));
    expectWindingFollowsNormals(s);
    EXPECT_GT(enclosedVolume(s), 0.0);
}

TEST(SmoothNormals, AreaWeighted) {
    // Two triangles sharing the edge (0,1): one in the xy plane with area 1, one in the xz
    // plane with area 2 (facing -y). The shared vertices' normal leans 2:1 towards the larger.
    std::vector<glm::dvec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, -4}};
    std::vector<uint32_t> idx = {0, 1, 2, 0, 3, 1};
    auto n = smoothNormals(p, idx);
    glm::dvec3 a(0, 0, 1), b(0, -1, 0);  // faces' unit normals
    EXPECT_NEAR(glm::distance(n[0], glm::normalize(1.0 * a + 2.0 * b)), 0.0, 1e-12);
    EXPECT_NEAR(glm::distance(n[2], a), 0.0, 1e-12);
    EXPECT_NEAR(glm::distance(n[3], b), 0.0, 1e-12);
}

TEST(ClosedMeshes, SpheresAreQuadsAreNotAndFlawsAreFound) {
    Mesh sphere = makeSphere({1, 2, 3}, 0.5, 24);
    EXPECT_TRUE(sphere.closed);
    EXPECT_TRUE(isClosedOutward(sphere));
    EXPECT_FALSE(isClosedOutward(makeQuad({0, 0, 0}, {0, 0, 1}, {1, 1})));
    // Inside out (every triangle reversed): closed, but its back faces are what is seen from outside.
    Mesh inverted = sphere;
    for (size_t t = 0; t + 2 < inverted.indices.size(); t += 3) std::swap(inverted.indices[t + 1], inverted.indices[t + 2]);
    EXPECT_FALSE(isClosedOutward(inverted));
    // One triangle flipped: its edges run the same way as their neighbours'.
    Mesh flipped = sphere;
    std::swap(flipped.indices[31], flipped.indices[32]);
    EXPECT_FALSE(isClosedOutward(flipped));
    // A hole.
    Mesh holed = sphere;
    holed.indices.resize(holed.indices.size() - 3);
    EXPECT_FALSE(isClosedOutward(holed));
    // A seam of duplicated vertices (as glTF files have, for their UVs) is welded by position.
    Mesh seamed = sphere;
    for (uint32_t& i : seamed.indices)
        if (i % 5 == 0) {
            seamed.positions.push_back(seamed.positions[i]);
            seamed.normals.push_back(seamed.normals[i]);
            i = uint32_t(seamed.positions.size() - 1);
        }
    EXPECT_TRUE(isClosedOutward(seamed));
}

TEST(SphereSegments, EdgesOfAboutSixPixelsAlongTheSilhouette) {
    // A sphere of radius 0.05 m, 10 m away, under a 40° field of view on a 1000-pixel-high image:
    // its image radius is 0.05/√(100 − 0.0025) · 500/tan 20° ≈ 6.87 px; 2π·6.87/6 = 7.2 → at least 16.
    Camera camera;
    camera.position = {0, 0, 10};
    camera.fov_y_deg = 40;
    camera.height = 1000;
    EXPECT_EQ(sphereSegmentsFor(camera, {0, 0, 0}, 0.05), 16);
    // Ten times bigger: 68.8 px, 72.02 segments → the next multiple of 8, 80.
    EXPECT_EQ(sphereSegmentsFor(camera, {0, 0, 0}, 0.5), 80);
    // Around the camera, or filling the view: the most.
    EXPECT_EQ(sphereSegmentsFor(camera, {0, 0, 10}, 1.0), 512);
    EXPECT_EQ(sphereSegmentsFor(camera, {0, 0, 0}, 9.99), 512);
    // Orthographic: the radius in pixels is r·height/height_m (0.5·1000/4 = 125 px → 131 → 136).
    camera.projection = Camera::Projection::Orthographic;
    camera.height_m = 4.0;
    EXPECT_EQ(sphereSegmentsFor(camera, {0, 0, 0}, 0.5), 136);
}
