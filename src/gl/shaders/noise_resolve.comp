#version 430 core
// Surface noise (docs/pipeline.md#noise-and-foam; van der Laan, Green & Sainz,
// US 8,947,430, eqs. 16-17) on the GPU, per fluid pixel after noise_splat.comp:
// the fixed-point sums become N (cpu::splatNoise's output; the host fills 0
// beforehand, what the pixels without fluid keep), and the normals are bumped
// in place by N's gradient exactly as cpu::bumpNormals
// (src/cpu/surface_noise.cpp), through the formulas of
// src/shared/surface_noise.h. The neighbours' N are read from their sums
// (noiseFromFixed of the same int), as only a neighbour of the same surface
// (fluid, its depth within the jump) counts. Work: only the 8-pixel row
// segments with fluid (fluid_segments.glsl, listed from the depth). With
// uWhitening (the velocity whitening map, docs/pipeline.md#noise-and-foam;
// Cords & Staadt 2008, "Instant Liquids" §4) the sums are the whitening's two
// (2*W*H) and each fluid pixel gets their ratio, whiteningFromFixed, as
// cpu::splatWhitening; no normals are touched.
#extension GL_GOOGLE_include_directive : require
#include "frame_params.h"
#include "surface_noise.h"
#include "velocity_map.h"

layout(local_size_x = 64) in;

// Buffer textures and image buffers: llvmpipe gathers and scatters those in
// SIMD but runs storage-buffer accesses lane by lane.
layout(binding = 0) uniform samplerBuffer depth;  // W*H eye depth, +inf = none
layout(binding = 1) uniform isamplerBuffer sums;  // W*H (whitening: 2*W*H) fixed-point sums (noise_splat.comp)
// W*H*3 view space (R32F), bumped in place: each invocation loads and stores its own pixel only.
layout(r32f, binding = 0) uniform imageBuffer normals;
layout(r32f, binding = 1) writeonly uniform imageBuffer noiseOut;  // W*H N or the map (0 beforehand)
layout(binding = 2) uniform isamplerBuffer uSegments;  // the fluid segments (fluid_segments.glsl)
#include "fluid_segments.glsl"

layout(location = 1) uniform int uBumpNormals;  // the normals are W x H x 3: bump them
layout(location = 2) uniform float uJump;       // kDepthJumpRadii * radius (host float, as the CPU)
layout(location = 3) uniform float uSpriteF;    // spriteRadii * radius * focalPx (host, the CPU's order)
layout(location = 4) uniform float uBump;
layout(location = 5) uniform int uWhitening;  // the whitening's two sums: write their ratio, nothing else

#define kInf uintBitsToFloat(0x7f800000u)

int W, H;

// The CPU's `same`: neighbour (x, y) is in the image and of the surface at depth z.
bool sameSurface(int x, int y, float z) {
    if (x < 0 || x >= W || y < 0 || y >= H) return false;
    precise float dz = texelFetch(depth, y * W + x).x - z;
    return abs(dz) <= uJump;
}

// N of a neighbour, 0 unless it counts (the CPU's `at`).
float neighbourNoise(int x, int y, bool ok) {
    return ok ? noiseFromFixed(texelFetch(sums, y * W + x).x) : 0.0;
}

void main() {
    W = P.size.x;
    H = P.size.y;
    // Only the 8-pixel row segments with fluid: every other pixel's N is
    // already 0 (a driver fill) and its normal is left as it is.
    for (int r = 0; r < uSegmentRounds; ++r) {
        int x, y;
        const int on = segmentPixel(r, W, x, y);
        if (on < 0) break;
        if (on == 0) continue;
        const int k = y * W + x;
        const float z = texelFetch(depth, k).x;
        if (!(z < kInf)) continue;
        if (uWhitening != 0) {
            imageStore(noiseOut, k, vec4(whiteningFromFixed(texelFetch(sums, k).x, texelFetch(sums, W * H + k).x)));
            continue;
        }
        const float n0 = noiseFromFixed(texelFetch(sums, k).x);
        imageStore(noiseOut, k, vec4(n0));
        if (uBumpNormals == 0) continue;
        const bool okl = sameSurface(x - 1, y, z), okr = sameSurface(x + 1, y, z);
        const bool oku = sameSurface(x, y - 1, z), okd = sameSurface(x, y + 1, z);
        const float dx = noiseDerivative(neighbourNoise(x - 1, y, okl), n0, neighbourNoise(x + 1, y, okr), okl, okr);
        const float dy = noiseDerivative(neighbourNoise(x, y - 1, oku), n0, neighbourNoise(x, y + 1, okd), oku, okd);
        precise float spritePx = uSpriteF / z;
        const int i = 3 * k;
        const vec3 n = vec3(imageLoad(normals, i).x, imageLoad(normals, i + 1).x, imageLoad(normals, i + 2).x);
        const vec3 o = noisePerturbedNormal(n, dx, dy, spritePx, uBump);
        imageStore(normals, i, vec4(o.x));
        imageStore(normals, i + 1, vec4(o.y));
        imageStore(normals, i + 2, vec4(o.z));
    }
}
