#include "radiosity/form_factor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace metamer::radiosity {

namespace {

constexpr double kPi = std::numbers::pi;

// The part of the polygon on or above the plane through x with normal n (Sutherland–Hodgman): what
// a point on a surface can see of it. At most one more vertex than it had.
std::vector<glm::dvec3> clipToHemisphere(const glm::dvec3& x, const glm::dvec3& n, std::span<const glm::dvec3> polygon) {
    std::vector<glm::dvec3> out;
    const size_t m = polygon.size();
    out.reserve(m + 1);
    for (size_t k = 0; k < m; ++k) {
        const glm::dvec3& p = polygon[k];
        const glm::dvec3& q = polygon[(k + 1) % m];
        const double hp = glm::dot(n, p - x), hq = glm::dot(n, q - x);
        if (hp >= 0.0) out.push_back(p);
        if ((hp >= 0.0) != (hq >= 0.0)) out.push_back(p + (q - p) * (hp / (hp - hq)));
    }
    return out;
}


struct Triangle {
    glm::dvec3 a, b, c;
};

// The emitter, with its front normal found once: a triangle takes the allocation-free path.
struct Emitter {
    std::span<const glm::dvec3> polygon;
    std::array<glm::dvec3, 3> triangle{};
    glm::dvec3 front{0.0};
    bool isTriangle = false;
    explicit Emitter(std::span<const glm::dvec3> p) : polygon(p), front(polygonNormal(p)), isTriangle(p.size() == 3) {
        if (isTriangle) triangle = {p[0], p[1], p[2]};
    }
    double from(const glm::dvec3& x, const glm::dvec3& n) const {
        return isTriangle ? pointToTriangle(x, n, triangle, front) : pointToPolygon(x, n, polygon);
    }
};

double ruleAverage(const Triangle& t, const glm::dvec3& n, const Emitter& emitter) {
    double sum = 0.0;
    for (const TrianglePoint& q : kTriangleRule) sum += q.w * emitter.from(q.a * t.a + q.b * t.b + q.c * t.c, n);
    return sum;
}

// The average of the point factor over t, given the rule's estimate `coarse` on t: the four
// halves' estimates are compared with it and each half refined until they agree to `tolerance`.
double adaptiveAverage(const Triangle& t, const glm::dvec3& n, const Emitter& polygon, double coarse,
                       double tolerance, int depth) {
    const glm::dvec3 ab = 0.5 * (t.a + t.b), bc = 0.5 * (t.b + t.c), ca = 0.5 * (t.c + t.a);
    const std::array<Triangle, 4> halves = {{{t.a, ab, ca}, {ab, t.b, bc}, {ca, bc, t.c}, {bc, ca, ab}}};
    std::array<double, 4> estimates;
    double fine = 0.0;
    for (int i = 0; i < 4; ++i) fine += 0.25 * (estimates[i] = ruleAverage(halves[i], n, polygon));
    if (std::fabs(fine - coarse) <= tolerance || depth >= 16) return fine;
    double refined = 0.0;
    for (int i = 0; i < 4; ++i) refined += 0.25 * adaptiveAverage(halves[i], n, polygon, estimates[i], tolerance, depth + 1);
    return refined;
}

}  // namespace

glm::dvec3 polygonNormal(std::span<const glm::dvec3> polygon) {
    glm::dvec3 sum(0.0);
    for (size_t k = 0; k < polygon.size(); ++k) sum += glm::cross(polygon[k], polygon[(k + 1) % polygon.size()]);
    const double length = glm::length(sum);
    return length > 0.0 ? sum / length : glm::dvec3(0.0);
}

double longestEdge(const std::array<glm::dvec3, 3>& t) {
    return std::max({glm::length(t[1] - t[0]), glm::length(t[2] - t[1]), glm::length(t[0] - t[2])});
}

double polygonArea(std::span<const glm::dvec3> polygon) {
    glm::dvec3 sum(0.0);
    for (size_t k = 0; k < polygon.size(); ++k) sum += glm::cross(polygon[k], polygon[(k + 1) % polygon.size()]);
    return 0.5 * glm::length(sum);
}

