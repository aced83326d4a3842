#include "render/camera_matrices.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace metamer {

CameraMatrices cameraMatrices(const Camera& worldCamera, const Scene& scene, const LocalFrame& frame) {
    const Camera camera = frame.camera(worldCamera);
    CameraMatrices m;
    glm::dvec3 f = glm::normalize(camera.target - camera.position);
    m.position = glm::vec3(camera.position);
    m.forward = glm::vec3(f);
    m.perspective = camera.projection == Camera::Projection::Perspective;

    // Depth range along the view axis, from every vertex, in the frame's units.
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& mesh : scene.meshes)
        for (const auto& p : mesh.positions) {
            double z = glm::dot(frame.position(p) - camera.position, f);
            lo = std::min(lo, z);
            hi = std::max(hi, z);
        }
    if (!(hi >= lo)) lo = hi = 0.0;  // no vertices
    // A flat scene seen face-on has no depth span, and one seen edge-on lies at depth 0: give it a
    // slab of 10⁻³ of its depth, or of one unit (about the scene's size) — never a fixed length, so
    // that a scene of micrometres and one of megametres get the same planes.
    double span = std::max(hi - lo, 1e-3 * std::max(std::fabs(lo), std::fabs(hi)));
    if (!(span > 0.0)) span = 1.0;
    const double mid = 0.5 * (lo + hi);
    lo = std::min(lo, mid - 0.5 * span);
    hi = std::max(hi, mid + 0.5 * span);
    double farPlane = hi + 0.01 * span;
    double nearPlane;
    if (m.perspective) {
        nearPlane = std::max(lo - 0.01 * span, farPlane * 1e-5);  // inside the scene: a small near
        if (!(farPlane > 0.0)) nearPlane = 1.0, farPlane = 2.0;    // everything behind the camera: nothing seen
    } else {
        nearPlane = std::max(lo - 0.01 * span, 0.0);  // nothing behind the camera plane is seen
        if (!(farPlane > nearPlane)) nearPlane = 0.0, farPlane = 1.0;
    }
    m.nearPlane = nearPlane;
    m.farPlane = farPlane;

    double aspect = double(camera.width) / double(camera.height);
    glm::dmat4 view = glm::lookAt(camera.position, camera.target, camera.up);
    glm::dmat4 proj;
    if (m.perspective) {
        proj = glm::perspective(glm::radians(camera.fov_y_deg), aspect, nearPlane, farPlane);
    } else {
        double hh = 0.5 * camera.height_m, hw = hh * aspect;
        proj = glm::ortho(-hw, hw, -hh, hh, nearPlane, farPlane);
    }
    proj[1][1] *= -1.0;  // Vulkan clip space: y points down, so row 0 is the top of the image
    // Multiplied in double and rounded once: with the origin near the scene, the depth row's
    // constant is small and keeps its precision in float.
    m.viewProjection = glm::mat4(proj * view);
    return m;
}

}  // namespace metamer
