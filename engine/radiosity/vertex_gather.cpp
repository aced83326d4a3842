#include "radiosity/vertex_gather.h"

#include "core/cpu_count.h"
#include "radiosity/form_factor.h"

#include <algorithm>
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

}  // namespace metamer::radiosity
