#include "radiosity/element_mesh.h"

#include "core/error.h"

#include <algorithm>
#include <deque>
#include <unordered_map>

namespace metamer::radiosity {

double ElementMesh::area(size_t t) const {
    const auto c = corners(t);
    return 0.5 * glm::length(glm::cross(c[1] - c[0], c[2] - c[0]));
}

glm::dvec3 ElementMesh::normal(size_t t) const {
    const auto c = corners(t);
    return glm::normalize(glm::cross(c[1] - c[0], c[2] - c[0]));
}

glm::dvec3 ElementMesh::centroid(size_t t) const {
    const auto c = corners(t);
    return (c[0] + c[1] + c[2]) / 3.0;
}

std::array<glm::dvec3, 3> ElementMesh::corners(size_t t) const {
    const auto& i = triangles[t];
    return {vertices[i[0]], vertices[i[1]], vertices[i[2]]};
}

namespace {

uint64_t edgeKey(uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); }

// The mesh with the triangles around each edge, bisecting along longest-edge propagation paths.
class Refiner {
public:
    Refiner(ElementMesh& mesh, size_t maxTriangles) : m_(mesh), maxTriangles_(maxTriangles) {
        for (uint32_t t = 0; t < m_.triangles.size(); ++t) link(t);
    }

    // Bisects until triangle t is split (its slot then holds its first half).
    void split(uint32_t t) {
        const std::array<uint32_t, 3> before = m_.triangles[t];
        while (m_.triangles[t] == before && !m_.truncated) {
            // Follow the longest edges from t until an edge that is the longest of every triangle
            // around it (or a boundary edge): splitting it keeps the triangles' shapes. The path
            // is finite (edges grow along it); the bound only guards against a broken mesh.
            uint32_t at = t;
            for (size_t step = 0;; ++step) {
                const auto [a, b] = longestEdge(at);
                uint32_t next = at;
                for (uint32_t o : around(a, b))
                    if (o != at && edgeKey(longestEdge(o).first, longestEdge(o).second) != edgeKey(a, b)) next = o;
                if (next == at || step > m_.triangles.size()) {
                    bisect(a, b);
                    break;
                }
                at = next;
            }
        }
    }

    std::pair<uint32_t, uint32_t> longestEdge(uint32_t t) const {
        const auto& v = m_.triangles[t];
        std::pair<uint32_t, uint32_t> best{v[0], v[1]};
        for (int k = 1; k < 3; ++k) {
            const std::pair<uint32_t, uint32_t> e{v[size_t(k)], v[size_t((k + 1) % 3)]};
            if (longer(e, best)) best = e;
        }
        return best;
    }

    double length2(uint32_t a, uint32_t b) const {
        const glm::dvec3 d = m_.vertices[a] - m_.vertices[b];
        return glm::dot(d, d);
    }

    size_t added() const { return added_; }

    const std::vector<uint32_t>& around(uint32_t a, uint32_t b) const {
        static const std::vector<uint32_t> none;
        const auto found = edges_.find(edgeKey(a, b));
        return found == edges_.end() ? none : found->second;
    }

private:
    // A strict order of edges, so that two triangles agree which of them is longer: by length,
    // then by their vertices.
    bool longer(const std::pair<uint32_t, uint32_t>& x, const std::pair<uint32_t, uint32_t>& y) const {
        const double lx = length2(x.first, x.second), ly = length2(y.first, y.second);
        if (lx != ly) return lx > ly;
        return edgeKey(x.first, x.second) > edgeKey(y.first, y.second);
    }

    void link(uint32_t t) {
        const auto& v = m_.triangles[t];
        for (int k = 0; k < 3; ++k) edges_[edgeKey(v[size_t(k)], v[size_t((k + 1) % 3)])].push_back(t);
    }

    void unlink(uint32_t t) {
        const auto& v = m_.triangles[t];
        for (int k = 0; k < 3; ++k) {
            auto& list = edges_[edgeKey(v[size_t(k)], v[size_t((k + 1) % 3)])];
            list.erase(std::remove(list.begin(), list.end(), t), list.end());
        }
    }

