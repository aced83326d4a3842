#version 450
// The spectral pass's vertex stage: world-space positions and normals (meshes are transformed on
// load), projected by the camera; texture coordinates and tangents pass through.
#extension GL_GOOGLE_include_directive : require
#include "interface.h"

layout(location = VERTEX_POSITION) in vec3 inPosition;
layout(location = VERTEX_NORMAL) in vec3 inNormal;
layout(location = VERTEX_UV) in vec2 inUv;
layout(location = VERTEX_TANGENT) in vec4 inTangent;

layout(location = 0) out vec3 worldPosition;
layout(location = 1) out vec3 worldNormal;
layout(location = 2) out vec2 uv;
layout(location = 3) out vec4 worldTangent;
#ifdef INDIRECT
// Interreflection's indirect light at the vertex, passed on to be interpolated (interface.h).
layout(location = VERTEX_INDIRECT) in vec4 inIndirect[INDIRECT_RECORD_VEC4];
layout(location = VARYING_INDIRECT) out vec4 indirect[INDIRECT_RECORD_VEC4];
#endif

layout(push_constant) uniform Push { SpectralPushConstants pc; };

// The depth pre-pass and the colour passes must compute bit-identical depths (test EQUAL).
invariant gl_Position;

void main() {
    worldPosition = inPosition;
    worldNormal = inNormal;
    uv = inUv;
    worldTangent = inTangent;
#ifdef INDIRECT
    for (int k = 0; k < INDIRECT_RECORD_VEC4; ++k) indirect[k] = inIndirect[k];
#endif
    gl_Position = pc.viewProjection * vec4(inPosition, 1.0);
}
