#include "color/lab.h"

#include <cmath>

namespace metamer {

namespace {

// CIE 15:2004 constants written as exact ratios (ε = (6/29)³, κ = (29/3)³) rather than the older
// rounded 0.008856 and 903.3, which leave a small jump at the knee.
constexpr double kEpsilon = 216.0 / 24389.0;
constexpr double kKappa = 24389.0 / 27.0;

// f(t) = t^(1/3) above the knee, (κ·t + 16)/116 below; continuous (value and slope) at t = ε.
double labF(double t) { return t > kEpsilon ? std::cbrt(t) : (kKappa * t + 16.0) / 116.0; }

// The inverse of labF. The branch is chosen on f itself: f > 6/29 exactly when t > ε.
double labFInverse(double f) {
    const double f3 = f * f * f;
    return f3 > kEpsilon ? f3 : (116.0 * f - 16.0) / kKappa;
}

// df/dt: t^(−2/3)/3 above the knee, κ/116 below.
double labFDerivative(double t) {
    if (t > kEpsilon) {
        const double c = std::cbrt(t);
        return 1.0 / (3.0 * c * c);
    }
    return kKappa / 116.0;
}

}  // namespace

glm::dmat3 xyzToLabJacobian(const glm::dvec3& xyz, const glm::dvec3& w) {
    const double fx = labFDerivative(xyz.x / w.x) / w.x;
    const double fy = labFDerivative(xyz.y / w.y) / w.y;
    const double fz = labFDerivative(xyz.z / w.z) / w.z;
    glm::dmat3 j(0.0);
    j[0] = glm::dvec3(0.0, 500.0 * fx, 0.0);
    j[1] = glm::dvec3(116.0 * fy, -500.0 * fy, 200.0 * fy);
    j[2] = glm::dvec3(0.0, 0.0, -200.0 * fz);
    return j;
}

glm::dvec3 xyzToLab(const glm::dvec3& xyz, const glm::dvec3& whiteXyz) {
    const double fx = labF(xyz.x / whiteXyz.x);
    const double fy = labF(xyz.y / whiteXyz.y);
    const double fz = labF(xyz.z / whiteXyz.z);
    return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

glm::dvec3 labToXyz(const glm::dvec3& lab, const glm::dvec3& whiteXyz) {
    const double fy = (lab.x + 16.0) / 116.0;
    const double fx = fy + lab.y / 500.0;
    const double fz = fy - lab.z / 200.0;
    return {whiteXyz.x * labFInverse(fx), whiteXyz.y * labFInverse(fy), whiteXyz.z * labFInverse(fz)};
}

}  // namespace metamer
