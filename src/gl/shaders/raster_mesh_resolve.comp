#version 430 core
#extension GL_GOOGLE_include_directive : require
// Mesh path (src/gl/raster_mesh.cpp): copies the draw's targets (drawn upside
// down, so texel row y is image row y) into the depth and normal images the
// later stages read (GpuImage layout: row 0 = the top, W*H and W*H*3 floats).
// Pixels no triangle covered hold the clear values: +inf and (0,0,0); the
// texture coordinates (W*H*2) are copied too when asked for, (0,0) where none.
#include "frame_params.h"

layout(local_size_x = 64) in;

layout(binding = 0) uniform sampler2D uDepth;   // R32F eye depth
layout(binding = 1) uniform sampler2D uNormal;  // RGBA32F view-space normal
layout(std430, binding = 2) writeonly buffer Depth { float depth[]; };
layout(std430, binding = 3) writeonly buffer Normals { float normals[]; };
layout(binding = 2) uniform sampler2D uUv;      // RG32F texture coordinates
layout(std430, binding = 4) writeonly buffer Uvs { float uvs[]; };  // W*H*2, with uWantUv
layout(location = 0) uniform int uWantUv;

void main() {
    const int W = P.size.x, H = P.size.y;
    const int x = int(gl_GlobalInvocationID.x), y = int(gl_GlobalInvocationID.y);
    if (x >= W || y >= H) return;
    const ivec2 texel = ivec2(x, y);
    const int i = y * W + x;
    depth[i] = texelFetch(uDepth, texel, 0).x;
    const vec3 n = texelFetch(uNormal, texel, 0).xyz;
    normals[3 * i] = n.x;
    normals[3 * i + 1] = n.y;
    normals[3 * i + 2] = n.z;
    if (uWantUv != 0) {
        const vec2 t = texelFetch(uUv, texel, 0).xy;
        uvs[2 * i] = t.x;
        uvs[2 * i + 1] = t.y;
    }
}
