#include "color/display_rgb.h"

namespace metamer {

namespace {

glm::dvec2 chromaticity(const glm::dvec3& xyz) {
    const double sum = xyz.x + xyz.y + xyz.z;
    return sum > 0.0 ? glm::dvec2(xyz.x / sum, xyz.y / sum) : glm::dvec2(0.0);
}

}  // namespace

DisplayPrimaries displayPrimaries(const DisplayModel& display) {
    const glm::dmat3& m = display.rgbToXyz;
    return {chromaticity(m[0]), chromaticity(m[1]), chromaticity(m[2]), chromaticity(m * glm::dvec3(1.0))};
}

}  // namespace metamer
