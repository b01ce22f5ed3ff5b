#version 430 core
// Spray drops (docs/pipeline.md#classification, docs/pipeline.md#noise-and-foam;
// the NVIDIA SSFR patent, US 8,947,430, draws the particles that left the body
// of water as spray particles) on the GPU, the scatter: the GL twin of
// cpu::drawSpray's per-pixel sums. The drops come projected from the host
// (shared::sprayDrop, the CPU's code), culled to those with pixels on screen;
// each pixel of a drop's rectangle in front of the fluid and the scene gets its
// fixed-point optical depth (sprayContribution, src/shared/spray.h) by atomicAdd
// (32-bit wrap-around, the CPU's uint sums): exact, so the order the GPU runs
// the drops in does not matter.
// The work comes cut into items of uChunk pixels of one drop's rectangle
// (row-major), one item per invocation: the lanes of a SIMD vector walk about
// the same number of pixels however unlike their drops are (specks, long
// streaks, a drop at the camera: one invocation per drop, as noise_splat.comp's
// pass 1, ran 3-4x slower on llvmpipe with streaks), and no invocation walks
// past llvmpipe's cap of 65,535 loop iterations (it silently stops there).
// Sums: W*H, row-major, row 0 = the TOP row (docs/conventions.md#conventions),
// zeroed beforehand; spray_resolve.comp turns them into cover.
#extension GL_GOOGLE_include_directive : require
#include "spray.h"

layout(local_size_x = 64) in;

// The drops, shared::SprayDrop in std430 (48 bytes: gl::SprayDrops::Packed).
layout(std430, binding = 0) readonly buffer Drops { SprayDrop drops[]; };
layout(std430, binding = 1) buffer Sums { uint sums[]; };
// The work items: (drop, the item's first pixel in its rectangle, row-major).
layout(std430, binding = 2) readonly buffer Items { uvec2 items[]; };
// The depths through buffer textures (SIMD gathers on llvmpipe).
layout(binding = 0) uniform samplerBuffer depth;       // W*H fluid eye depth, +inf = none
layout(binding = 1) uniform samplerBuffer sceneDepth;  // W*H scene eye depth, +inf = none (when uHasScene)

layout(location = 0) uniform ivec2 uSize;    // W, H
layout(location = 1) uniform int uHasScene;  // the scene depth is bound (camera-sized)
layout(location = 2) uniform uint uItems;    // work items
layout(location = 3) uniform uint uChunk;    // pixels per item (the last of a drop's may have fewer)

void splatPixel(SprayDrop d, int x, int y) {
    const int k = y * uSize.x + x;
    // Hidden behind the fluid or the scene (+inf where none), as the CPU.
    if (!(d.z < texelFetch(depth, k).x)) return;
    if (uHasScene != 0 && !(d.z < texelFetch(sceneDepth, k).x)) return;
    const int v = sprayContribution(d, x, y);
    if (v != 0) atomicAdd(sums[k], uint(v));  // outside the capsule: nothing to add
}

void main() {
    // Grid-stride loop (the host keeps it to one round: gl::SprayDrops).
    for (uint it = gl_GlobalInvocationID.x; it < uItems; it += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        const uvec2 item = items[it];
        const SprayDrop d = drops[item.x];
        const ivec4 rect = d.rect;
        const int w = rect.z - rect.x;
        const int first = int(item.y), end = min((rect.w - rect.y) * w, first + int(uChunk));
        int x = rect.x + first % w, y = rect.y + first / w;
        for (int p = first; p < end; ++p) {
            splatPixel(d, x, y);
            const bool wrap = x + 1 == rect.z;
            x = wrap ? rect.x : x + 1;
            y = wrap ? y + 1 : y;
        }
    }
}
