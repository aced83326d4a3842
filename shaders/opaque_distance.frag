#version 450
// The depth pre-pass's fragment stage, in scenes with transparent objects: the distance of the
// nearest opaque surface at each pixel, in the local frame's units, along the view ray from the
// eye (perspective) or from the camera's plane (orthographic) — the same measure transmit.frag
// takes of a transparent surface, so that it can tell which lies in front and end a medium's
// path at the opaque surface. A depth buffer cannot: its precision far from a small near plane
// (a camera inside the scene's bounds) is ~10⁻³ of the distance.
#extension GL_GOOGLE_include_directive : require
#include "interface.h"

layout(push_constant) uniform Push { SpectralPushConstants pc; };

layout(location = 0) in vec3 worldPosition;
// The rest of spectral.vert's outputs, declared so that the interfaces match; not read.
layout(location = 1) in vec3 worldNormal;
layout(location = 2) in vec2 uv;
layout(location = 3) in vec4 worldTangent;

layout(location = 0) out float opaqueDistance;

void main() {
    const vec3 d = worldPosition - pc.cameraPosition.xyz;
    opaqueDistance = pc.cameraPosition.w > 0.5 ? length(d) : dot(d, pc.cameraForward.xyz);
}
