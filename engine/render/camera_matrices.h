// The camera as the rasterizer sees it: view-projection for Vulkan clip space (y down, depth
// 0..1), following the pixel conventions of docs/physics.md ("Camera"), in the scene's local
// frame (scene/local_frame.h): the vertices the matrix meets are in the frame's units.
// Tests: engine/preview/camera_control_test.cpp, tests/numerics_test.cpp,
// tests/gpu_known_answer_test.cpp.
#pragma once

#include "scene/local_frame.h"
#include "scene/scene.h"

#include <glm/glm.hpp>

namespace metamer {

struct CameraMatrices {
    glm::mat4 viewProjection{1.0f};      // frame units → clip
    glm::vec3 position{0.0f};            // in the frame
    glm::vec3 forward{0.0f, 0.0f, -1.0f};
    bool perspective = true;
    double nearPlane = 0.0, farPlane = 1.0;  // distances along the view axis, in the frame's units
};

// `camera` in world coordinates (m). Near and far planes are fitted to the scene's extent along
// the view, so depth precision is spent where the geometry is, at any scale.
CameraMatrices cameraMatrices(const Camera& camera, const Scene& scene, const LocalFrame& frame);

}  // namespace metamer
