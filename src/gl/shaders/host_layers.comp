#version 430 core
#extension GL_GOOGLE_include_directive : require
// The embedding's scene layer (src/gl/host_layers.cpp): a host application's
// colour and depth textures (row 0 = the BOTTOM row, as GL has them) into the
// scene stage's colour (linear RGBA) and eye depth (metres, +inf: nothing),
// row 0 = the TOP row as every image of the pipeline. The CPU reads a
// backdrop of kind window:NEAR,FAR with the same shared::backdropEyeDepth
// (src/core/backdrop_layer.cpp) and decodes 8-bit sRGB with the same table.
#include "backdrop.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform sampler2D uHostColor;
layout(binding = 1) uniform sampler2D uHostDepth;
layout(std430, binding = 1) writeonly buffer SceneColor { vec4 sceneColor[]; };
layout(std430, binding = 2) writeonly buffer SceneDepth { float sceneDepth[]; };
layout(std430, binding = 3) readonly buffer Decode { float srgbToLinear[256]; };

layout(location = 0) uniform ivec3 uSize;   // W, H, and 1 when the colour holds 8-bit sRGB codes
layout(location = 1) uniform vec2 uPlanes;  // the camera's near and far planes, metres

float decoded(float code) { return srgbToLinear[int(clamp(code, 0.0, 1.0) * 255.0 + 0.5)]; }

void main() {
    const int x = int(gl_GlobalInvocationID.x), y = int(gl_GlobalInvocationID.y);
    const int W = uSize.x, H = uSize.y;
    if (x >= W || y >= H) return;
    const ivec2 texel = ivec2(x, H - 1 - y);
    vec3 c = texelFetch(uHostColor, texel, 0).rgb;
    if (uSize.z != 0) c = vec3(decoded(c.r), decoded(c.g), decoded(c.b));
    const float raw = texelFetch(uHostDepth, texel, 0).r;
    const int i = y * W + x;
    sceneColor[i] = vec4(c, 1.0);
    sceneDepth[i] = backdropEyeDepth(raw, kBackdropWindow, 1.0, uPlanes.x, uPlanes.y);  // window depth needs no ray
}
