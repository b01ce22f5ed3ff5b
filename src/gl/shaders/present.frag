#version 430 core
#extension GL_GOOGLE_include_directive : require
// The present pass (src/gl/present.cpp): copies the backend's final colour
// (linear RGBA floats, row 0 = the TOP row, as every GpuImage) into the
// window's default framebuffer or an embedding host's (row 0 = the BOTTOM row), encoded to 8-bit sRGB
// exactly as the PNG writer does: clamp, the transfer function of
// src/shared/srgb.h, rounding to the nearest of the 256 levels (so the 8-bit
// framebuffer stores the level as is). Alpha is dropped: a window shows RGB.
#include "srgb.h"

layout(std430, binding = 0) readonly buffer Color { vec4 color[]; };  // W*H linear RGBA

// x, y = the image's width and height; z = the framebuffer's height; w = the
// image's left edge in the framebuffer, pixels.
layout(location = 0) uniform ivec4 uSize;
// 1: encode to 8-bit sRGB levels (an 8-bit target); 0: write the linear
// values as they are (a float target: an embedding host's HDR frame).
layout(location = 1) uniform int uSrgb;

layout(location = 0) out vec4 fragColor;

float level(float linear) { return floor(srgbEncode(linear) * 255.0 + 0.5) / 255.0; }

void main() {
    const int x = int(gl_FragCoord.x) - uSize.w;
    const int y = uSize.z - 1 - int(gl_FragCoord.y);  // the image's top-left at (left, top) of the window
    if (x < 0 || x >= uSize.x || y < 0 || y >= uSize.y) {
        fragColor = vec4(0.0, 0.0, 0.0, 1.0);  // outside the image (a resize not rendered yet)
        return;
    }
    const vec4 c = color[y * uSize.x + x];
    fragColor = uSrgb != 0 ? vec4(level(c.r), level(c.g), level(c.b), 1.0) : vec4(c.rgb, 1.0);
}
