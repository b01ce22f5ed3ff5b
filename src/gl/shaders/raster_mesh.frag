#version 430 core
#extension GL_GOOGLE_include_directive : require
// Mesh path (src/gl/raster_mesh.cpp): the GL twin of src/cpu/raster_mesh.cpp's
// fragment. A fragment at or behind the scene depth is discarded (as the
// CPU's z-buffer starting at the scene depth); the depth test keeps the
// nearest: it compares near / eyeDepth with GL_GREATER in a float depth
// buffer (a reversed linear depth: relative precision is the same at every
// distance, so the order of two surfaces is that of their eye depths as the
// CPU compares them). The targets get the linear eye depth and the
// renormalised interpolated normal, and the texture coordinates.
#include "frame_params.h"

in float vEyeDepth;
in vec3 vNormal;
in vec2 vUv;

// W*H eye depth of the scene, row 0 = the top (a GpuImage).
layout(std430, binding = 1) readonly buffer SceneDepth { float sceneDepth[]; };
layout(location = 0) uniform int uHasScene;

layout(location = 0) out float outDepth;
layout(location = 1) out vec4 outNormal;
layout(location = 2) out vec2 outUv;

void main() {
    const int x = int(gl_FragCoord.x);
    const int row = int(gl_FragCoord.y);  // drawn upside down: framebuffer row = image row
    const float z = vEyeDepth;
    if (uHasScene != 0 && !(z < sceneDepth[row * P.size.x + x])) discard;
    gl_FragDepth = P.eye.w / z;
    outDepth = z;
    const float len = length(vNormal);
    outNormal = vec4(len > 0.0 ? vNormal / len : vec3(0.0), 0.0);
    outUv = vUv;
}
