// A bounding-volume hierarchy over world-space triangles, in double precision, for the CPU
// reference renderer. Built once per render by median splits; traversed front to back for the
// nearest hit. Simplicity over speed: it is the golden the GPU is checked against.
#pragma once

#include "scene/local_frame.h"
#include "scene/scene.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

namespace metamer {

struct BvhTriangle {
    glm::dvec3 p0, p1, p2;
    uint32_t mesh = 0;      // index into Scene::meshes
    uint32_t triangle = 0;  // index of the triangle within its mesh (indices[3*triangle ...])
};

struct Ray {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0};  // unit length: t is then metres
};

struct RayHit {
    double t = 0.0;          // ray parameter of the hit
    double b1 = 0.0, b2 = 0.0;  // barycentrics of p1 and p2 (b0 = 1 - b1 - b2)
    uint32_t index = 0;      // into Bvh::triangles()
};

// Möller–Trumbore in double. Accepts t in (tMin, tMax). Barycentrics may lie a hair outside
// [0, 1] (kEdgeSlack): the two triangles of a shared edge compute its barycentric from different
// products, so without slack rounding can make a ray through the edge miss both. The cost is a
// triangle grown by 1e-10 of its size, far below what any image resolves.
inline constexpr double kEdgeSlack = 1e-10;
std::optional<RayHit> intersectTriangle(const BvhTriangle& tri, const Ray& ray, double tMin,
                                        double tMax);

class Bvh {
public:
    // Every triangle of every mesh (of those `keep` accepts, when given), its corners in `frame`
    // (scene/local_frame.h); meshes keep their index so hits can name them.
    static std::vector<BvhTriangle> collectTriangles(const Scene& scene, const LocalFrame& frame = {},
                                                     const std::function<bool(const Mesh&)>& keep = {});

    explicit Bvh(std::vector<BvhTriangle> triangles);

    // The nearest hit with t in (tMin, tMax), or none.
    std::optional<RayHit> intersect(const Ray& ray, double tMin = 1e-9,
                                    double tMax = std::numeric_limits<double>::infinity()) const;

    // Whether any triangle but `skip` (an index into triangles(), the one a shadow ray leaves) is
    // hit with t in (tMin, tMax): the shadow ray's question, answered at the first hit found.
    bool occluded(const Ray& ray, double tMin, double tMax, uint32_t skip) const;

    // Every hit with t in (tMin, tMax), in no particular order (the transparent surfaces a ray
    // crosses before the opaque one it ends on).
    std::vector<RayHit> allHits(const Ray& ray, double tMin, double tMax) const;

    const std::vector<BvhTriangle>& triangles() const { return triangles_; }
    size_t nodeCount() const { return nodes_.size(); }
    int depth() const { return depth_; }

    static constexpr int kLeafSize = 4;

private:
    struct Node {
        glm::dvec3 lo, hi;  // bounds, padded outward (see bvh.cpp)
        uint32_t first = 0;  // leaf: first triangle; inner: index of the second child
        uint32_t count = 0;  // leaf: triangle count; inner: 0 (first child is this node + 1)
    };

    uint32_t build(uint32_t begin, uint32_t end, int depth);
    // Calls visit(i) for each triangle of every leaf whose box the ray enters within (tMin, tMax),
    // depth first, until one returns true (then true); occluded's and allHits' walk.
    template <typename Visit>
    bool visitLeaves(const Ray& ray, double tMin, double tMax, Visit&& visit) const;

    std::vector<BvhTriangle> triangles_;
    std::vector<Node> nodes_;
    int depth_ = 0;
};

}  // namespace metamer
