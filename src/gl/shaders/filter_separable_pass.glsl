// One 1-D pass (x or y) of the separable depth filters
// (docs/pipeline.md#smoothing), the GPU twin of cpu::detail::filterLine
// (src/cpu/filter_separable.h): per centre pixel the kernel radius
// s = kernelPxDepth / z0 (a world length projected at the centre depth,
// capped), weights from the CPU's own normalised tables blended between integer
// radii, taps that are +inf or further than jumpM from z0 dropped and the rest
// renormalised; those formulas are src/shared/separable_filter.h, the CPU's.
// Included by filter_separable.comp (Gaussian, binomial: no range weight) and
// filter_separable_bilateral.comp (MENISCUS_BILATERAL: the CPU's
// RangeGaussian).
// Parity: the CPU sums the taps -m .. m (m = n + 1) in groups of kLanes = 4,
// one accumulator per lane, and adds the lanes in order at the end; here a
// group is a vec4 (its weights one texel of the table, laid out per radius in
// group order), so every sum sees the same operands in the same order, and
// all arithmetic is `precise` (no FMA contraction or reassociation). Taps the
// CPU excludes (no fluid, off the image, across a jump) add exact zeros there;
// here they are selected away, so +inf needs no finite stand-in.
// Work: one invocation per pixel of a row segment of 64, kRows rows per
// invocation (llvmpipe pays per work group); the lanes of a work group read
// neighbouring pixels of one row for every tap, in both passes.
#include "separable_filter.h"

layout(local_size_x = 64) in;

layout(binding = 0) uniform samplerBuffer uSrc;    // R32F view of the source image
// RGBA32F: for radius n, group j (taps -m + 4j .. -m + 4j + 3): texel
// 2 (n * uGroups + j) = the CPU's row(n) there, the next texel diff(n).
layout(binding = 1) uniform samplerBuffer uTable;
layout(std430, binding = 1) writeonly buffer Dst { float dst[]; };

layout(location = 0) uniform ivec2 uSize;          // W, H
layout(location = 1) uniform int uAxis;            // 0: x pass (taps along a row), 1: y pass
layout(location = 2) uniform float uKernelPxDepth; // kernelWorldM * focalPx, rounded on the CPU as there
layout(location = 3) uniform float uJumpM;         // jumpRadii * r
layout(location = 4) uniform int uMaxRadius;       // table.maxRadius()
layout(location = 5) uniform int uGroups;          // groups per table radius: (2 (maxRadius + 1) + 4) / 4
#ifdef MENISCUS_BILATERAL
layout(location = 6) uniform float uRangeScale;    // 1 / (2 sigma^2 ln 2), as RangeGaussian's scale_
#endif

const int kRows = 16;  // pixels per invocation
// (Macros: a bit cast is not a constant expression for a global const.)
#define kNoFluid uintBitsToFloat(0x7f7fffffu)  // FLT_MAX: the CPU's finite stand-in for no fluid
#define kInf uintBitsToFloat(0x7f800000u)

#ifdef MENISCUS_BILATERAL
// RangeGaussian::operator() of the CPU, four taps at a time: exp(-dz^2 / (2
// sigma^2)) as 2^-x, the integer part from the exponent bits, the rest by
// shared::separableRangeWeight. Only the weights of included taps (|dz| <=
// jump, finite) are used.
vec4 rangeWeight(vec4 dz) {
    precise vec4 x = separableRangeExponent(dz, uRangeScale);
    x = mix(vec4(kSeparableRangeCap), x, lessThan(x, vec4(kSeparableRangeCap)));  // x < 60 ? x : 60 (NaN -> 60)
    const ivec4 i = ivec4(x);                                                      // x >= 0: truncation = floor
    const vec4 pow2 = intBitsToFloat((127 - i) << 23);
    return separableRangeWeight(x, vec4(i), pow2);
}
#endif

// The taps of one pixel, group by group. `checked`: some tap may be off the
// image (a constant argument, so each call is compiled without or with the test).
void accumulate(const bool checked, int idx, int pos, int len, int step, float z0, int m, float t, int tableBase,
                inout vec4 sw, inout vec4 sd) {
    const int groups = (2 * m + 4) / 4;  // ceil((2 m + 1) / 4)
    for (int j = 0; j < groups; ++j) {
        const int k0 = 4 * j - m;
        vec4 v;
        for (int l = 0; l < 4; ++l) {
            const int k = k0 + l;
            if (checked) {
                const int p = pos + k;
                v[l] = (p >= 0 && p < len) ? texelFetch(uSrc, idx + k * step).x : kInf;
            } else {
                v[l] = texelFetch(uSrc, idx + k * step).x;
            }
        }
        const vec4 a = texelFetch(uTable, tableBase + 2 * j), d = texelFetch(uTable, tableBase + 2 * j + 1);
        precise vec4 dz = v - z0;
        const bvec4 ok = lessThanEqual(abs(dz), vec4(uJumpM));  // false for +inf / NaN taps
#ifdef MENISCUS_BILATERAL
        precise vec4 w = separableSpatialWeight(a, d, t) * rangeWeight(dz);
#else
        precise vec4 w = separableSpatialWeight(a, d, t);
#endif
        precise vec4 wdz = w * dz;
        sw += mix(vec4(0.0), w, ok);
        sd += mix(vec4(0.0), wdz, ok);
    }
}

void main() {
    const int W = uSize.x, H = uSize.y;
    const int x = int(gl_GlobalInvocationID.x);
    if (x >= W) return;
    const int len = uAxis == 0 ? W : H;
    const int step = uAxis == 0 ? 1 : W;  // index distance of neighbouring taps
    const float maxS = float(uMaxRadius);
    for (int y = int(gl_WorkGroupID.y) * kRows; y < H; y += int(gl_NumWorkGroups.y) * kRows) {
        for (int r = 0; r < kRows && y + r < H; ++r) {
            const int row = y + r;
            const int idx = row * W + x;
            const int pos = uAxis == 0 ? x : row;  // the pixel's place along its line
            const float z0 = texelFetch(uSrc, idx).x;
            // toLine: +inf / NaN / FLT_MAX are no fluid and stay +inf.
            if (!(z0 < kNoFluid)) {
                dst[idx] = kInf;
                continue;
            }
            const float s = separableKernelPx(uKernelPxDepth, z0, maxS);
            const int n = int(s);
            const float t = separableBlend(s, n);
            const int m = n + 1;
            const int tableBase = 2 * n * uGroups;
            precise vec4 sw = vec4(0.0), sd = vec4(0.0);
            // Every tap of every group (the last one rounded up) on the image: no test per tap.
            if (pos - m >= 0 && pos - m + 4 * ((2 * m + 4) / 4) <= len)
                accumulate(false, idx, pos, len, step, z0, m, t, tableBase, sw, sd);
            else
                accumulate(true, idx, pos, len, step, z0, m, t, tableBase, sw, sd);
            dst[idx] = separableResult(z0, sw, sd);
        }
    }
}
