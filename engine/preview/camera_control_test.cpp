// Orbit, pan and zoom: checked through the camera matrices the spectral pass uses
// (render/camera_matrices), so "the target follows the cursor" is measured in projected pixels.
#include "preview/camera_control.h"
#include "render/camera_matrices.h"

#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>

#include <cmath>

using namespace metamer;
using namespace metamer::preview;

namespace {

Scene sceneWith(const Camera& c) {
    Scene s;
    s.camera = c;
    Mesh m;  // something to fit the depth range to
    m.positions = {{-1, -1, -1}, {1, 1, 1}, {1, -1, 0}};
    m.indices = {0, 1, 2};
    s.meshes.push_back(m);
    return s;
}

// Where a world point lands in the image, in pixels (x right, y down).
glm::dvec2 project(const Camera& c, const glm::dvec3& p) {
    const Scene s = sceneWith(c);
    const LocalFrame frame = localFrameFor(s, c);
    CameraMatrices m = cameraMatrices(c, s, frame);
    glm::vec4 clip = m.viewProjection * glm::vec4(glm::vec3(frame.position(p)), 1.0f);
    glm::dvec2 ndc(clip.x / clip.w, clip.y / clip.w);
    return {(ndc.x + 1.0) * 0.5 * c.width, (ndc.y + 1.0) * 0.5 * c.height};
}

Camera perspective() {
    Camera c;
    c.position = {1.0, 2.0, 6.0};
    c.target = {0.5, 0.0, 0.0};
    c.width = 400;
    c.height = 300;
    c.fov_y_deg = 40.0;
    return c;
}

}  // namespace

TEST(CameraControl, OrbitKeepsTargetAndDistanceAndTurnsByTheAngles) {
    Camera c = perspective();
    Camera o = orbit(c, 0.3, 0.0);
    EXPECT_EQ(o.target, c.target);
    EXPECT_NEAR(glm::length(o.position - o.target), glm::length(c.position - c.target), 1e-12);
    // A pure yaw turns the offset's projection on the plane normal to up by exactly the angle.
    glm::dvec2 a(c.position.x - c.target.x, c.position.z - c.target.z), b(o.position.x - o.target.x,
                                                                       o.position.z - o.target.z);
    EXPECT_NEAR(std::acos(glm::dot(a, b) / (glm::length(a) * glm::length(b))), 0.3, 1e-12);
    EXPECT_NEAR(o.position.y, c.position.y, 1e-12);
    // Positive pitch raises the camera; the target stays at the image centre.
    Camera up = orbit(c, 0.0, 0.2);
    EXPECT_GT(up.position.y, c.position.y);
    glm::dvec2 centre = project(up, up.target);
    EXPECT_NEAR(centre.x, 200.0, 1e-3);
    EXPECT_NEAR(centre.y, 150.0, 1e-3);
}

TEST(CameraControl, OrbitStopsShortOfThePoles) {
    Camera c = perspective();
    Camera top = orbit(c, 0.0, 10.0);  // far past straight above
    glm::dvec3 offset = glm::normalize(top.position - top.target);
    EXPECT_NEAR(std::acos(offset.y), glm::radians(1.0), 1e-9);
    Camera bottom = orbit(c, 0.0, -10.0);
    offset = glm::normalize(bottom.position - bottom.target);
    EXPECT_NEAR(std::acos(offset.y), glm::pi<double>() - glm::radians(1.0), 1e-9);
}

TEST(CameraControl, PanMovesTheTargetDepthWithTheCursor) {
    for (auto projection : {Camera::Projection::Perspective, Camera::Projection::Orthographic}) {
        Camera c = perspective();
        c.projection = projection;
        c.height_m = 3.0;
        glm::dvec2 before = project(c, c.target);
        Camera p = pan(c, 25.0, -10.0);
        // The old target point moved 25 px right and 10 px up on the screen.
        glm::dvec2 after = project(p, c.target);
        EXPECT_NEAR(after.x - before.x, 25.0, 1e-3);
        EXPECT_NEAR(after.y - before.y, -10.0, 1e-3);
        EXPECT_NEAR(glm::length(p.position - p.target), glm::length(c.position - c.target), 1e-12);
    }
}

TEST(CameraControl, ZoomDolliesPerspectiveAndNarrowsOrthographic) {
    Camera c = perspective();
    Camera z = zoom(c, 0.5);
    EXPECT_NEAR(glm::length(z.position - z.target), 0.5 * glm::length(c.position - c.target), 1e-12);
    EXPECT_EQ(z.target, c.target);
    // Twice as close: a small offset from the target looks about twice as large.
    glm::dvec3 q = c.target + glm::dvec3(0.01, 0.0, 0.0);
    double before = glm::length(project(c, q) - project(c, c.target));
    double after = glm::length(project(z, q) - project(z, z.target));
    EXPECT_NEAR(after / before, 2.0, 0.01);
    c.projection = Camera::Projection::Orthographic;
    EXPECT_DOUBLE_EQ(zoom(c, 0.25).height_m, 0.5);
    EXPECT_EQ(zoom(c, 0.25).position, c.position);
    EXPECT_EQ(zoom(c, -1.0).height_m, c.height_m);  // nonsense factors change nothing
}
