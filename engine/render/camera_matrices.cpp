#include "render/camera_matrices.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace metamer {

CameraMatrices cameraMatrices(const Camera& camera, const Scene& scene) {
    CameraMatrices m;
    glm::dvec3 f = glm::normalize(camera.target - camera.position);
    m.position = glm::vec3(camera.position);
    m.forward = glm::vec3(f);
    m.perspective = camera.projection == Camera::Projection::Perspective;

    // Depth range along the view axis from the scene's bounding box corners.
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& mesh : scene.meshes)
        for (const auto& p : mesh.positions) {
            double z = glm::dot(p - camera.position, f);
            lo = std::min(lo, z);
            hi = std::max(hi, z);
        }
    if (!(hi > lo)) {  // empty or flat scene
        lo = 0.0;
        hi = std::max(1.0, std::isfinite(hi) ? hi + 1.0 : 1.0);
    }
    double span = hi - lo;
    double farPlane = hi + 0.01 * span + 1e-6;
    double nearPlane;
    if (m.perspective)
        nearPlane = std::max(lo - 0.01 * span, farPlane * 1e-5);  // inside the scene: a small near
    else
        nearPlane = std::max(lo - 0.01 * span, 0.0);  // nothing behind the camera plane is seen
    m.near_m = nearPlane;
    m.far_m = farPlane;

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
    m.viewProjection = glm::mat4(proj * view);
    return m;
}

}  // namespace metamer
