#version 430 core
// Surface noise (docs/pipeline.md#noise-and-foam; van der Laan, Green & Sainz,
// US 8,947,430, eqs. 14-17) and the velocity whitening map
// (docs/pipeline.md#noise-and-foam; Cords & Staadt 2008, "Instant Liquids" §4)
// on the GPU, the scatter: the GL twin of the sprites of cpu::splatNoise and
// cpu::splatWhitening, one shader for both payloads (uWhitening) as both splat
// the same sprites. The culling of src/cpu/surface_sprites.cpp (in front of the
// near plane, a non-empty sprite, its centre on the image, a weight of at least
// kNoiseMinWeight against the smoothed depth at the centre) and each pixel's
// fixed-point contribution, all by src/shared/surface_noise.h (and
// velocity_map.h), added with atomicAdd (32-bit wrap-around, the CPU's uint
// sums): exact, so the order the GPU runs the particles in does not matter.
// Three passes (uPass):
//  0. One invocation per particle: the culling alone, listing the particles
//     that count (typically a third: those near the surface), with the
//     indirect dispatches of passes 1 and 2. Splatting here would leave the
//     SIMD lanes of the culled particles idle while the others walk their
//     sprites (1.6x slower on llvmpipe for the bench's frame).
//  1. One invocation per listed sprite of up to kMaxPixels pixels, over its
//     rectangle.
//  2. The larger sprites (near the camera), as splat.comp's pass 1: llvmpipe
//     silently stops an invocation's loops after 65,535 iterations in all, and
//     every pixel costs 1 + octaves of them (fractalNoise3's octave loop; 1 for
//     the whitening), so pass 1 walks at most 7 x 4096 = 28,672 and each larger
//     rectangle is spread over kBigGroups x 64 invocations (host-set kBigGroups
//     work groups per listed sprite).
// Passes 1 and 2 recompute a listed particle's sprite and weight from its
// index: the same operations on the same inputs, so the same bits.
// Sums, row-major, row 0 = the TOP row (docs/conventions.md#conventions),
// zeroed beforehand: the noise's W*H; the whitening's 2*W*H, sum(w g whiteness)
// in [0, W*H) and sum(w g) in [W*H, 2*W*H). noise_resolve.comp turns them into
// N or the map.
#extension GL_GOOGLE_include_directive : require
#include "frame_params.h"
#include "surface_noise.h"
#include "velocity_map.h"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { float positions[]; };  // world xyz (Splat's buffer)
layout(std430, binding = 1) buffer Sums { uint sums[]; };
// Per particle: (payload, amplitude); the payload is the noise's idz, or the
// whiteness (amplitude 1) for the whitening.
layout(std430, binding = 2) readonly buffer Attributes { vec2 payloadAmplitude[]; };
// The smoothed depth through a buffer texture (SIMD gathers on llvmpipe).
layout(binding = 0) uniform samplerBuffer depth;  // W*H eye depth, +inf = none

// The indirect dispatches of passes 1 and 2 and their lists (the host sets
// both headers to x = 0 / kBigGroups, y = 0 / 0, z = 1, count = 0 before pass 0).
layout(std430, binding = 4) buffer Lists {
    uint smallX, smallY, smallZ;  // pass 1's work groups: x = ceil(listed / 64), at most kMaxGroups
    uint smallCount;              // listed small sprites
    uint bigX, bigY, bigZ;        // pass 2's work groups: x = kBigGroups, y = listed, at most kMaxGroups
    uint bigCount;                // listed large sprites
    uint lists[];                 // [0, uCount): the small ones' particle indices; [uCount, 2 uCount): the large
};

layout(location = 0) uniform uint uCount;      // particles
layout(location = 1) uniform int uPass;        // 0: culling and lists; 1: the small listed sprites; 2: the large
layout(location = 2) uniform float uNear;      // camera.nearM (the CPU's, not P.eye.w's clamped copy)
layout(location = 3) uniform float uSpriteM;   // spriteRadii * radius (host float, as the CPU)
layout(location = 4) uniform float uFalloffM;  // depthFalloffRadii * radius
layout(location = 5) uniform float uFrequency;
layout(location = 6) uniform int uOctaves;
layout(location = 7) uniform float uLacunarity;
layout(location = 8) uniform float uGain;
layout(location = 9) uniform float uSigma;
layout(location = 10) uniform int uWhitening;  // 0: the noise; 1: the whitening map (uFrequency.. unused)

const int kMaxPixels = 4096;     // largest rectangle one invocation walks in pass 1
const uint kMaxGroups = 65535u;  // the minimum GL_MAX_COMPUTE_WORK_GROUP_COUNT

