// The frame both renderers compute positions in: an origin near what the camera sees and a unit
// of length that is a power of two near the scene's size. A float32 position keeps 24 bits
// relative to its magnitude, so world coordinates 10⁵ m from the world origin keep only
// millimetres; in this frame a position's rounding is relative to its distance from the scene,
// and the numbers the GPU sees are O(1) whatever the scene's scale. Moving to the frame is exact
// where the world coordinates allow it (a difference of nearby doubles, then a power of two).
// docs/numerics.md, "Scale and position". Tests: scene/local_frame_test.cpp, tests/numerics_test.cpp.
#pragma once

#include "scene/scene.h"

#include <glm/glm.hpp>

#include <cmath>

namespace metamer {

// The lengths Metamer renders (docs/numerics.md): a scene whose objects span 10⁻¹⁵ … 10¹⁵ m, with
// its camera and lights within 2⁶⁰ (1.2 × 10¹⁸) of that span of it. Beyond, an input error.
inline constexpr double kSmallestSceneExtent_m = 1e-15;
inline constexpr double kLargestSceneExtent_m = 1e15;
inline constexpr double kFarthestInExtents = 1152921504606846976.0;  // 2⁶⁰

struct LocalFrame {
    glm::dvec3 origin{0.0};  // m, world coordinates
    int unitExponent = 0;    // one unit of the frame is 2^unitExponent m

    // A world position (m) in the frame's units.
    glm::dvec3 position(const glm::dvec3& world) const {
        const glm::dvec3 d = world - origin;
        return {std::ldexp(d.x, -unitExponent), std::ldexp(d.y, -unitExponent), std::ldexp(d.z, -unitExponent)};
    }
    // A length (m) in the frame's units.
    double length(double metres) const { return std::ldexp(metres, -unitExponent); }
    // Lengths in the frame's units times this are metres.
    double unit_m() const { return std::ldexp(1.0, unitExponent); }
    // 1/d² with d in the frame's units, times this, is 1/d² in m⁻² (a point light's falloff): a
    // power of two, so the product is exact.
    double inverseSquareUnit() const { return std::ldexp(1.0, -2 * unitExponent); }
    // The camera with its position and target in the frame, and an orthographic height in units.
    Camera camera(const Camera& world) const;
};

// The frame for rendering `scene` from `camera`: the origin is the point of the objects' bounding
// box nearest the camera (the camera's own position when it is inside), the unit the power of two
// nearest the box's diagonal (1 m for a scene without extent). A scene outside the lengths above
// is an input error naming the objects, the camera or the light.
LocalFrame localFrameFor(const Scene& scene, const Camera& camera);

}  // namespace metamer
