#include "scene/shapes.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <utility>

namespace metamer {

namespace {

// Beyond this |cos| between hint and normal the projected "up" is too ill-conditioned to trust.
constexpr double kParallelCos = 0.999;

}  // namespace

int sphereSegmentsFor(const Camera& camera, const glm::dvec3& center, double radius) {
    constexpr int kMost = 512;
    double pixels;  // the sphere's radius on the image, px
    if (camera.projection == Camera::Projection::Orthographic) {
        pixels = radius * camera.height / camera.height_m;
    } else {
        const double distance = glm::length(center - camera.position);
        if (!(distance > radius * 1.0001)) return kMost;
        const double tanHalf = std::tan(0.5 * camera.fov_y_deg * std::numbers::pi / 180.0);
        pixels = radius / std::sqrt(distance * distance - radius * radius) * 0.5 * camera.height / tanHalf;
    }
    const double segments = 2.0 * std::numbers::pi * pixels / 6.0;
    if (!(segments < kMost)) return kMost;
    return std::max(16, 8 * int(std::ceil(segments / 8.0)));
}

bool isClosedOutward(const Mesh& mesh) {
    const size_t triangles = mesh.indices.size() / 3;
    if (triangles < 4 || mesh.positions.empty()) return false;
    // Weld: the same position, the same vertex.
    std::vector<uint32_t> order(mesh.positions.size()), weld(mesh.positions.size());
    std::iota(order.begin(), order.end(), 0u);
    auto less = [&](uint32_t a, uint32_t b) {
        const glm::dvec3 &p = mesh.positions[a], &q = mesh.positions[b];
        return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
    };
    std::sort(order.begin(), order.end(), less);
    for (size_t i = 0; i < order.size(); ++i)
        weld[order[i]] = i > 0 && !less(order[i - 1], order[i]) ? weld[order[i - 1]] : order[i];
    // Every directed edge once, and its reverse once.
    std::vector<std::pair<uint32_t, uint32_t>> edges;
    edges.reserve(3 * triangles);
    double volume = 0.0;
    const glm::dvec3 origin = mesh.positions[mesh.indices[0]];
    for (size_t t = 0; t < triangles; ++t) {
        const uint32_t a = weld[mesh.indices[3 * t]], b = weld[mesh.indices[3 * t + 1]], c = weld[mesh.indices[3 * t + 2]];
        if (a == b || b == c || c == a) return false;  // a degenerate triangle: not a clean surface
        edges.insert(edges.end(), {{a, b}, {b, c}, {c, a}});
        volume += glm::dot(mesh.positions[a] - origin, glm::cross(mesh.positions[b] - origin, mesh.positions[c] - origin));
    }
    std::sort(edges.begin(), edges.end());
    for (size_t i = 0; i < edges.size(); ++i) {
        if (i > 0 && edges[i] == edges[i - 1]) return false;  // an edge used twice the same way
        if (!std::binary_search(edges.begin(), edges.end(), std::make_pair(edges[i].second, edges[i].first))) return false;
    }
    return volume > 0.0;
}

Mesh makeSphere(const glm::dvec3& center, double radius, int segments) {
    const int n = segments;      // meridians
    const int m = segments / 2;  // latitude bands; m - 1 rings of n vertices between the poles
    const double pi = std::numbers::pi;
    Mesh mesh;
    auto add = [&](const glm::dvec3& dir) {
        mesh.positions.push_back(center + radius * dir);
        mesh.normals.push_back(dir);
    };
    add({0, 1, 0});  // north pole: vertex 0
    for (int i = 1; i < m; ++i) {
        double theta = pi * i / m;  // from +y
        for (int j = 0; j < n; ++j) {
            double phi = 2.0 * pi * j / n;
            // phi grows from +z towards +x: counter-clockwise seen from +y.
            add({std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi)});
        }
    }
    add({0, -1, 0});  // south pole: last vertex
    const uint32_t south = static_cast<uint32_t>(mesh.positions.size() - 1);
    auto ring = [&](int i, int j) { return static_cast<uint32_t>(1 + (i - 1) * n + (j % n)); };
    auto tri = [&](uint32_t a, uint32_t b, uint32_t c) {
        mesh.indices.insert(mesh.indices.end(), {a, b, c});
    };
    // Seen from outside, south is down and growing phi is to the right, so
    // (top-left, bottom-left, bottom-right) is counter-clockwise.
    for (int j = 0; j < n; ++j) tri(0, ring(1, j), ring(1, j + 1));
    for (int i = 1; i < m - 1; ++i)
        for (int j = 0; j < n; ++j) {
            uint32_t a = ring(i, j), b = ring(i, j + 1), c = ring(i + 1, j), d = ring(i + 1, j + 1);
            tri(a, c, d);
            tri(a, d, b);
        }
    for (int j = 0; j < n; ++j) tri(ring(m - 1, j), south, ring(m - 1, j + 1));
    mesh.closed = true;  // no seam duplicates, counter-clockwise from outside
    return mesh;
}

