#version 430 core
#extension GL_GOOGLE_include_directive : require
// One Jacobi step of screen-space curvature flow: van der Laan, Green & Sainz,
// "Screen Space Fluid Rendering with Curvature Flow", I3D 2009 (NVIDIA patent
// US 8,947,430, eqs. 3-12), as restated in docs/pipeline.md#curvature-flow --
// the GPU twin of flowSpan in src/cpu/filter_curvature_flow.cpp. The step
// (D = C²G with G = z_x² + z_y² + (Cz)², analytic ∂D, z ← z − Δt·H,
// Δt = alpha·z/f) and the discontinuity rules are src/shared/curvature_flow.h,
// the CPU's, `precise` here (no FMA contraction or reassociation). Buffers
// are (W + 2) x (H + 2) with a +inf frame (set by the host), so the stencil
// needs no bounds tests.
// Work: only the 8-pixel row segments that hold fluid (fluid_segments.glsl):
// the fluid set never changes, and every other pixel stays +inf in both
// buffers and in the output.
#include "frame_params.h"
#include "curvature_flow.h"

layout(local_size_x = 64) in;

// The source is read through a buffer texture over the same buffer: llvmpipe
// fetches texels with vector gathers, SSBO loads one lane at a time; likewise
// the result is written through an R32F image buffer over the other buffer.
layout(binding = 0) uniform samplerBuffer src;
layout(r32f, binding = 0) writeonly uniform imageBuffer dst;

layout(binding = 1) uniform isamplerBuffer uSegments;  // the fluid segments (fluid_segments.glsl)
#include "fluid_segments.glsl"

layout(location = 0) uniform ivec2 uSize;  // W, H of the image (unpadded)
layout(location = 1) uniform int uFinal;   // 1: write the unpadded W x H output

void main() {
    const int W = uSize.x, PW = W + 2;
    const float kInf = uintBitsToFloat(0x7f800000u);
    const float C = P.up.w;  // 1/f, rounded on the CPU as there
    precise float thr = P.filterJumpRadii * P.radius;
    for (int r = 0; r < uSegmentRounds; ++r) {
        int x, y;
        const int on = segmentPixel(r, W, x, y);
        if (on < 0) break;
        if (on == 0) continue;
        // Padded index of (x - 1, y - 1): padded column x, padded row y.
        const int k = y * PW + x;
        const vec3 u = vec3(texelFetch(src, k).x, texelFetch(src, k + 1).x, texelFetch(src, k + 2).x);
        const vec3 c = vec3(texelFetch(src, k + PW).x, texelFetch(src, k + PW + 1).x, texelFetch(src, k + PW + 2).x);
        const vec3 d =
            vec3(texelFetch(src, k + 2 * PW).x, texelFetch(src, k + 2 * PW + 1).x, texelFetch(src, k + 2 * PW + 2).x);
        const float z = c.y;
        float result = z;  // +inf stays +inf
        if (z < kInf) {
            const float zl = c.x, zr = c.z, zu = u.y, zd = d.y;
            const float zul = u.x, zur = u.z, zdl = d.x, zdr = d.z;
            result = curvatureFlowStep(z, zl, zr, zu, zd, zul, zur, zdl, zdr, C, thr, P.cfAlpha);
        }
        imageStore(dst, uFinal != 0 ? y * W + x : k + PW + 1, vec4(result));
    }
}
