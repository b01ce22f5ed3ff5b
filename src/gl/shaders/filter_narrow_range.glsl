// One pass of the narrow-range filter: N. Truong and C. Yuksel, "A Narrow-Range
// Filter for Screen-Space Fluid Rendering", Proc. ACM Comput. Graph. Interact.
// Tech. 1(1) (I3D 2018), as restated in docs/pipeline.md#narrow-range-filter --
// the GPU twin of filterN and pass() in src/cpu/filter_narrow_range.cpp, which
// documents the procedure (mirror tap pairs centre outward, front taps drop the
// pair, behind taps count as z0 + mu·r, inside taps widen the range,
// Gaussian σ = R/3) and its choices. Every operation follows the CPU in the
// same order and is `precise` (no FMA contraction or reassociation); the
// Gaussian weights are the CPU's (computed in double on the host), so the two
// agree to the last bit in practice. Buffers: depth padded by uPad >= any
// kernel radius with −inf (taps outside the image are "in front"). Reads and
// writes go through buffer textures / image buffers: llvmpipe vectorises those,
// SSBO accesses run lane by lane. Work: only the 8-pixel row segments that hold
// fluid (fluid_segments.glsl). Pixels outside them keep their value, which both
// ping-pong buffers and the output already hold.
// Included by filter_narrow_range_2d.comp and _1d.comp, which set kTwoD: two
// programs, as llvmpipe would run the unused kernel's code masked as well.
#include "frame_params.h"
#include "kernel_radius.h"  // projectedRadiusPx, as the CPU's

layout(local_size_x = 64) in;

layout(binding = 0) uniform samplerBuffer src;       // padded depth (R32F)
layout(binding = 1) uniform isamplerBuffer taps;     // 2-D: linear offsets sorted centre outward
layout(binding = 2) uniform samplerBuffer weights;   // gaussian(d², R) at weightBase(R) + d²
layout(binding = 3) uniform isamplerBuffer meta;     // [R]: 2-D rings of radius R; [uCap + 1 + R]: weightBase(R)
layout(binding = 4) uniform isamplerBuffer rings;    // 2-D: per distinct d², (end tap index, d²)
layout(binding = 5) uniform isamplerBuffer uSegments;  // the fluid segments (fluid_segments.glsl)
#include "fluid_segments.glsl"
layout(r32f, binding = 0) writeonly uniform imageBuffer dst;  // padded, or the W x H output (uFinal)
layout(std430, binding = 5) readonly buffer ZMin { uint zMinBits; };  // nearest input depth

layout(location = 0) uniform ivec2 uSize;  // W, H of the image (unpadded)
layout(location = 1) uniform int uPad;     // frame width = uCap
layout(location = 2) uniform int uCap;     // min(maxKernelPx, max(W, H)): the tables' largest radius
layout(location = 3) uniform int uStep;    // 1-D: taps k·uStep (1: x, padded width: y)
layout(location = 4) uniform int uFinal;   // 1: write the unpadded W x H output


// One mirror pair (a, b) of weight w: the body of the CPU's filterN loop.
void accumulate(float a, float b, float w, float z0, float tau, float behind, inout float lower, inout float upper,
                inout float sum, inout float wsum) {
    const bool frontA = a < lower, frontB = b < lower;
    const bool behindA = a > upper, behindB = b > upper;
    precise float da = behindA ? behind : a - z0;
    precise float db = behindB ? behind : b - z0;
    // A tap in front drops the pair (keeps the mean unbiased).
    if (!(frontA || frontB)) {
        precise float s = sum + w * (da + db);
        precise float ws = wsum + w;
        sum = s;
        wsum = ws;
    }
    // Range extension by inside taps (both classified against the old range).
    precise float la = frontA ? lower : a - tau, lb = frontB ? lower : b - tau;
    precise float ua = behindA ? upper : a + tau, ub = behindB ? upper : b + tau;
    precise float lo = la < lower ? la : lower;
    lo = lb < lo ? lb : lo;
    precise float hi = ua > upper ? ua : upper;
    hi = ub > hi ? ub : hi;
    lower = lo;
    upper = hi;
}

void main() {
    const int W = uSize.x, PW = W + 2 * uPad;
    const float kInf = uintBitsToFloat(0x7f800000u);
    const float f = P.right.w;
    precise float world = P.nrFilterSizeRadii * P.radius;
    precise float tau = P.nrLambda * P.radius;
    precise float behind = P.nrMu * P.radius;
    // The kernel radius at the nearest input depth bounds every pixel's (the
    // filtered depth never gets nearer), as on the CPU.
    const float zMin = uintBitsToFloat(zMinBits);
    const int Rmax = zMin < kInf ? projectedRadiusPx(world, f, zMin, uCap) : 0;

    for (int k = 0; k < uSegmentRounds; ++k) {
        int x, y;
        const int on = segmentPixel(k, W, x, y);
        if (on < 0) break;
        if (on == 0) continue;
        const int c = (y + uPad) * PW + x + uPad;
        const float z0 = texelFetch(src, c).x;
        float result = z0;  // +inf, or a kernel under one pixel: unchanged
        const int R = z0 < kInf ? projectedRadiusPx(world, f, z0, Rmax) : 0;
        if (R > 0) {
            const int n = texelFetch(meta, R).x;  // 2-D: rings of radius R's disc
            const int wBase = texelFetch(meta, uCap + 1 + R).x;
            precise float lower = z0 - tau, upper = z0 + tau;
            precise float sum = 0.0;   // deviations from z0; the centre adds weight 1, deviation 0
            precise float wsum = 0.0;  // over pairs (each tap of a pair has weight w)
            if (kTwoD) {
                // 2-D: the disc's taps ring by ring (equal d², so one weight
                // fetch per ring); the first n rings are radius R's disc.
                int t = 0;
                for (int g = 0; g < n; ++g) {
                    const ivec2 ring = texelFetch(rings, g).xy;  // (end tap, d²)
                    const float w = texelFetch(weights, wBase + ring.y).x;
                    for (; t < ring.x; ++t) {
                        const int off = texelFetch(taps, t).x;
                        accumulate(texelFetch(src, c + off).x, texelFetch(src, c - off).x, w, z0, tau, behind, lower,
                                   upper, sum, wsum);
                    }
                }
            } else {
                for (int k = 1; k <= R; ++k) {
                    const int off = k * uStep;
                    const float w = texelFetch(weights, wBase + k * k).x;
                    accumulate(texelFetch(src, c + off).x, texelFetch(src, c - off).x, w, z0, tau, behind, lower,
                               upper, sum, wsum);
                }
            }
            precise float mean = z0 + sum / (2.0 * wsum + 1.0);
            result = mean;
        }
        imageStore(dst, uFinal != 0 ? y * W + x : c, vec4(result));
    }
}
