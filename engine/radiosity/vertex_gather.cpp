#include "radiosity/vertex_gather.h"

#include "core/cpu_count.h"
#include "radiosity/form_factor.h"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <thread>

namespace metamer::radiosity {

Eigen::MatrixXd gatherFactors(std::span<const GatherPoint> points, std::span<const std::array<glm::dvec3, 3>> elements,
                              const Bvh* occluders) {
    const size_t m = points.size(), n = elements.size();
    Eigen::MatrixXd W = Eigen::MatrixXd::Zero(Eigen::Index(m), Eigen::Index(n));
    std::vector<glm::dvec3> centroid(n), front(n);
    for (size_t j = 0; j < n; ++j) {
        centroid[j] = (elements[j][0] + elements[j][1] + elements[j][2]) / 3.0;
        front[j] = polygonNormal(elements[j]);
    }
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t p; (p = next.fetch_add(1)) < m;) {
            const GatherPoint& g = points[p];
            // A hair inside its own surface: far below any element, far above rounding.
            const glm::dvec3 x = g.position + 1e-7 * g.inside;
            for (size_t j = 0; j < n; ++j) {
                const double f = pointToTriangle(x, g.normal, elements[j], front[j]);
                if (f == 0.0) continue;
                if (occluders) {
                    const glm::dvec3 d = centroid[j] - x;
                    const double length = glm::length(d);
                    if (length > 0.0 && occluders->occluded(Ray{x, d / length}, 1e-9 * length, length * (1.0 - 1e-9), g.source))
                        continue;
                }
                W(Eigen::Index(p), Eigen::Index(j)) = f;
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

Eigen::MatrixXd sampledGatherFactors(std::span<const GatherPoint> points, std::span<const std::array<glm::dvec3, 3>> elements,
                                     const Bvh& occluders, int side) {
    const size_t m = points.size(), n = elements.size();
    Eigen::MatrixXd W = Eigen::MatrixXd::Zero(Eigen::Index(m), Eigen::Index(n));
    // Stratified points on a triangle: a side × side grid of cell centres on the unit square,
    // mapped by (s, t) → (1 − √s, √s(1 − t), √s·t), which keeps equal areas.
    std::vector<glm::dvec3> weights;
    for (int a = 0; a < side; ++a)
        for (int b = 0; b < side; ++b) {
            const double u = std::sqrt((a + 0.5) / side), t = (b + 0.5) / side;
            weights.push_back({1.0 - u, u * (1.0 - t), u * t});
        }
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t p; (p = next.fetch_add(1)) < m;) {
            const GatherPoint& g = points[p];
            const glm::dvec3 x = g.position + 1e-7 * g.inside;
            for (size_t j = 0; j < n; ++j) {
                const auto& c = elements[j];
                const double f = pointToTriangle(x, g.normal, c, polygonNormal(c));
                if (f == 0.0) continue;
                int seen = 0;
                for (const glm::dvec3& w : weights) {
                    const glm::dvec3 d = w.x * c[0] + w.y * c[1] + w.z * c[2] - x;
                    const double length = glm::length(d);
                    seen += length > 0.0 && !occluders.occluded(Ray{x, d / length}, 1e-9 * length, length * (1.0 - 1e-9), g.source);
                }
                W(Eigen::Index(p), Eigen::Index(j)) = f * seen / double(weights.size());
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
