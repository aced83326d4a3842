#include "radiosity/element_coupling.h"

#include "core/cpu_count.h"
#include "core/timing.h"
#include "radiosity/form_factor.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

namespace metamer::radiosity {

namespace {

// Whether some corner of `a` lies in front of the plane of `b` (normal nb): else nothing a sends
// or receives crosses to b's front.
bool anyCornerInFront(const std::array<glm::dvec3, 3>& a, const std::array<glm::dvec3, 3>& b, const glm::dvec3& nb,
                      double slack) {
    for (const glm::dvec3& c : a)
        if (glm::dot(nb, c - b[0]) > slack) return true;
    return false;
}

// Whether every corner of `a` lies in front of the plane of `b`: then no point of either sees the
// other past its horizon, and the point-to-point kernel needs no clipping.
bool allCornersInFront(const std::array<glm::dvec3, 3>& a, const std::array<glm::dvec3, 3>& b, const glm::dvec3& nb) {
    for (const glm::dvec3& c : a)
        if (!(glm::dot(nb, c - b[0]) > 0.0)) return false;
    return true;
}

}  // namespace

Coupling formFactorMatrix(std::span<const std::array<glm::dvec3, 3>> elements, const Bvh* occluders,
                          std::span<const uint32_t> elementSource, const CouplingOptions& options) {
    const auto t0 = Clock::now();
    const size_t n = elements.size();
    Coupling out;
    out.formFactors = Eigen::MatrixXd::Zero(Eigen::Index(n), Eigen::Index(n));
    std::vector<glm::dvec3> normal(n), centroid(n);
    std::vector<double> size(n), area(n);
    for (size_t i = 0; i < n; ++i) {
        area[i] = polygonArea(elements[i]);
        normal[i] = polygonNormal(elements[i]);
        centroid[i] = (elements[i][0] + elements[i][1] + elements[i][2]) / 3.0;
        size[i] = longestEdge(elements[i]);
    }
    // Every element's rule points, for whichever pair it receives in.
    std::vector<std::array<glm::dvec3, 7>> points(n);
    for (size_t i = 0; i < n; ++i)
        for (size_t q = 0; q < kTriangleRule.size(); ++q)
            points[i][q] = kTriangleRule[q].on(elements[i]);
    std::atomic<size_t> nextRow{0}, nearPairs{0}, rays{0}, blocked{0};
    auto work = [&] {
        size_t myNear = 0, myRays = 0, myBlocked = 0;
        for (size_t i; (i = nextRow.fetch_add(1)) < n;) {
            // Each pair once, with the smaller element as the receiver (the rule averages over it;
            // the emitter is exact); the other direction by reciprocity, A_r F_rs = A_s F_sr.
            for (size_t j = i + 1; j < n; ++j) {
                const size_t r = area[i] <= area[j] ? i : j, s = r == i ? j : i;
                const auto& receiver = elements[r];
                // One wholly behind the other's plane, or both in one plane: no exchange.
                if (!anyCornerInFront(receiver, elements[s], normal[s], 1e-12 * size[s]) ||
                    !anyCornerInFront(elements[s], receiver, normal[r], 1e-12 * size[r]))
                    continue;
                const double distance = glm::length(centroid[s] - centroid[r]);
                const bool near = distance < options.nearRatio * std::max(size[r], size[s]);
                // Whether each rule point sees the emitter's centroid.
                std::array<double, 7> seen;
                seen.fill(1.0);
                int visible = 7;
                if (occluders) {
                    // Near pairs: a ray from each rule point (their partial shadows matter); far
                    // ones: one, from the receiver's centroid (the rule's first point).
                    for (size_t q = 0; q < (near ? kTriangleRule.size() : 1); ++q) {
                        const glm::dvec3 d = centroid[s] - points[r][q];
                        const double length = glm::length(d);
                        if (!(length > 0.0)) continue;
                        ++myRays;
                        const Ray ray{points[r][q], d / length};
                        if (occluders->occluded(ray, 1e-9 * length, length * (1.0 - 1e-9), elementSource[r])) {
                            seen[q] = 0.0;
                            --visible;
                            ++myBlocked;
                        }
                    }
                }
                if (!near && seen[0] == 0.0) continue;
                if (visible == 0) continue;
                double f = 0.0;
                if (near) {
                    ++myNear;
                    f = triangleToPolygon(receiver[0], receiver[1], receiver[2], elements[s], options.tolerance) * visible / 7.0;
                } else if (distance >= options.farRatio * std::max(size[r], size[s]) &&
                           visible == 7 && allCornersInFront(receiver, elements[s], normal[s]) &&
                           allCornersInFront(elements[s], receiver, normal[r])) {
                    // The rule on both ends: no arc tangent, for most pairs.
                    for (size_t q = 0; q < kTriangleRule.size(); ++q)
                        f += kTriangleRule[q].w * pointToTriangleByRule(points[r][q], normal[r], points[s], normal[s], area[s]);
                } else {
                    for (size_t q = 0; q < kTriangleRule.size(); ++q)
                        if (seen[q] > 0.0) f += kTriangleRule[q].w * pointToTriangle(points[r][q], normal[r], elements[s], normal[s]);
                }
                out.formFactors(Eigen::Index(r), Eigen::Index(s)) = f;
                out.formFactors(Eigen::Index(s), Eigen::Index(r)) = f * area[r] / area[s];
            }
        }
        nearPairs += myNear;
        rays += myRays;
        blocked += myBlocked;
    };
    std::vector<std::thread> pool;
    const int threads = std::max(1, std::min<int>(usableCpuCount(), int(n / 16) + 1));
    for (int t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    out.nearPairs = nearPairs;
    out.rays = rays;
    out.blockedRays = blocked;
    out.seconds = msSince(t0) / 1000.0;
    return out;
}

}  // namespace metamer::radiosity
