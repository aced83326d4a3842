#version 450
// The spectral pass's vertex stage: world-space positions and normals (meshes are transformed on
// load), projected by the camera.
#extension GL_GOOGLE_include_directive : require
#include "interface.h"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;

layout(location = 0) out vec3 worldPosition;
layout(location = 1) out vec3 worldNormal;

layout(push_constant) uniform Push { SpectralPushConstants pc; };

// The depth pre-pass and the colour passes must compute bit-identical depths (test EQUAL).
invariant gl_Position;

void main() {
    worldPosition = inPosition;
    worldNormal = inNormal;
    gl_Position = pc.viewProjection * vec4(inPosition, 1.0);
}
