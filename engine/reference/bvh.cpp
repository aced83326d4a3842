#include "reference/bvh.h"

#include <algorithm>
#include <cmath>

namespace metamer {

namespace {

glm::dvec3 centroid(const BvhTriangle& t) { return (t.p0 + t.p1 + t.p2) / 3.0; }

// The slab test. Bounds are padded at build time, so the rounding of the products here cannot
// reject a ray that grazes a triangle lying on the box's face. The ray's reciprocal direction is
// taken once per ray (Slabs), not once per box.
struct Slabs {
    glm::dvec3 origin, inv;
    bool parallel[3];  // |d| < 1e-200: 1/d would be inf, with 0·inf = NaN on the face
    explicit Slabs(const Ray& ray) : origin(ray.origin), inv(0.0) {
        for (int a = 0; a < 3; ++a) {
            parallel[a] = std::fabs(ray.direction[a]) < 1e-200;
            if (!parallel[a]) inv[a] = 1.0 / ray.direction[a];
        }
    }
};

bool hitsBox(const glm::dvec3& lo, const glm::dvec3& hi, const Slabs& ray, double tMin, double tMax, double& tEnter) {
    double t0 = tMin, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        const double o = ray.origin[a];
        if (ray.parallel[a]) {
            if (o < lo[a] || o > hi[a]) return false;
            continue;
        }
        double n = (lo[a] - o) * ray.inv[a], f = (hi[a] - o) * ray.inv[a];
        if (n > f) std::swap(n, f);
        t0 = std::max(t0, n);
        t1 = std::min(t1, f);
        if (t0 > t1) return false;
    }
    tEnter = t0;
    return true;
}

// A traversal's stack: on the call's own stack up to 64 entries (a BVH 31 deep), else the heap;
// shadow rays are most of the rays interreflection casts, millions a scene.
template <typename Entry>
class TraversalStack {
public:
    explicit TraversalStack(int depth) {
        const size_t need = 2 * static_cast<size_t>(depth) + 2;
        if (need > kInline) {
            heap_.resize(need);
            data_ = heap_.data();
        }
    }
    void push(const Entry& e) { data_[size_++] = e; }
    Entry pop() { return data_[--size_]; }
    bool empty() const { return size_ == 0; }

private:
    static constexpr size_t kInline = 64;
    Entry inline_[kInline];
    std::vector<Entry> heap_;
    Entry* data_ = inline_;
    size_t size_ = 0;
};

}  // namespace

std::optional<RayHit> intersectTriangle(const BvhTriangle& tri, const Ray& ray, double tMin,
                                        double tMax) {
    const glm::dvec3 e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0;
    const glm::dvec3 pvec = glm::cross(ray.direction, e2);
    const double det = glm::dot(e1, pvec);
    // det = 0: the ray is parallel to the plane, or the triangle is degenerate.
    if (det == 0.0 || !std::isfinite(det)) return std::nullopt;
    const double inv = 1.0 / det;
    const glm::dvec3 tvec = ray.origin - tri.p0;
    const double u = glm::dot(tvec, pvec) * inv;
    if (u < -kEdgeSlack || u > 1.0 + kEdgeSlack) return std::nullopt;
    const glm::dvec3 qvec = glm::cross(tvec, e1);
    const double v = glm::dot(ray.direction, qvec) * inv;
    if (v < -kEdgeSlack || u + v > 1.0 + kEdgeSlack) return std::nullopt;
    const double t = glm::dot(e2, qvec) * inv;
    if (!(t > tMin && t < tMax)) return std::nullopt;
    return RayHit{t, u, v, 0};
}

std::vector<BvhTriangle> Bvh::collectTriangles(const Scene& scene, const LocalFrame& frame,
                                               const std::function<bool(const Mesh&)>& keep) {
    std::vector<BvhTriangle> out;
    out.reserve(keep ? 0 : scene.triangleCount());
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        if (keep && !keep(mesh)) continue;
        for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
            BvhTriangle t;
            t.p0 = frame.position(mesh.positions.at(mesh.indices[i]));
            t.p1 = frame.position(mesh.positions.at(mesh.indices[i + 1]));
            t.p2 = frame.position(mesh.positions.at(mesh.indices[i + 2]));
            t.mesh = static_cast<uint32_t>(m);
            t.triangle = static_cast<uint32_t>(i / 3);
            out.push_back(t);
        }
    }
    return out;
}

Bvh::Bvh(std::vector<BvhTriangle> triangles) : triangles_(std::move(triangles)) {
    if (triangles_.empty()) return;
    nodes_.reserve(2 * triangles_.size() / kLeafSize + 1);
    build(0, static_cast<uint32_t>(triangles_.size()), 1);
}

