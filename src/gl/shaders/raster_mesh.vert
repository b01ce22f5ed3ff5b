#version 430 core
#extension GL_GOOGLE_include_directive : require
// Mesh path (src/gl/raster_mesh.cpp): the GL twin of src/cpu/raster_mesh.cpp's
// vertex transform. World position and normal to view space with the camera
// axes of the frame block; the clip position is made so that the viewport
// transform gives the docs/conventions.md#conventions pixel coordinates
// themselves (x = W/2 + f x/w, y = H/2 - f y/w, row 0 at the top: the image is
// drawn upside down in GL's bottom-up framebuffer, so its rows are the image's
// and the driver's fill rule, top-left in framebuffer rows on llvmpipe, is the
// CPU's top-left in image rows), w = eye depth.
// z is 0: no GL near/far clip; the near plane is the clip distance, in view
// space as on the CPU. The eye depth and the normal go to the fragment shader
// interpolated perspective-correctly (GL's default).
#include "frame_params.h"

layout(location = 0) in vec3 aPosition;  // world, metres
layout(location = 1) in vec3 aNormal;    // world, unit, out of the fluid
layout(location = 2) in vec2 aUv;        // texture coordinates (a constant (0, 0) when the mesh has none)

out gl_PerVertex {
    vec4 gl_Position;
    float gl_ClipDistance[1];
};
out float vEyeDepth;
out vec3 vNormal;
out vec2 vUv;

void main() {
    const vec3 d = aPosition - P.eye.xyz;
    const vec3 v = vec3(dot(d, P.right.xyz), dot(d, P.up.xyz), dot(d, P.back.xyz));
    vUv = aUv;
    vNormal = vec3(dot(aNormal, P.right.xyz), dot(aNormal, P.up.xyz), dot(aNormal, P.back.xyz));
    const float w = -v.z;
    vEyeDepth = w;
    const float f = P.right.w;
    gl_Position = vec4(2.0 * f / float(P.size.x) * v.x, -2.0 * f / float(P.size.y) * v.y, 0.0, w);
    gl_ClipDistance[0] = w - P.eye.w;  // eye depth >= near
}
