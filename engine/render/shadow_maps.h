// Where each shadowing light's depth is drawn: the layers of the shadow maps and their
// world → clip matrices, fitted to the scene's bounds — plain C++, no Vulkan object. One layer per
// directional light (an orthographic view along the light, covering every triangle), six per point
// light (cube faces +x, −x, +y, −y, +z, −z: 90° perspective views). docs/physics.md, "Shadows".
// Tests: engine/render/shadow_maps_test.cpp.
#pragma once

#include "scene/local_frame.h"
#include "scene/scene.h"

#include <glm/glm.hpp>

#include <vector>

namespace metamer {

struct ShadowLayer {
    glm::dmat4 viewProjection{1.0};  // frame → clip (x, y in [−1, 1] over the map, depth 0..1)
};

struct ShadowLight {
    int firstLayer = -1;  // −1: casts no shadows
    // A texel's size: frame units (directional), or units per unit of distance along the face's
    // axis (point).
    double texel = 0.0;
};

struct ShadowMaps {
    std::vector<ShadowLayer> layers;
    std::vector<ShadowLight> lights;  // per scene light
    bool any() const { return !layers.empty(); }
};

// `size`: texels per side of every layer. A point light's near plane lies at 1e-3 of the scene's
// size (closer triangles cast no shadow). More layers than MAX_SHADOW_LAYERS is an input error
// naming the light that does not fit. Positions and matrices are in `frame` (scene/local_frame.h).
ShadowMaps planShadowMaps(const Scene& scene, int size, const LocalFrame& frame = {});

}  // namespace metamer
