#version 430 core
#extension GL_GOOGLE_include_directive : require
// One Jacobi step of screen-space curvature flow: van der Laan, Green & Sainz,
// "Screen Space Fluid Rendering with Curvature Flow", I3D 2009 (NVIDIA patent
// US 8,947,430, eqs. 3-12), as restated in SPEC §3.5 -- the GPU twin of
// flowSpan in src/cpu/filter_curvature_flow.cpp, which documents the formula
// (D = C²G with G = z_x² + z_y² + (Cz)², analytic ∂D, z ← z − Δt·H,
// Δt = alpha·z/f) and the discontinuity rules. Every operation follows the CPU
// in the same order and is `precise` (no FMA contraction or reassociation).
// Buffers are (W + 2) x (H + 2) with a +inf frame (filter_curvature_flow_pad.comp).
// Each invocation walks a column strip of kRows pixels keeping the 3x3
// neighbourhood in registers: 3 loads per pixel instead of 9.
#include "frame_params.h"

layout(local_size_x = 64) in;

// The source is read through a buffer texture over the same buffer: llvmpipe
// fetches texels with vector gathers, SSBO loads one lane at a time; likewise
// the result is written through an R32F image buffer over the other buffer.
layout(binding = 0) uniform samplerBuffer src;
layout(r32f, binding = 0) writeonly uniform imageBuffer dst;

layout(std430, binding = 6) readonly buffer TileList { uint tileList[]; };  // tiles with fluid

layout(location = 0) uniform ivec2 uSize;  // W, H of the image (unpadded)
layout(location = 1) uniform int uTilesX;  // tiles (64 x kRows pixels, one work group each) per row

const int kRows = 8;

void main() {
    const int W = uSize.x, H = uSize.y, PW = W + 2;
    // One work group per listed tile (filter_curvature_flow_pad.comp, mode 1).
    const int tile = int(tileList[gl_WorkGroupID.x]);
    const int x = (tile % uTilesX) * 64 + int(gl_LocalInvocationID.x);
    const int y0 = (tile / uTilesX) * kRows;
    if (x >= W || y0 >= H) return;
    const float kInf = uintBitsToFloat(0x7f800000u);
    const float C = P.up.w;  // 1/f, rounded on the CPU as there
    precise float thr = P.filterJumpRadii * P.radius;
    precise float halfAlpha = 0.5 * P.cfAlpha;

    // Padded index of (x - 1, y0 - 1): padded column x, padded row y0.
    int k = y0 * PW + x;
    vec3 u = vec3(texelFetch(src, k).x, texelFetch(src, k + 1).x, texelFetch(src, k + 2).x);
    k += PW;
    vec3 c = vec3(texelFetch(src, k).x, texelFetch(src, k + 1).x, texelFetch(src, k + 2).x);
    k += PW;
    const int yEnd = min(y0 + kRows, H);
    for (int y = y0; y < yEnd; ++y, k += PW) {
        const vec3 d = vec3(texelFetch(src, k).x, texelFetch(src, k + 1).x, texelFetch(src, k + 2).x);
        const float z = c.y;
        float result = z;  // +inf stays +inf
        if (z < kInf) {
            const float zl = c.x, zr = c.z, zu = u.y, zd = d.y;
            const float zul = u.x, zur = u.z, zdl = d.x, zdr = d.z;
            // |a − z| <= thr is false for +inf neighbours.
            precise float el = abs(zl - z), er = abs(zr - z), eu = abs(zu - z), ed = abs(zd - z);
            precise float eul = abs(zul - z), eur = abs(zur - z), edl = abs(zdl - z), edr = abs(zdr - z);
            const bool vx = el <= thr && er <= thr;
            const bool vy = eu <= thr && ed <= thr;
            const bool vxy = vx && vy && eul <= thr && eur <= thr && edl <= thr && edr <= thr;
            precise float px = vx ? 0.5 * (zr - zl) : 0.0;
            precise float pxx = vx ? (zr + zl - 2.0 * z) : 0.0;
            precise float py = vy ? 0.5 * (zd - zu) : 0.0;
            precise float pyy = vy ? (zd + zu - 2.0 * z) : 0.0;
            precise float pxy = vxy ? 0.25 * ((zdr - zdl) - (zur - zul)) : 0.0;
            precise float w = C * z;
            precise float G = px * px + py * py + w * w;
            precise float Gx = 2.0 * (px * pxx + py * pxy + C * w * px);
            precise float Gy = 2.0 * (px * pxy + py * pyy + C * w * py);
            precise float num = 0.5 * (px * Gx + py * Gy) - (pxx + pyy) * G;  // 2H = num / G^{3/2}
            precise float zNew = z - halfAlpha * w * num / (G * sqrt(G));
            result = zNew;
        }
        imageStore(dst, (y + 1) * PW + x + 1, vec4(result));
        u = c;
        c = d;
    }
}
