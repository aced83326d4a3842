#include "preview/camera_control.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace metamer::preview {

namespace {

// The camera's right and true up vectors (unit): right = forward × up.
void basis(const Camera& c, glm::dvec3& forward, glm::dvec3& right, glm::dvec3& up) {
    forward = glm::normalize(c.target - c.position);
    right = glm::normalize(glm::cross(forward, c.up));
    up = glm::cross(right, forward);
}

glm::dvec3 rotate(const glm::dvec3& v, const glm::dvec3& axis, double angle) {
    // Rodrigues' formula for a unit axis.
    return v * std::cos(angle) + glm::cross(axis, v) * std::sin(angle) +
           axis * glm::dot(axis, v) * (1.0 - std::cos(angle));
}

}  // namespace

double metresPerPixel(const Camera& c) {
    if (c.projection == Camera::Projection::Orthographic) return c.height_m / c.height;
    double distance = glm::length(c.target - c.position);
    return 2.0 * distance * std::tan(glm::radians(c.fov_y_deg) / 2.0) / c.height;
}

Camera orbit(const Camera& c, double yaw_rad, double pitch_rad) {
    Camera out = c;
    glm::dvec3 forward, right, up;
    basis(c, forward, right, up);
    const glm::dvec3 worldUp = glm::normalize(c.up);
    glm::dvec3 offset = c.position - c.target;  // from the target to the camera
    // Pitch first, limited so the offset keeps at least 1° from ±up.
    const double limit = glm::radians(1.0);
    double polar = std::acos(std::clamp(glm::dot(glm::normalize(offset), worldUp), -1.0, 1.0));  // 0: above
    double wanted = std::clamp(polar - pitch_rad, limit, glm::pi<double>() - limit);
    offset = rotate(offset, right, wanted - polar);  // about right, a positive angle lowers the camera
    offset = rotate(offset, worldUp, yaw_rad);
    out.position = c.target + offset;
    return out;
}

Camera pan(const Camera& c, double dx_px, double dy_px) {
    Camera out = c;
    glm::dvec3 forward, right, up;
    basis(c, forward, right, up);
    double m = metresPerPixel(c);
    // The scene follows the cursor, so the camera moves the other way (image y points down).
    glm::dvec3 shift = -right * (dx_px * m) + up * (dy_px * m);
    out.position += shift;
    out.target += shift;
    return out;
}

Camera zoom(const Camera& c, double factor) {
    Camera out = c;
    if (!(factor > 0.0) || !std::isfinite(factor)) return out;
    if (c.projection == Camera::Projection::Orthographic) {
        out.height_m = c.height_m * factor;
    } else {
        glm::dvec3 offset = c.position - c.target;
        double d = glm::length(offset);
        double nd = std::max(d * factor, 1e-6);
        out.position = c.target + offset * (nd / d);
    }
    return out;
}

}  // namespace metamer::preview