std::optional<QuadAxes> quadAxes(const glm::dvec3& normal, const std::optional<glm::dvec3>& upHint) {
    glm::dvec3 n = glm::normalize(normal);
    glm::dvec3 hint;
    if (upHint) {
        hint = glm::normalize(*upHint);
        if (std::fabs(glm::dot(hint, n)) > kParallelCos) return std::nullopt;
    } else {
        // A floor or ceiling has no vertical in its plane; -z is "up" for a camera looking
        // down -z at it, so a floor's height runs away from such a camera.
        hint = std::fabs(n.y) > kParallelCos ? glm::dvec3(0, 0, -1) : glm::dvec3(0, 1, 0);
    }
    QuadAxes a;
    a.normal = n;
    a.up = glm::normalize(hint - glm::dot(hint, n) * n);
    a.right = glm::normalize(glm::cross(a.up, n));
    return a;
}

Mesh makeQuad(const glm::dvec3& center, const glm::dvec3& normal, const glm::dvec2& size,
              const std::optional<glm::dvec3>& upHint) {
    QuadAxes a = *quadAxes(normal, upHint);
    glm::dvec3 r = 0.5 * size.x * a.right, u = 0.5 * size.y * a.up;
    Mesh mesh;
    // right × up = normal, so (-,-), (+,-), (+,+), (-,+) runs counter-clockwise about it.
    mesh.positions = {center - r - u, center + r - u, center + r + u, center - r + u};
    mesh.normals.assign(4, a.normal);
    // The image stands upright on the quad: u runs along "right", v down along −"up"; so the
    // tangent is "right" and cross(normal, right) = up is the bitangent with w = +1.
    mesh.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    mesh.tangents.assign(4, glm::dvec4(a.right, 1.0));
    mesh.indices = {0, 1, 2, 0, 2, 3};
    return mesh;
}

Mesh makeBox(const glm::dvec3& center, const glm::dvec3& size) {
    Mesh mesh;
    const glm::dvec3 h = 0.5 * size;
    for (int axis = 0; axis < 3; ++axis)
        for (double sign : {-1.0, 1.0}) {
            glm::dvec3 n(0.0);
            n[axis] = sign;
            // Two in-plane axes with right × up = n, so corners (-,-), (+,-), (+,+), (-,+) run
            // counter-clockwise about the outward normal.
            glm::dvec3 up(0.0), right(0.0);
            up[(axis + 2) % 3] = 1.0;
            right = glm::cross(up, n);
            const glm::dvec3 c = center + n * h[axis];
            const glm::dvec3 r = right * glm::dot(glm::abs(right), h), u = up * glm::dot(up, h);
            const uint32_t first = uint32_t(mesh.positions.size());
            for (const glm::dvec3& p : {c - r - u, c + r - u, c + r + u, c - r + u}) {
                mesh.positions.push_back(p);
                mesh.normals.push_back(n);
            }
            mesh.indices.insert(mesh.indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
        }
    mesh.closed = isClosedOutward(mesh);
    return mesh;
}

glm::dmat4 objectTransform(const glm::dvec3& translate, const glm::dvec3& rotateDeg,
                           const glm::dvec3& scale) {
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), translate);
    m = glm::rotate(m, glm::radians(rotateDeg.z), glm::dvec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(rotateDeg.y), glm::dvec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(rotateDeg.x), glm::dvec3(1, 0, 0));
    return glm::scale(m, scale);
}

