#version 430 core
#extension GL_GOOGLE_include_directive : require
// Normals stage (docs/pipeline.md#normals) on the GPU: the GL twin of
// src/cpu/normals.cpp. After van der Laan, Green & Sainz 2009 (US 8,947,430,
// eqs. 3-6) and Cords & Staadt 2008 ("Instant Liquids" §2.3,
// perspective-correct normals): every fluid pixel is back-projected with its
// smoothed eye depth to the view-space point P = z * ray(x+1/2, y+1/2), and
// n = normalize(dP/dx × dP/dy), with the exact inverse projection; per axis the
// central difference, or at a discontinuity (|dz| > jump, neighbour +inf or
// outside the image) the one-sided difference with the smaller |dz|, or with
// neither the screen axis made perpendicular to the view ray.
// Every operation follows the CPU's normalAt / axisTangent in the same order,
// `precise` (no FMA contraction or reassociation), so the two agree to the
// rounding of division and sqrt.
// Work: a work group per tile of 64 columns x uRows rows lists the tile's
// fluid pixels in shared memory, then computes the list 64 at a time (main).
#include "frame_params.h"

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

// Tangent along one image axis from the point p (depth z) and its two
// neighbours m (previous, depth zm) and q (next, depth zp), +inf depth when
// outside the image or no fluid; the fallback fb when neither is usable.
// Non-finite neighbour points are never selected (rejected by their depth first).
vec3 axisTangent(vec3 p, float z, vec3 m, float zm, vec3 q, float zp, float jump, vec3 fb) {
    precise float dzm = z - zm, dzp = zp - z;  // +inf - finite = +inf: never usable
    const bool okm = abs(dzm) <= jump, okp = abs(dzp) <= jump;
    // Smooth surface: central difference. A crease (the two sides disagree):
    // the flatter side. One usable side: that one.
    precise float crease = abs(dzp - dzm);
    const bool central = okm && okp && crease <= jump;
    const bool plus = okp && (!okm || abs(dzp) < abs(dzm));
    precise vec3 qm = q - m, qp = q - p, pm = p - m;
    return central ? qm : plus ? qp : okm ? pm : fb;
}

// The CPU's normalAt: the normal of the pixel with column ray rxc, row ray ryc,
// depth z and its four neighbours' depths; rxl, rxr: rays of the columns left
// and right, ryu, ryd: of the rows above and below.
vec3 normalAt(float z, float zl, float zr, float zu, float zd, float rxc, float rxl, float rxr, float ryc, float ryu,
              float ryd, float jump) {
    precise vec3 p = vec3(z * rxc, z * ryc, -z);
    // Unit view ray, for the fallback tangents and the orientation.
    precise float invLen = 1.0 / sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    precise vec3 u = vec3(p.x * invLen, p.y * invLen, p.z * invLen);
    precise vec3 ml = vec3(zl * rxl, zl * ryc, -zl), qr = vec3(zr * rxr, zr * ryc, -zr);
    precise vec3 fx = vec3(1.0 - u.x * u.x, 0.0 - u.x * u.y, 0.0 - u.x * u.z);
    precise vec3 t = axisTangent(p, z, ml, zl, qr, zr, jump, fx);  // along +x (right)
    precise vec3 md = vec3(zd * rxc, zd * ryd, -zd), qu = vec3(zu * rxc, zu * ryu, -zu);
    precise vec3 fy = vec3(0.0 - u.y * u.x, 1.0 - u.y * u.y, 0.0 - u.y * u.z);
    precise vec3 s = axisTangent(p, z, md, zd, qu, zu, jump, fy);  // toward the row above (+y view)
    // n = t × s, written out in the CPU's order.
    precise vec3 n = vec3(t.y * s.z - s.y * t.z, t.z * s.x - s.z * t.x, t.x * s.y - s.x * t.y);
    precise float nlen = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    const bool ok = nlen > 0.0;  // degenerate tangents: face the camera
    precise float invN = 1.0 / nlen;
    precise vec3 nn = vec3(n.x * invN, n.y * invN, n.z * invN);
    n = ok ? nn : -u;
    precise float nu = n.x * u.x + n.y * u.y + n.z * u.z;
    const bool flip = ok && nu > 0.0;  // toward the eye
    n = flip ? -n : n;
    return z < kInf ? n : vec3(0.0);
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
            // Rays per column and row exactly as the CPU's tables (Camera::pixelRay).
            precise float rxc = ((float(px) + 0.5) - halfW) / f;
            precise float rxl = ((float(px - 1) + 0.5) - halfW) / f;
            precise float rxr = ((float(px + 1) + 0.5) - halfW) / f;
            precise float ryc = -((float(py) + 0.5) - halfH) / f;
            precise float ryu = -((float(py - 1) + 0.5) - halfH) / f;
            precise float ryd = -((float(py + 1) + 0.5) - halfH) / f;
            const vec3 nrm = normalAt(texelFetch(uDepth, int(k)).x, depthAt(px - 1, py), depthAt(px + 1, py), depthAt(px, py - 1),
                                      depthAt(px, py + 1), rxc, rxl, rxr, ryc, ryu, ryd, jump);
            normals[3 * k + 0] = nrm.x;
            normals[3 * k + 1] = nrm.y;
            normals[3 * k + 2] = nrm.z;
        }
    }
}