uint32_t Bvh::build(uint32_t begin, uint32_t end, int depth) {
    depth_ = std::max(depth_, depth);
    const uint32_t self = static_cast<uint32_t>(nodes_.size());
    nodes_.push_back({});

    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    glm::dvec3 clo = lo, chi = hi;  // bounds of the centroids, to choose the split axis
    for (uint32_t i = begin; i < end; ++i) {
        const BvhTriangle& t = triangles_[i];
        for (const glm::dvec3& p : {t.p0, t.p1, t.p2}) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        glm::dvec3 c = centroid(t);
        clo = glm::min(clo, c);
        chi = glm::max(chi, c);
    }
    // Pad by far more than the rounding of the slab test and the edge slack of the triangle test,
    // relative to the coordinates' magnitude: a padded box can only cost time, never a hit.
    const double mag = std::max({glm::length(lo), glm::length(hi), glm::length(hi - lo), 1e-30});
    const glm::dvec3 pad(1e-9 * mag);
    nodes_[self].lo = lo - pad;
    nodes_[self].hi = hi + pad;

    const uint32_t count = end - begin;
    if (count <= static_cast<uint32_t>(kLeafSize)) {
        nodes_[self].first = begin;
        nodes_[self].count = count;
        return self;
    }
    // Median split on the axis along which the centroids spread the most.
    const glm::dvec3 extent = chi - clo;
    int axis = 0;
    if (extent.y > extent[axis]) axis = 1;
    if (extent.z > extent[axis]) axis = 2;
    const uint32_t mid = begin + count / 2;
    std::nth_element(triangles_.begin() + begin, triangles_.begin() + mid, triangles_.begin() + end,
                     [axis](const BvhTriangle& a, const BvhTriangle& b) {
                         return centroid(a)[axis] < centroid(b)[axis];
                     });
    build(begin, mid, depth + 1);  // first child: self + 1
    const uint32_t second = build(mid, end, depth + 1);
    nodes_[self].first = second;
    nodes_[self].count = 0;
    return self;
}

std::optional<RayHit> Bvh::intersect(const Ray& ray, double tMin, double tMax) const {
    if (nodes_.empty()) return std::nullopt;
    std::optional<RayHit> best;
    double tBest = tMax;
    double tEnter = 0.0;
    const Slabs slabs(ray);
    if (!hitsBox(nodes_[0].lo, nodes_[0].hi, slabs, tMin, tBest, tEnter)) return std::nullopt;

    // Depth-first, nearer child first; a node is skipped once its box starts beyond the best hit.
    struct Entry {
        uint32_t node;
        double tEnter;
    };
    TraversalStack<Entry> stack(depth_);
    stack.push({0, tEnter});
    while (!stack.empty()) {
        const Entry e = stack.pop();
        if (e.tEnter > tBest) continue;
        const Node& node = nodes_[e.node];
        if (node.count > 0) {
            for (uint32_t i = node.first; i < node.first + node.count; ++i) {
                if (auto h = intersectTriangle(triangles_[i], ray, tMin, tBest)) {
                    h->index = i;
                    tBest = h->t;
                    best = h;
                }
            }
            continue;
        }
        const uint32_t a = e.node + 1, b = node.first;
        double ta = 0.0, tb = 0.0;
        const bool hitA = hitsBox(nodes_[a].lo, nodes_[a].hi, slabs, tMin, tBest, ta);
        const bool hitB = hitsBox(nodes_[b].lo, nodes_[b].hi, slabs, tMin, tBest, tb);
        if (hitA && hitB) {
            if (ta <= tb) {
                stack.push({b, tb});
                stack.push({a, ta});
            } else {
                stack.push({a, ta});
                stack.push({b, tb});
            }
        } else if (hitA) {
            stack.push({a, ta});
        } else if (hitB) {
            stack.push({b, tb});
        }
    }
    return best;
}

template <typename Visit>
bool Bvh::visitLeaves(const Ray& ray, double tMin, double tMax, Visit&& visit) const {
    if (nodes_.empty()) return false;
    double tEnter = 0.0;
    const Slabs slabs(ray);
    if (!hitsBox(nodes_[0].lo, nodes_[0].hi, slabs, tMin, tMax, tEnter)) return false;
    TraversalStack<uint32_t> stack(depth_);
    stack.push(0);
    while (!stack.empty()) {
        const uint32_t self = stack.pop();
        const Node& node = nodes_[self];
        if (node.count > 0) {
            for (uint32_t i = node.first; i < node.first + node.count; ++i)
                if (visit(i)) return true;
            continue;
        }
        for (uint32_t child : {self + 1, node.first})
            if (hitsBox(nodes_[child].lo, nodes_[child].hi, slabs, tMin, tMax, tEnter)) stack.push(child);
    }
    return false;
}

bool Bvh::occluded(const Ray& ray, double tMin, double tMax, uint32_t skip) const {
    return visitLeaves(ray, tMin, tMax, [&](uint32_t i) {
        return i != skip && intersectTriangle(triangles_[i], ray, tMin, tMax).has_value();
    });
}

std::vector<RayHit> Bvh::allHits(const Ray& ray, double tMin, double tMax) const {
    std::vector<RayHit> hits;
    visitLeaves(ray, tMin, tMax, [&](uint32_t i) {
        if (auto h = intersectTriangle(triangles_[i], ray, tMin, tMax)) {
            h->index = i;
            hits.push_back(*h);
        }
        return false;
    });
    return hits;
}

}  // namespace metamer
