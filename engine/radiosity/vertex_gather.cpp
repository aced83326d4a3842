#include "radiosity/vertex_gather.h"

#include "core/cpu_count.h"
#include "radiosity/form_factor.h"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <thread>

namespace metamer::radiosity {

Eigen::MatrixXd gatherFactors(std::span<const GatherPoint> points, std::span<const std::array<glm::dvec3, 3>> elements,
                              const Bvh* occluders, int side) {
    const size_t m = points.size(), n = elements.size();
    Eigen::MatrixXd W = Eigen::MatrixXd::Zero(Eigen::Index(m), Eigen::Index(n));
    std::vector<glm::dvec3> front(n), centroid(n);
    std::vector<double> area(n), farFrom(n);
    std::vector<std::array<glm::dvec3, 7>> rule(n);
    for (size_t j = 0; j < n; ++j) {
        const auto& c = elements[j];
        front[j] = polygonNormal(c);
        area[j] = polygonArea(c);
        centroid[j] = (c[0] + c[1] + c[2]) / 3.0;
        farFrom[j] = kRuleFarRatio * longestEdge(c);
        for (size_t q = 0; q < kTriangleRule.size(); ++q) rule[j][q] = kTriangleRule[q].on(c);
    }
    // Where each element is seen at (barycentric): its centroid, or stratified points — a side ×
    // side grid of cell centres on the unit square mapped by (s, t) → (1 − √s, √s(1 − t), √s·t),
    // which keeps equal areas.
    std::vector<glm::dvec3> weights;
    for (int a = 0; a < side; ++a)
        for (int b = 0; b < side; ++b) {
            const double u = std::sqrt((a + 0.5) / side), t = (b + 0.5) / side;
            weights.push_back({1.0 - u, u * (1.0 - t), u * t});
        }
    const size_t per = side == 0 ? 1 : weights.size();
    std::vector<glm::dvec3> targets(n * per);  // [element][point]
    for (size_t j = 0; j < n; ++j) {
        const auto& c = elements[j];
        if (side == 0) targets[j] = centroid[j];
        for (size_t k = 0; k < weights.size(); ++k)
            targets[j * per + k] = weights[k].x * c[0] + weights[k].y * c[1] + weights[k].z * c[2];
    }
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t p; (p = next.fetch_add(1)) < m;) {
            const GatherPoint& g = points[p];
            // A hair inside its own surface: far below any element, far above rounding.
            const glm::dvec3 x = g.position + 1e-7 * g.inside;
            for (size_t j = 0; j < n; ++j) {
                const auto& c = elements[j];
                // Far, wholly above x's plane and facing x: the rule; else the closed form.
                const glm::dvec3 d = centroid[j] - x;
                const bool far = glm::dot(d, d) >= farFrom[j] * farFrom[j] && glm::dot(front[j], x - c[0]) > 0.0 &&
                                 glm::dot(g.normal, c[0] - x) > 0.0 && glm::dot(g.normal, c[1] - x) > 0.0 &&
                                 glm::dot(g.normal, c[2] - x) > 0.0;
                const double f = far ? pointToTriangleByRule(x, g.normal, rule[j], front[j], area[j])
                                     : pointToTriangle(x, g.normal, c, front[j]);
                if (f == 0.0) continue;
                size_t seen = per;
                if (occluders)
                    for (size_t k = 0; k < per; ++k) {
                        const glm::dvec3 d = targets[j * per + k] - x;
                        const double length = glm::length(d);
                        seen -= length > 0.0 && occluders->occluded(Ray{x, d / length}, 1e-9 * length, length * (1.0 - 1e-9), g.source);
                    }
                W(Eigen::Index(p), Eigen::Index(j)) = f * double(seen) / double(per);
            }
        }
    };
    std::vector<std::thread> pool;
    const int threads = std::max(1, std::min<int>(usableCpuCount(), int(m / 16) + 1));
    for (int t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    return W;
}

std::vector<char> buriedPoints(std::span<const GatherPoint> points, const Bvh& occluders, const std::vector<char>& closed) {
    std::vector<char> buried(points.size(), 0);
    for (size_t p = 0; p < points.size(); ++p) {
        const GatherPoint& g = points[p];
        const glm::dvec3 n = g.normal;
        const glm::dvec3 u = glm::normalize(std::fabs(n.x) < 0.9 ? glm::cross(n, glm::dvec3(1, 0, 0)) : glm::cross(n, glm::dvec3(0, 1, 0)));
        const glm::dvec3 v = glm::cross(n, u);
        const glm::dvec3 x = g.position + 1e-7 * g.inside;
        // The normal, and rings at 45° and 80° from it: a point beside a solid sees out along some.
        bool inside = true;
        for (int k = 0; k < 9 && inside; ++k) {
            const double polar = k == 0 ? 0.0 : (k < 5 ? 0.785398163 : 1.396263402), azimuth = 1.570796327 * (k % 4) + 0.4;
            const glm::dvec3 d = std::cos(polar) * n + std::sin(polar) * (std::cos(azimuth) * u + std::sin(azimuth) * v);
            const auto hit = occluders.intersect(Ray{x, d});
            if (!hit) {
                inside = false;
                break;
            }
            const BvhTriangle& t = occluders.triangles()[hit->index];
            const glm::dvec3 front = glm::cross(t.p1 - t.p0, t.p2 - t.p0);
            inside = t.mesh < closed.size() && closed[t.mesh] && glm::dot(front, d) > 0.0;
        }
        buried[p] = inside;
    }
    return buried;
}

}  // namespace metamer::radiosity