// The view-space centre of particle i, as binParticles / splat.comp:
// {dot(d, right), dot(d, up), dot(d, back)}, glm::dot's order (x + y) + z.
vec3 viewCentre(uint i) {
    precise vec3 d = vec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]) - P.eye.xyz;
    precise vec3 c = vec3(d.x * P.right.x + d.y * P.right.y + d.z * P.right.z,
                          d.x * P.up.x + d.y * P.up.y + d.z * P.up.z,
                          d.x * P.back.x + d.y * P.back.y + d.z * P.back.z);
    return c;
}

// cpu::findSurfaceSprites step 1: whether particle i splats, and then its sprite and weight.
bool particleSprite(uint i, out NoiseSprite sp, out float weight) {
    const int W = P.size.x, H = P.size.y;
    weight = 0.0;
    const vec3 c = viewCentre(i);
    precise float z = -c.z;
    if (!(z > uNear)) return false;
    sp = noiseSprite(c, P.right.w, W, H, uSpriteM);
    if (sp.rect.x >= sp.rect.z || sp.rect.y >= sp.rect.w) return false;
    const float fx = floor(sp.centre.x), fy = floor(sp.centre.y);
    if (!(fx >= 0.0 && fx < float(W) && fy >= 0.0 && fy < float(H))) return false;  // centre off screen
    const float d = texelFetch(depth, int(fy) * W + int(fx)).x;
    weight = noiseParticleWeight(z, d, P.radius, uFalloffM, payloadAmplitude[i].y);
    return weight >= kNoiseMinWeight;
}

void splatPixel(NoiseSprite sp, int x, int y, float weight, float payload) {
    const int k = y * P.size.x + x;
    if (uWhitening != 0) {
        int white, norm;
        whiteningContribution(sp, x, y, weight, payload, uSigma, white, norm);
        if (white != 0) atomicAdd(sums[k], uint(white));
        if (norm != 0) atomicAdd(sums[P.size.x * P.size.y + k], uint(norm));
        return;
    }
    const int v = noiseContribution(sp, x, y, weight, payload, uFrequency, uOctaves, uLacunarity, uGain, uSigma);
    if (v != 0) atomicAdd(sums[k], uint(v));  // outside the disc: nothing to add
}

void main() {
    NoiseSprite sp;
    float weight;
    if (uPass == 0) {
        // Grid-stride loop: any particle count with a bounded dispatch size.
        for (uint i = gl_GlobalInvocationID.x; i < uCount; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
            if (!particleSprite(i, sp, weight)) continue;
            const int n = (sp.rect.z - sp.rect.x) * (sp.rect.w - sp.rect.y);
            if (n > kMaxPixels) {
                const uint slot = atomicAdd(bigCount, 1u);
                lists[uCount + slot] = i;
                if (slot < kMaxGroups) atomicAdd(bigY, 1u);
            } else {
                const uint slot = atomicAdd(smallCount, 1u);
                lists[slot] = i;
                if (slot % gl_WorkGroupSize.x == 0u && slot / gl_WorkGroupSize.x < kMaxGroups) atomicAdd(smallX, 1u);
            }
        }
    } else if (uPass == 1) {
        // The listed small sprites, one per invocation: lanes of a SIMD vector
        // all have a sprite to walk. One loop over the rectangle's pixels
        // (lanes run as long as the largest rectangle of the vector, not as
        // its tallest times its widest).
        for (uint s = gl_GlobalInvocationID.x; s < smallCount; s += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
            const uint i = lists[s];
            if (!particleSprite(i, sp, weight)) continue;  // listed, so never: the same bits as pass 0's
            const float payload = payloadAmplitude[i].x;
            const ivec4 rect = sp.rect;
            const int n = (rect.z - rect.x) * (rect.w - rect.y);
            int x = rect.x, y = rect.y;
            for (int p = 0; p < n; ++p) {
                splatPixel(sp, x, y, weight, payload);
                const bool wrap = x + 1 == rect.z;
                x = wrap ? rect.x : x + 1;
                y = wrap ? y + 1 : y;
            }
        }
    } else {
        // Work group (gx, gy): listed large sprites gy, gy + kMaxGroups, ...;
        // its invocations take every (bigX * 64)-th pixel of the rectangle.
        const uint stride = bigX * gl_WorkGroupSize.x;
        const uint first = gl_WorkGroupID.x * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
        for (uint s = gl_WorkGroupID.y; s < bigCount; s += kMaxGroups) {
            const uint i = lists[uCount + s];
            if (!particleSprite(i, sp, weight)) continue;  // listed, so never
            const float payload = payloadAmplitude[i].x;
            const ivec4 rect = sp.rect;
            const uint w = uint(rect.z - rect.x), n = w * uint(rect.w - rect.y);
            for (uint p = first; p < n; p += stride)
                splatPixel(sp, rect.x + int(p % w), rect.y + int(p / w), weight, payload);
        }
    }
}