void transformMesh(Mesh& mesh, const glm::dmat4& m) {
    // Normals transform by the inverse transpose of the linear part, up to a positive factor that
    // normalizing removes; dividing the linear part by its largest entry first keeps the
    // determinant from underflowing (a scale of 1e-120) or overflowing, which would make every
    // normal 0/0.
    glm::dmat3 linear(m);
    double big = 0.0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) big = std::max(big, std::fabs(linear[c][r]));
    if (big > 0.0 && std::isfinite(big)) linear /= big;
    glm::dmat3 normalMatrix = glm::transpose(glm::inverse(linear));
    for (auto& p : mesh.positions) p = glm::dvec3(m * glm::dvec4(p, 1.0));
    for (auto& n : mesh.normals) n = glm::normalize(normalMatrix * n);
    // Tangents lie in the surface and move with it; a mirror reverses the bitangent's handedness.
    const double handedness = glm::determinant(linear) < 0.0 ? -1.0 : 1.0;
    for (auto& t : mesh.tangents) {
        glm::dvec3 v = linear * glm::dvec3(t);
        double len = glm::length(v);
        t = glm::dvec4(len > 0.0 ? v / len : glm::dvec3(0.0), t.w * handedness);
    }
    if (glm::determinant(linear) < 0.0)
        for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
}

std::vector<glm::dvec4> tangentsFromUvs(const std::vector<glm::dvec3>& positions, const std::vector<glm::dvec3>& normals,
                                        const std::vector<glm::dvec2>& uvs, const std::vector<uint32_t>& indices) {
    std::vector<glm::dvec3> tSum(positions.size(), glm::dvec3(0.0)), vSum(positions.size(), glm::dvec3(0.0));
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
        glm::dvec3 e1 = positions[b] - positions[a], e2 = positions[c] - positions[a];
        glm::dvec2 d1 = uvs[b] - uvs[a], d2 = uvs[c] - uvs[a];
        double det = d1.x * d2.y - d2.x * d1.y;
        if (!(std::fabs(det) > 0.0)) continue;  // no UV area: no direction of u
        // ∂p/∂u and ∂p/∂v on this triangle, weighted by its area (|e1 × e2|/2) through 1/det.
        glm::dvec3 dpdu = (e1 * d2.y - e2 * d1.y) / det, dpdv = (e2 * d1.x - e1 * d2.x) / det;
        double area = 0.5 * glm::length(glm::cross(e1, e2));
        for (uint32_t i : {a, b, c}) {
            tSum[i] += area * dpdu;
            vSum[i] += area * dpdv;
        }
    }
    std::vector<glm::dvec4> out(positions.size(), glm::dvec4(0.0));
    for (size_t i = 0; i < positions.size(); ++i) {
        const glm::dvec3& n = normals[i];
        glm::dvec3 t = tSum[i] - n * glm::dot(n, tSum[i]);
        double len = glm::length(t);
        if (!(len > 1e-12 * (glm::length(tSum[i]) + 1e-300))) continue;  // none: no normal mapping here
        t /= len;
        // The bitangent cross(n, t)·w points up the image, towards decreasing v.
        double w = glm::dot(glm::cross(n, t), vSum[i]) > 0.0 ? -1.0 : 1.0;
        out[i] = glm::dvec4(t, w);
    }
    return out;
}

std::vector<glm::dvec3> smoothNormals(const std::vector<glm::dvec3>& positions,
                                      const std::vector<uint32_t>& indices) {
    std::vector<glm::dvec3> sum(positions.size(), glm::dvec3(0.0));
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
        // |cross| is twice the area: the weighting comes for free.
        glm::dvec3 face = glm::cross(positions[b] - positions[a], positions[c] - positions[a]);
        sum[a] += face;
        sum[b] += face;
        sum[c] += face;
    }
    for (auto& n : sum) {
        double len = glm::length(n);
        n = len > 0.0 ? n / len : glm::dvec3(0, 0, 1);
    }
    return sum;
}

}  // namespace metamer
