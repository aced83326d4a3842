#include "scene/local_frame.h"

#include "core/error.h"

#include <algorithm>
#include <limits>

namespace metamer {

Camera LocalFrame::camera(const Camera& world) const {
    Camera c = world;
    c.position = position(world.position);
    c.target = position(world.target);
    c.height_m = length(world.height_m);
    return c;
}

LocalFrame localFrameFor(const Scene& scene, const Camera& camera) {
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    for (const Mesh& mesh : scene.meshes)
        for (const glm::dvec3& p : mesh.positions) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    LocalFrame frame;
    if (!(hi.x >= lo.x)) {  // no vertices: nothing to see; keep the camera's neighbourhood exact
        frame.origin = camera.position;
        return frame;
    }
    frame.origin = glm::clamp(camera.position, lo, hi);
    const double extent = glm::length(hi - lo);
    const Where objects{scene.file.string(), "objects"};
    if (extent > 0.0) {
        if (!(extent >= kSmallestSceneExtent_m && extent <= kLargestSceneExtent_m))
            failInput(objects,
                      "the objects span {:g} m (their bounding box's diagonal); Metamer renders scenes from {:g} m to {:g} m "
                      "across (docs/numerics.md, \"Scale and position\")",
                      extent, kSmallestSceneExtent_m, kLargestSceneExtent_m);
        frame.unitExponent = std::ilogb(extent);
        if (extent > std::ldexp(1.5, frame.unitExponent)) ++frame.unitExponent;  // the nearest power of two
    }
    // Everything else the renderers place: within 2⁶⁰ of the scene's span (float32 holds the
    // squares of such distances, in units, with room to spare).
    const double farthest = kFarthestInExtents;
    auto near = [&](const glm::dvec3& p) {
        const glm::dvec3 q = frame.position(p);
        return std::max({std::fabs(q.x), std::fabs(q.y), std::fabs(q.z)}) <= farthest;
    };
    const Where cam{scene.file.string(), "camera.position"};
    if (!near(camera.position))
        failInput(cam,
                  "the camera is {:g} m from objects that span {:g} m; Metamer places the camera and lights within "
                  "{:g} times the scene's span of it (docs/numerics.md, \"Scale and position\")",
                  glm::length(camera.position - frame.origin), extent, farthest);
    for (const Light& light : scene.lights)
        if (light.type == Light::Type::Point && !near(light.position))
            failInput(Where{scene.file.string(), light.name + ".position"},
                      "the light is {:g} m from objects that span {:g} m; Metamer places the camera and lights within "
                      "{:g} times the scene's span of it (docs/numerics.md, \"Scale and position\")",
                      glm::length(light.position - frame.origin), extent, farthest);
    return frame;
}

}  // namespace metamer
