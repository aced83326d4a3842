#version 450
// The shadow-map depth pass: the scene's triangles seen from one light (one layer of the shadow
// maps; a point light draws six). Depth only; the pipeline adds a slope-scaled bias.
#extension GL_GOOGLE_include_directive : require
#include "interface.h"

layout(location = VERTEX_POSITION) in vec3 inPosition;

layout(push_constant) uniform Push { ShadowPushConstants pc; };

void main() { gl_Position = pc.lightViewProjection * vec4(inPosition, 1.0); }
