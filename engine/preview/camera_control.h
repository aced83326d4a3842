// Orbit, pan and zoom of the scene camera, as the preview's mouse does them. Pure functions of
// the Camera (scene/scene.h): the image size, projection and field of view never change, so a
// moved camera renders exactly as the same camera written in the scene file would.
#pragma once

#include "scene/scene.h"

namespace metamer::preview {

// Turns the camera about its target: `yaw_rad` about the camera's up vector, `pitch_rad` about
// its right vector (positive: the camera rises). The distance to the target is kept; the pitch
// stops 1° short of the up vector's poles, where the view direction would be parallel to `up`.
Camera orbit(const Camera& camera, double yaw_rad, double pitch_rad);

// Moves position and target together in the image plane so that a point at the target's depth
// follows the cursor: `dx_px` to the right, `dy_px` down, in image pixels.
Camera pan(const Camera& camera, double dx_px, double dy_px);

// factor < 1 comes closer: a perspective camera moves towards its target (the distance × factor,
// kept above 1e-6 m); an orthographic one narrows its view (height_m × factor).
Camera zoom(const Camera& camera, double factor);

// Metres in the scene per image pixel at the target's depth.
double metresPerPixel(const Camera& camera);

}  // namespace metamer::preview
