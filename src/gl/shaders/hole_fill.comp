#version 430 core
#extension GL_GOOGLE_include_directive : require
// Hole filling (docs/pipeline.md#hole-filling) on the GPU: the GL twin of
// src/cpu/hole_fill.cpp. An uncovered pixel that liquid of one surface closes
// in along its row, its column and both diagonals (nearest covered pixels
// within uMaxPx steps each way, on one surface: at most uJumpRadii r apart in
// depth plus a slanted sheet's climb; on three of the lines at most
// uSpanRadii r apart) takes the
// four lines' mean interpolated depth, and the larger of its thickness and
// theirs; never behind the scene. The rule and every formula are
// src/shared/hole_fill.h, the CPU's; the lines are visited in its order.
// Work: one invocation per pixel (x = column, y = row), every pixel written.
// The row and the column take their ends from hole_fill_sweep.comp's steps;
// only the diagonals walk, and only where the row or the column is narrow
// (llvmpipe, frame 21 at 1280x720: 182 ms walking every line, 2 passes).
#include "frame_params.h"
#include "hole_fill.h"

layout(local_size_x = 64) in;

layout(binding = 0) uniform samplerBuffer uDepth;      // W*H raw eye depth, +inf = none
layout(binding = 1) uniform samplerBuffer uThickness;  // W*H metres (when uHas.x != 0)
layout(binding = 2) uniform samplerBuffer uScene;      // W*H scene eye depth (when uHas.y != 0)
layout(std430, binding = 3) writeonly buffer OutDepth { float outDepth[]; };
// Steps to the nearest covered pixel before | after << 8 along the row and
// the column (hole_fill_sweep.comp): the row and column lines without a walk.
layout(std430, binding = 5) readonly buffer RowSteps { uint rowSteps[]; };
layout(std430, binding = 6) readonly buffer ColumnSteps { uint columnSteps[]; };
layout(std430, binding = 4) writeonly buffer OutThickness { float outThickness[]; };

layout(location = 0) uniform float uSpanRadii;
layout(location = 1) uniform float uJumpRadii;
layout(location = 2) uniform int uMaxPx;
layout(location = 3) uniform ivec2 uHas;  // thickness, scene

#define kInf uintBitsToFloat(0x7f800000u)

int W, H;

// The nearest covered pixel from (x, y) along (dx, dy), at most uMaxPx steps:
// its steps (0: none), depth and thickness.
int walk(int x, int y, int dx, int dy, out float z, out float t) {
    z = kInf;
    t = 0.0;
    for (int i = 1; i <= uMaxPx; ++i) {
        const int xx = x + i * dx, yy = y + i * dy;
        if (xx < 0 || xx >= W || yy < 0 || yy >= H) break;
        const int j = yy * W + xx;
        const float zz = texelFetch(uDepth, j).x;
        if (zz < kInf) {
            z = zz;
            t = uHas.x != 0 ? texelFetch(uThickness, j).x : 0.0;
            return i;
        }
    }
    return 0;
}

void main() {
    W = P.size.x;
    H = P.size.y;
    const int x = int(gl_GlobalInvocationID.x), y = int(gl_GlobalInvocationID.y);
    if (x >= W || y >= H) return;
    const int i = y * W + x;
    const float z0 = texelFetch(uDepth, i).x;
    const float t0 = uHas.x != 0 ? texelFetch(uThickness, i).x : 0.0;
    float zOut = z0, tOut = t0;
    if (!(z0 < kInf)) {
        float zs[4], ts[4];
        bool closed = true;
        int narrow = 0;
        for (int k = 0; k < 4 && closed; ++k) {
            const int dx = holeLineDx(k), dy = holeLineDy(k);
            float za = kInf, ta = 0.0, zb = kInf, tb = 0.0;
            int a, b;
            if (k < 2) {
                const uint s = k == 0 ? rowSteps[i] : columnSteps[i];
                const int before = int(s & 255u), after = int(s >> 8);
                a = before <= uMaxPx ? before : 0;
                b = after <= uMaxPx ? after : 0;
                if (a != 0 && b != 0) {
                    const int ia = i - a * (dy * W + dx), ib = i + b * (dy * W + dx);
                    za = texelFetch(uDepth, ia).x;
                    zb = texelFetch(uDepth, ib).x;
                    ta = uHas.x != 0 ? texelFetch(uThickness, ia).x : 0.0;
                    tb = uHas.x != 0 ? texelFetch(uThickness, ib).x : 0.0;
                }
            } else if (narrow == 0) {  // row and column both long: three narrow lines are out of reach
                closed = false;
                break;
            } else {
                a = walk(x, y, -dx, -dy, za, ta);
                b = a != 0 ? walk(x, y, dx, dy, zb, tb) : 0;
            }
            if (a == 0 || b == 0) {
                closed = false;
                break;
            }
            zs[k] = holeInterpolate(za, zb, a, b);
            ts[k] = holeInterpolate(ta, tb, a, b);
            const float len = holeLineLengthPx(a, b, k >= 2);
            closed = holeLineSameSurface(za, zb, zs[k], len, P.radius, P.right.w, uJumpRadii);
            narrow += holeLineNarrow(zs[k], len, P.radius, P.right.w, uSpanRadii) ? 1 : 0;
        }
        if (closed && narrow >= kHoleNarrowLines) {
            const float z = holeMean(zs[0], zs[1], zs[2], zs[3]);
            if (uHas.y == 0 || z < texelFetch(uScene, i).x) {
                zOut = z;
                tOut = max(t0, holeMean(ts[0], ts[1], ts[2], ts[3]));
            }
        }
    }
    outDepth[i] = zOut;
    if (uHas.x != 0) outThickness[i] = tOut;
}
