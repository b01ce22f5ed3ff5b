#version 430 core
#extension GL_GOOGLE_include_directive : require
// One 1-D pass (x or y) of the thickness blur (docs/pipeline.md#thickness;
// thesis §4.1.3), the GPU twin of blurLine in src/cpu/thickness.cpp at full
// resolution: a Gaussian whose sigma is constant in world space, projected with
// the raw fluid depth of the centre pixel. Kernel radius R = ceil(3 sigma_px)
// in whole pixels (capped), weights from the CPU's table row R (sigma = R / 3).
// Pixels with no fluid in the raw depth (R = 0) are copied; taps off the image
// are left out and the remaining weights renormalised.
// Parity: the CPU sums the taps -R .. R in groups of 4, one accumulator per
// lane, added as (l0 + l1) + (l2 + l3); here a group is a vec4 (its weights
// one texel of the table) with the same pairing, and all arithmetic is
// `precise`. Off-image taps multiply the CPU's zero padding, exact zeros.
// Work: only the 8-pixel row segments with fluid in the raw depth
// (fluid_segments.glsl); the host has copied the source into the destination,
// so the other pixels (no fluid: copied) already hold their result.
layout(local_size_x = 64) in;

layout(binding = 0) uniform samplerBuffer uSrc;    // R32F view of the source thickness
layout(binding = 1) uniform samplerBuffer uTable;  // RGBA32F: radius R, group j at R * uGroups + j
layout(std430, binding = 1) writeonly buffer Dst { float dst[]; };
layout(std430, binding = 3) readonly buffer RawDepth { float rawDepth[]; };
layout(binding = 2) uniform isamplerBuffer uSegments;  // fluid segments of the raw depth
#include "fluid_segments.glsl"
#include "kernel_radius.h"

layout(location = 0) uniform ivec2 uSize;      // W, H
layout(location = 1) uniform int uAxis;        // 0: x pass, 1: y pass
layout(location = 2) uniform float uKPxDepth;  // 3 blurSigmaRadii r * focalPx, rounded on the CPU as there
layout(location = 3) uniform int uMaxRadius;   // min(255, maxKernelPx) >= 1
layout(location = 4) uniform int uGroups;      // groups of 4 taps stored per radius


// ceil(kPxDepth / z) in [0, maxR]; 0 for +inf, NaN or non-positive depth:
// shared/kernel_radius.h (the CPU's projectedRadiusPx, vectorised there) of
// the world length kPxDepth / f at focal length 1 (exact: x * 1 = x).
int kernelRadius(float z) { return projectedRadiusPx(uKPxDepth, 1.0, z, uMaxRadius); }

// sum_k src * weight over the groups of taps; `checked`: some tap may be off
// the image (constant per call, so each call compiles without or with the test).
vec4 accumulate(const bool checked, int idx, int pos, int len, int step, int R) {
    const int groups = (2 * R + 4) / 4;  // ceil((2 R + 1) / 4)
    precise vec4 s = vec4(0.0);
    for (int j = 0; j < groups; ++j) {
        const int k0 = 4 * j - R;
        vec4 v;
        for (int l = 0; l < 4; ++l) {
            const int k = k0 + l;
            if (checked) {
                const int p = pos + k;
                v[l] = (p >= 0 && p < len) ? texelFetch(uSrc, idx + k * step).x : 0.0;  // the CPU's zero padding
            } else {
                v[l] = texelFetch(uSrc, idx + k * step).x;
            }
        }
        s += v * texelFetch(uTable, R * uGroups + j);
    }
    return s;
}

void main() {
    const int W = uSize.x, H = uSize.y;
    const int len = uAxis == 0 ? W : H;
    const int step = uAxis == 0 ? 1 : W;
    for (int k = 0; k < uSegmentRounds; ++k) {
        int x, row;
        const int on = segmentPixel(k, W, x, row);
        if (on < 0) break;
        if (on == 0) continue;
        {
            const int idx = row * W + x;
            const int pos = uAxis == 0 ? x : row;
            const int R = kernelRadius(rawDepth[idx]);
            if (R == 0) {
                dst[idx] = texelFetch(uSrc, idx).x;
                continue;
            }
            // Every tap of every group (the last one rounded up) on the image: no test per tap.
            const bool interior = pos - R >= 0 && pos - R + 4 * ((2 * R + 4) / 4) <= len;
            precise vec4 s = interior ? accumulate(false, idx, pos, len, step, R)
                                      : accumulate(true, idx, pos, len, step, R);
            precise float sum = (s.x + s.y) + (s.z + s.w);
            if (pos < R || pos + R >= len) {
                // Near the border: renormalise by the weights of the taps on the
                // image, summed in order (the CPU's table row R, tap k at group
                // (k + R) / 4, lane (k + R) % 4).
                precise float wsum = 0.0;
                for (int k = max(-R, -pos); k <= min(R, len - 1 - pos); ++k)
                    wsum += texelFetch(uTable, R * uGroups + (k + R) / 4)[(k + R) % 4];
                sum /= wsum;
            }
            dst[idx] = sum;
        }
    }
}
