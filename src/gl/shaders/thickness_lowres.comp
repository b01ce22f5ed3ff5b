#version 430 core
// Reduced-resolution thickness (docs/pipeline.md#thickness allows it; ThicknessParams::
// resolutionDivisor), the GPU twin of lowResThickness in src/cpu/thickness.cpp
// around the low-resolution chords (splat.comp, uDiv > 1) and their blur
// (filter_separable_thickness.comp on the low grid):
// Mode 0: the nearest depth of each d x d block (+inf: none; NaN skipped, as
//   std::min(z, v) on the CPU): of the raw fluid depth, which the
//   low-resolution blur projects its sigma with, and of the scene depth, which
//   clips the low-resolution chords.
// Mode 1: bilinear upsampling onto the full-resolution fluid pixels (0
//   elsewhere): full pixel x samples the low grid at (x + 1/2) / d - 1/2,
//   clamped to the grid; the two low rows are interpolated first, then along
//   the row, in the CPU's operation order (`precise`).
layout(local_size_x = 64) in;

layout(std430, binding = 1) readonly buffer Src { float src[]; };       // mode 0: a depth W x H; mode 1: low thickness w x h
layout(std430, binding = 2) readonly buffer Raw { float rawDepth[]; };  // mode 1: raw depth W x H
layout(std430, binding = 3) writeonly buffer Dst { float dst[]; };      // mode 0: w x h; mode 1: W x H

layout(location = 0) uniform ivec2 uSize;  // W, H (full resolution)
layout(location = 1) uniform int uDiv;     // d: 2 or 4
layout(location = 2) uniform int uMode;

#define kInf uintBitsToFloat(0x7f800000u)

// One axis of the bilinear taps: (i0, i1, fraction) as the CPU's taps().
void tapOf(int x, int lowN, out int i0, out int i1, out float f) {
    precise float u = (float(x) + 0.5) / float(uDiv) - 0.5;
    u = clamp(u, 0.0, float(lowN - 1));
    i0 = min(int(u), lowN - 1);
    i1 = min(i0 + 1, lowN - 1);
    precise float fr = u - float(i0);
    f = fr;
}

void main() {
    const int W = uSize.x, H = uSize.y, d = uDiv;
    const int w = (W + d - 1) / d, h = (H + d - 1) / d;
    const uint n = uMode == 0 ? uint(w * h) : uint(W * H);
    // Grid-stride loop: any image size with a bounded dispatch size.
    for (uint k = gl_GlobalInvocationID.x; k < n; k += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        if (uMode == 0) {
            const int i = int(k % uint(w)), j = int(k / uint(w));
            float z = kInf;
            for (int y = d * j; y < min(H, d * j + d); ++y)
                for (int x = d * i; x < min(W, d * i + d); ++x) {
                    const float v = src[y * W + x];
                    z = v < z ? v : z;
                }
            dst[k] = z;
        } else {
            const int x = int(k % uint(W)), y = int(k / uint(W));
            if (!(rawDepth[k] < kInf)) {
                dst[k] = 0.0;
                continue;
            }
            int x0, x1, y0, y1;
            float fx, fy;
            tapOf(x, w, x0, x1, fx);
            tapOf(y, h, y0, y1, fy);
            const float a0 = src[y0 * w + x0], a1 = src[y0 * w + x1];
            const float b0 = src[y1 * w + x0], b1 = src[y1 * w + x1];
            precise float r0 = a0 + fy * (b0 - a0);
            precise float r1 = a1 + fy * (b1 - a1);
            precise float t = r0 + fx * (r1 - r0);
            dst[k] = t;
        }
    }
}
