#version 430 core
#extension GL_GOOGLE_include_directive : require
// Hole filling (docs/pipeline.md#hole-filling), first step on the GPU: per row
// (uAxis 0) or per column (uAxis 1), one invocation sweeps the line both ways
// and stores for every pixel the steps to the nearest covered pixel before it
// and after it on that line (0 on a covered pixel; 255: none within 254 steps,
// or the image's edge first), packed as before | after << 8. hole_fill.comp
// reads them for its row and column lines instead of walking: the same ends as
// the CPU's scans and sweeps (src/cpu/hole_fill.cpp), so the same fill.
#include "frame_params.h"

layout(local_size_x = 64) in;

layout(binding = 0) uniform samplerBuffer uDepth;  // W*H raw eye depth, +inf = none
layout(std430, binding = 5) buffer RowSteps { uint rowSteps[]; };  // W*H (uAxis 0)
layout(std430, binding = 6) buffer ColumnSteps { uint columnSteps[]; };  // W*H (uAxis 1)

layout(location = 0) uniform int uAxis;

#define kInf uintBitsToFloat(0x7f800000u)

void main() {
    const int W = P.size.x, H = P.size.y;
    const int line = int(gl_GlobalInvocationID.x);
    const int n = uAxis == 0 ? W : H, lines = uAxis == 0 ? H : W;
    if (line >= lines) return;
    int d = 255;
    for (int k = 0; k < n; ++k) {
        const int i = uAxis == 0 ? line * W + k : k * W + line;
        d = texelFetch(uDepth, i).x < kInf ? 0 : min(d + 1, 255);
        if (uAxis == 0) rowSteps[i] = uint(d);
        else columnSteps[i] = uint(d);
    }
    d = 255;
    for (int k = n - 1; k >= 0; --k) {
        const int i = uAxis == 0 ? line * W + k : k * W + line;
        d = texelFetch(uDepth, i).x < kInf ? 0 : min(d + 1, 255);
        if (uAxis == 0) rowSteps[i] |= uint(d) << 8;
        else columnSteps[i] |= uint(d) << 8;
    }
}
