#version 430 core
#extension GL_GOOGLE_include_directive : require
// Normals stage (docs/pipeline.md#normals) on the GPU: the GL twin of
// src/cpu/normals.cpp. The formulas (the exact back-projection, the choice of
// neighbour difference per axis, the normal from the two tangents, turned
// toward the eye) are src/shared/normals.h, the CPU's, `precise` here, so the
// two agree to the rounding of division and sqrt.
// Work: a work group per tile of 64 columns x uRows rows lists the tile's
// fluid pixels in shared memory, then computes the list 64 at a time (main).
#include "frame_params.h"
#include "normals.h"

layout(local_size_x = 64) in;

// The depth through a buffer texture: llvmpipe gathers texel fetches in SIMD
// but reads storage buffers lane by lane (about 5x slower per read).
layout(binding = 0) uniform samplerBuffer uDepth;                           // W*H eye depth, +inf = none
layout(std430, binding = 2) writeonly buffer Normals { float normals[]; };  // W*H*3 view-space unit normals

layout(location = 0) uniform int uRows;  // rows per work group's tile, <= kMaxRows

// A work group's tile: 64 columns x uRows rows.
const int kMaxRows = 16;
shared uint tileList[64 * kMaxRows];  // pixel indices of the tile's fluid pixels
shared uint tileCount;

#define kInf uintBitsToFloat(0x7f800000u)

int W, H;

// Depth at (x, y), +inf outside the image.
float depthAt(int x, int y) {
    return x >= 0 && x < W && y >= 0 && y < H ? texelFetch(uDepth, y * W + x).x : kInf;
}

void main() {
    W = P.size.x;
    H = P.size.y;
    const uint lid = gl_LocalInvocationID.x;
    // 1. List this tile's fluid pixels; the others already hold (0,0,0) (a
    // driver fill before the dispatch). llvmpipe runs both sides of a divergent
    // branch under a mask, so an `if (fluid) normalAt` would cost the full
    // computation for every pixel; a loop over the list costs it only per
    // fluid pixel.
    if (lid == 0u) tileCount = 0u;
    barrier();
    const int x = int(gl_GlobalInvocationID.x);
    const int y0 = int(gl_WorkGroupID.y) * uRows;
    if (x < W) {
        const int yEnd = min(y0 + uRows, H);
        for (int y = y0; y < yEnd; ++y) {
            const uint k = uint(y) * uint(W) + uint(x);
            if (texelFetch(uDepth, int(k)).x < kInf) tileList[atomicAdd(tileCount, 1u)] = k;
        }
    }
    barrier();
    // 2. The normals of the listed pixels, 64 at a time.
    const float f = P.right.w;
    precise float jump = P.normalsJumpRadii * P.radius;
    precise float halfW = 0.5 * float(W), halfH = 0.5 * float(H);
    const uint n = tileCount;
    for (uint base = 0u; base < n; base += gl_WorkGroupSize.x) {
        const uint i = base + lid;
        if (i < n) {
            const uint k = tileList[i];
            const int px = int(k % uint(W)), py = int(k / uint(W));
            // Rays per column and row as the CPU's tables.
            const float rxc = normalsRayX(px, halfW, f), rxl = normalsRayX(px - 1, halfW, f);
            const float rxr = normalsRayX(px + 1, halfW, f), ryc = normalsRayY(py, halfH, f);
            const float ryu = normalsRayY(py - 1, halfH, f), ryd = normalsRayY(py + 1, halfH, f);
            const vec3 nrm = normalsAt(texelFetch(uDepth, int(k)).x, depthAt(px - 1, py), depthAt(px + 1, py), depthAt(px, py - 1),
                                      depthAt(px, py + 1), rxc, rxl, rxr, ryc, ryu, ryd, jump);
            normals[3 * k + 0] = nrm.x;
            normals[3 * k + 1] = nrm.y;
            normals[3 * k + 2] = nrm.z;
        }
    }
}
