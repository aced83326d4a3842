// The elements radiosity is solved on: a scene mesh's triangles bisected until none has an edge
// longer than asked, conformingly (no T-junctions: an edge split in one triangle is split in every
// triangle sharing it), by Rivara's longest-edge propagation — a triangle is split at the midpoint
// of its longest edge, after the neighbours whose longest edge leads to it, so the triangles keep
// their shape (angles stay above half the smallest input angle). Further refinement where the
// light changes fast uses the same bisection (refineEdges).
//
// Each element vertex remembers the two vertices it is the midpoint of (an input vertex: itself
// twice), so any per-vertex attribute — normals, texture coordinates, tangents — interpolates onto
// the elements as the rasterizer would across the input triangle (interpolate).
// Tests: engine/radiosity/element_mesh_test.cpp (conformity, areas, edge lengths, angles).
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace metamer::radiosity {

struct ElementMesh {
    std::vector<glm::dvec3> vertices;
    std::vector<std::pair<uint32_t, uint32_t>> parents;  // [vertex]: the edge it halves (an input vertex: itself twice)
    std::vector<std::array<uint32_t, 3>> triangles;     // counter-clockwise seen from the front, as the input's
    std::vector<uint32_t> inputTriangle;                 // [triangle]: the input triangle it is part of
    size_t inputVertices = 0;                            // vertices [0, inputVertices) are the input's
    bool truncated = false;  // refinement stopped at the triangle limit: some edges are longer than asked

    double area(size_t t) const;
    glm::dvec3 normal(size_t t) const;  // unit, from the winding
    glm::dvec3 centroid(size_t t) const;
    std::array<glm::dvec3, 3> corners(size_t t) const;
};

// The mesh (positions, 3 indices per triangle, counter-clockwise from the front) bisected until no
// edge is longer than maxEdge (metres), or until a bisection would make more than maxTriangles
// (then `truncated`: the caller says what fits, and refuses).
ElementMesh refineMesh(std::span<const glm::dvec3> positions, std::span<const uint32_t> indices, double maxEdge,
                       size_t maxTriangles);

// Bisects, conformingly, every triangle that has one of `edges` (pairs of vertex indices, either
// order), and what the propagation needs, within maxTriangles (else `truncated`); returns how many
// triangles were added.
size_t refineEdges(ElementMesh& mesh, std::span<const std::pair<uint32_t, uint32_t>> edges, size_t maxTriangles);

// A per-vertex attribute of the input, on every element vertex (midpoints: the mean of the two).
template <typename T>
std::vector<T> interpolate(const ElementMesh& mesh, std::span<const T> input) {
    std::vector<T> out(input.begin(), input.begin() + std::ptrdiff_t(mesh.inputVertices));
    out.reserve(mesh.vertices.size());
    for (size_t v = mesh.inputVertices; v < mesh.vertices.size(); ++v)
        out.push_back((out[mesh.parents[v].first] + out[mesh.parents[v].second]) * 0.5);
    return out;
}

}  // namespace metamer::radiosity