namespace {

// Lambert's sum over the closed polygon's edges (at most 4 vertices here), F = −Σ/2π.
double lambertSum(const glm::dvec3& x, const glm::dvec3& n, const glm::dvec3* v, int count) {
    double sum = 0.0;
    for (int k = 0; k < count; ++k) {
        const glm::dvec3 r0 = v[k] - x, r1 = v[(k + 1) % count] - x;
        const glm::dvec3 c = glm::cross(r0, r1);
        const double s = glm::length(c);
        if (!(s > 0.0)) continue;
        sum += std::atan2(s, glm::dot(r0, r1)) * glm::dot(n, c) / s;
    }
    return std::clamp(-sum / (2.0 * kPi), 0.0, 1.0);
}

}  // namespace

double pointToTriangle(const glm::dvec3& x, const glm::dvec3& n, const std::array<glm::dvec3, 3>& t,
                       const glm::dvec3& front) {
    if (!(glm::dot(front, x - t[0]) > 0.0)) return 0.0;
    const double h[3] = {glm::dot(n, t[0] - x), glm::dot(n, t[1] - x), glm::dot(n, t[2] - x)};
    const bool above[3] = {h[0] >= 0.0, h[1] >= 0.0, h[2] >= 0.0};
    if (!above[0] && !above[1] && !above[2]) return 0.0;
    if (above[0] && above[1] && above[2]) return lambertSum(x, n, t.data(), 3);
    // Clipped to x's hemisphere: a triangle cut by a plane leaves at most 4 vertices.
    glm::dvec3 v[4];
    int count = 0;
    for (int k = 0; k < 3; ++k) {
        const int k1 = (k + 1) % 3;
        if (above[k]) v[count++] = t[size_t(k)];
        if (above[k] != above[k1]) v[count++] = t[size_t(k)] + (t[size_t(k1)] - t[size_t(k)]) * (h[k] / (h[k] - h[k1]));
    }
    return count >= 3 ? lambertSum(x, n, v, count) : 0.0;
}

double pointToTriangleByRule(const glm::dvec3& x, const glm::dvec3& n, const std::array<glm::dvec3, 7>& rule,
                             const glm::dvec3& front, double area) {
    double sum = 0.0;
    for (size_t k = 0; k < kTriangleRule.size(); ++k) {
        const glm::dvec3 d = rule[k] - x;
        const double d2 = glm::dot(d, d);
        sum += kTriangleRule[k].w * std::max(0.0, glm::dot(n, d)) * std::max(0.0, -glm::dot(front, d)) / (d2 * d2);
    }
    return sum * area / kPi;
}

double pointToPolygon(const glm::dvec3& x, const glm::dvec3& n, std::span<const glm::dvec3> polygon) {
    if (polygon.size() < 3) return 0.0;
    // Seen from behind, or edge-on: nothing of its front side reaches x.
    const glm::dvec3 front = polygonNormal(polygon);
    if (!(glm::dot(front, x - polygon[0]) > 0.0)) return 0.0;
    const std::vector<glm::dvec3> visible = clipToHemisphere(x, n, polygon);
    if (visible.size() < 3) return 0.0;
    // Lambert: each edge subtends the angle γ between its end points seen from x, in the plane
    // whose normal ĝ is the normalized cross product; the polygon faces x, so seen from x it winds
    // clockwise and the sum comes out negative.
    double sum = 0.0;
    for (size_t k = 0; k < visible.size(); ++k) {
        const glm::dvec3 r0 = visible[k] - x, r1 = visible[(k + 1) % visible.size()] - x;
        const glm::dvec3 c = glm::cross(r0, r1);
        const double s = glm::length(c);
        if (!(s > 0.0)) continue;  // an edge through x or of no length subtends nothing
        sum += std::atan2(s, glm::dot(r0, r1)) * glm::dot(n, c) / s;
    }
    return std::clamp(-sum / (2.0 * kPi), 0.0, 1.0);
}

double triangleToPolygon(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                         std::span<const glm::dvec3> polygon, double tolerance) {
    const std::array<glm::dvec3, 3> receiver{a, b, c};
    const glm::dvec3 n = polygonNormal(receiver);
    if (glm::dot(n, n) == 0.0) return 0.0;
    const Triangle t{a, b, c};
    const Emitter emitter(polygon);
    return adaptiveAverage(t, n, emitter, ruleAverage(t, n, emitter), tolerance, 0);
}

}  // namespace metamer::radiosity
