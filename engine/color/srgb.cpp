#include "color/srgb.h"

#include <glm/matrix.hpp>

#include <cmath>

namespace metamer {

namespace {

// RGB -> XYZ columns are the primaries scaled so that RGB (1,1,1) lands on the white.
glm::dmat3 deriveXyzToRgb() {
    auto column = [](double x, double y) { return glm::dvec3(x / y, 1.0, (1.0 - x - y) / y); };
    glm::dmat3 primaries(column(0.64, 0.33), column(0.30, 0.60), column(0.15, 0.06));
    glm::dvec3 scale = glm::inverse(primaries) * kD65WhiteXyz;
    glm::dmat3 rgbToXyz(primaries[0] * scale.x, primaries[1] * scale.y, primaries[2] * scale.z);
    return glm::inverse(rgbToXyz);
}

}  // namespace

const glm::dmat3& xyzToLinearSrgbMatrix() {
    static const glm::dmat3 m = deriveXyzToRgb();
    return m;
}

glm::dvec3 xyzToLinearSrgb(const glm::dvec3& xyz) { return xyzToLinearSrgbMatrix() * xyz; }

double srgbEncode(double v) {
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

double srgbDecode(double e) {
    return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
}

}  // namespace metamer
