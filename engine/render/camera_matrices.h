// The camera as the rasterizer sees it: view-projection for Vulkan clip space (y down, depth
// 0..1), following the pixel conventions of docs/physics.md ("Camera").
// Tests: engine/preview/camera_control_test.cpp, tests/numerics_test.cpp,
// tests/gpu_known_answer_test.cpp.
#pragma once

#include "scene/scene.h"

#include <glm/glm.hpp>

namespace metamer {

struct CameraMatrices {
    glm::mat4 viewProjection{1.0f};
    glm::vec3 position{0.0f};
    glm::vec3 forward{0.0f, 0.0f, -1.0f};
    bool perspective = true;
    double near_m = 0.0, far_m = 1.0;
};

// Near and far planes are fitted to the scene's bounds so depth precision is spent where the
// geometry is.
CameraMatrices cameraMatrices(const Camera& camera, const Scene& scene);

}  // namespace metamer
