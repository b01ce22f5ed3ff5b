#version 430 core
// Reduced-resolution processing (docs/pipeline.md#reduced-resolution): the full
// scene depth reduced to the low camera, per low pixel the farthest depth of
// the full pixels it covers (shared/upsample.h: lowPixelSpan). The GL twin of
// cpu::reduceSceneDepth; max of exact values, so the same bits.
#extension GL_GOOGLE_include_directive : require
#include "upsample.h"

layout(local_size_x = 64) in;

layout(binding = 0) uniform samplerBuffer fullDepth;             // W*H eye depth
layout(std430, binding = 0) writeonly buffer Low { float low[]; };  // lw*lh

layout(location = 0) uniform ivec2 uFull;  // W, H
layout(location = 1) uniform ivec2 uLow;   // lw, lh
layout(location = 2) uniform int uD;       // divisor

void main() {
    const int W = uFull.x, H = uFull.y, lw = uLow.x, lh = uLow.y;
    const uint pixels = uint(lw) * uint(lh);
    for (uint k = gl_GlobalInvocationID.x; k < pixels; k += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        const int i = int(k % uint(lw)), j = int(k / uint(lw));
        const ivec2 xs = lowPixelSpan(i, W, lw, uD), ys = lowPixelSpan(j, H, lh, uD);
        float z = 0.0;
        for (int y = ys.x; y < ys.y; ++y)
            for (int x = xs.x; x < xs.y; ++x) z = max(z, texelFetch(fullDepth, y * W + x).x);
        low[k] = z;
    }
}