    // Splits edge (a, b) at its midpoint in every triangle around it, each into two with its winding.
    void bisect(uint32_t a, uint32_t b) {
        const std::vector<uint32_t> triangles = around(a, b);
        if (m_.triangles.size() + triangles.size() > maxTriangles_) {
            m_.truncated = true;
            return;
        }
        const uint32_t mid = uint32_t(m_.vertices.size());
        m_.vertices.push_back(0.5 * (m_.vertices[a] + m_.vertices[b]));
        m_.parents.push_back({a, b});
        for (uint32_t t : triangles) {
            unlink(t);
            // Rotate the triangle so that the split edge is its first, in its own winding.
            std::array<uint32_t, 3> v = m_.triangles[t];
            while (!((v[0] == a && v[1] == b) || (v[0] == b && v[1] == a))) std::rotate(v.begin(), v.begin() + 1, v.end());
            const std::array<std::array<uint32_t, 3>, 2> halves{{{v[0], mid, v[2]}, {mid, v[1], v[2]}}};
            for (int h = 0; h < 2; ++h) {
                const uint32_t id = uint32_t(m_.triangles.size());
                if (h == 0) {
                    // The first half takes t's slot, so that indices stay dense.
                    m_.triangles[t] = halves[0];
                    link(t);
                    continue;
                }
                m_.triangles.push_back(halves[1]);
                m_.inputTriangle.push_back(m_.inputTriangle[t]);
                link(id);
                ++added_;
            }
        }
    }

    ElementMesh& m_;
    size_t maxTriangles_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> edges_;
    size_t added_ = 0;
};

}  // namespace

ElementMesh refineMesh(std::span<const glm::dvec3> positions, std::span<const uint32_t> indices, double maxEdge,
                       size_t maxTriangles) {
    if (indices.size() % 3 != 0) failRuntime("radiosity: {} indices are not whole triangles", indices.size());
    if (!(maxEdge > 0.0)) failRuntime("radiosity: element size {} must be positive", maxEdge);
    ElementMesh mesh;
    mesh.vertices.assign(positions.begin(), positions.end());
    mesh.inputVertices = positions.size();
    for (uint32_t v = 0; v < positions.size(); ++v) mesh.parents.push_back({v, v});
    for (size_t t = 0; t < indices.size(); t += 3) {
        for (size_t k = 0; k < 3; ++k)
            if (indices[t + k] >= positions.size())
                failRuntime("radiosity: index {} past the {} positions", indices[t + k], positions.size());
        mesh.triangles.push_back({indices[t], indices[t + 1], indices[t + 2]});
        mesh.inputTriangle.push_back(uint32_t(t / 3));
    }
    Refiner refiner(mesh, maxTriangles);
    const double limit2 = maxEdge * maxEdge;
    // Bisection only shortens edges and keeps a triangle's slot for its first half: sweep the
    // triangles (new ones are appended) until every one is short enough.
    for (size_t t = 0; t < mesh.triangles.size() && !mesh.truncated; ++t)
        while (!mesh.truncated) {
            const auto [a, b] = refiner.longestEdge(uint32_t(t));
            if (refiner.length2(a, b) <= limit2) break;
            refiner.split(uint32_t(t));
        }
    return mesh;
}

size_t refineEdges(ElementMesh& mesh, std::span<const std::pair<uint32_t, uint32_t>> edges, size_t maxTriangles) {
    Refiner refiner(mesh, maxTriangles);
    for (const auto& [a, b] : edges) {
        // Every triangle still having the edge is split (at its own longest edge first, which
        // splits the edge itself or shortens the triangle towards it).
        while (!refiner.around(a, b).empty() && !mesh.truncated) refiner.split(refiner.around(a, b).front());
    }
    return refiner.added();
}

}  // namespace metamer::radiosity
