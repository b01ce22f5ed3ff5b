#version 430 core
#extension GL_GOOGLE_include_directive : require
// The SPH surface, ray cast (docs/pipeline.md#ray-cast-surface) on the GPU: the
// GL twin of src/cpu/raycast.cpp. One invocation per pixel: where the splat's
// depth is finite, shared::sphRaycast marches the pixel's ray through the
// particles' density (Fraedrich, Auer & Westermann 2010) from that depth to the
// iso level, summing the field over core/sph_field.h's grid exactly as
// evaluateSphField does (cells z, then y, each row of three cells one range
// of the sorted points, points in order), every operation `precise`, so the
// two agree to the rounding of sqrt and division.
#include "frame_params.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 1) readonly buffer Points { vec4 points[]; };  // grid-sorted world xyz (w unused)
layout(std430, binding = 2) readonly buffer Starts { uint starts[]; };  // cellCount + 1 range starts
layout(std430, binding = 3) readonly buffer Start { float startDepth[]; };  // W*H, the splat, +inf = none
layout(std430, binding = 4) readonly buffer Scene { float sceneDepth[]; };  // W*H when uHasScene
layout(std430, binding = 5) writeonly buffer Depth { float depthOut[]; };   // W*H
layout(std430, binding = 6) writeonly buffer Normals { float normals[]; };  // W*H*3
layout(std430, binding = 7) readonly buffer Quiet { uint quiet[]; };        // SphField::quiet bits

layout(location = 0) uniform vec3 uLo;        // the grid's corner, world metres
layout(location = 1) uniform float uInvCell;  // 1 / cell side
layout(location = 2) uniform ivec3 uDims;     // cells per axis (0: no particles)
layout(location = 3) uniform float uSupport;  // h, metres
layout(location = 4) uniform float uIso;      // SphField::isoRaw
layout(location = 5) uniform float uStep;     // march step, metres
layout(location = 6) uniform int uMaxSteps;
layout(location = 7) uniform int uNewtonSteps;
layout(location = 8) uniform int uHasScene;
layout(location = 9) uniform float uInvH2;    // 1 / h^2

// Defined below, called by sph_surface.h's sphRaycast.
void sphFieldAt(vec3 p, out float f, out vec3 grad);
bool sphQuiet(vec3 p);
float sphLastInCell(vec3 origin, vec3 dir, float t);
#include "sph_surface.h"

// evaluateSphField (core/sph_field.cpp), operation for operation: the point
// at offset j of its row's range goes into partial sum j mod 4 (the CPU's
// lane), the four added as (s0 + s1) + (s2 + s3).
void sphFieldAt(vec3 p, out float f, out vec3 grad) {
    precise float h2 = uSupport * uSupport;
    precise float invH = 1.0 / uSupport;
    precise vec3 u = clamp((p - uLo) * uInvCell, vec3(0.0), vec3(uDims - 1));
    const ivec3 c = ivec3(u);
    precise vec4 sum = vec4(0.0), gx = vec4(0.0), gy = vec4(0.0), gz = vec4(0.0);
    const int x0 = max(c.x - 1, 0), x1 = min(c.x + 1, uDims.x - 1);
    for (int z = max(c.z - 1, 0); z <= min(c.z + 1, uDims.z - 1); ++z)
        for (int y = max(c.y - 1, 0); y <= min(c.y + 1, uDims.y - 1); ++y) {
            const uint row = uint((z * uDims.y + y) * uDims.x);
            const uint b = starts[row + uint(x0)], e = starts[row + uint(x1) + 1u];
            for (uint i = b; i < e; ++i) {
                precise vec3 d = p - points[i].xyz;
                precise float d2 = (d.x * d.x + d.y * d.y) + d.z * d.z;
                if (d2 < h2) {
                    const uint lane = (i - b) & 3u;
                    precise float q = sqrt(d2) * invH;
                    sum[lane] += sphKernel(q);
                    precise float w = sphKernelGradient(q);
                    gx[lane] += w * d.x;
                    gy[lane] += w * d.y;
                    gz[lane] += w * d.z;
                }
            }
        }
    precise float fs = (sum[0] + sum[1]) + (sum[2] + sum[3]);
    precise vec3 gs = vec3((gx[0] + gx[1]) + (gx[2] + gx[3]), (gy[0] + gy[1]) + (gy[2] + gy[3]),
                           (gz[0] + gz[1]) + (gz[2] + gz[3]));
    f = fs;
    grad = gs;
}

// sphFieldQuiet (core/sph_field.cpp): the quiet bit of p's (clamped) cell.
bool sphQuiet(vec3 p) {
    precise vec3 u = clamp((p - uLo) * uInvCell, vec3(0.0), vec3(uDims - 1));
    const ivec3 c = ivec3(u);
    const uint i = uint((c.z * uDims.y + c.y) * uDims.x + c.x);
    return ((quiet[i >> 5u] >> (i & 31u)) & 1u) != 0u;
}

// sphFieldLastInCell (core/sph_field.cpp): how far the ray stays in the cell
// of its point at t (t when outside the grid's box).
float sphLastInCell(vec3 origin, vec3 dir, float t) {
    precise vec3 p = sphRayPoint(origin, dir, t);
    precise vec3 u = (p - uLo) * uInvCell;
    for (int a = 0; a < 3; ++a)
        if (!(u[a] >= 0.0 && u[a] < float(uDims[a]))) return t;
    precise float cell = 1.0 / uInvCell;
    precise float exitT = uintBitsToFloat(0x7f800000u);
    for (int a = 0; a < 3; ++a) {
        precise float c = floor(u[a]);
        if (dir[a] > 0.0) exitT = min(exitT, (uLo[a] + (c + 1.0) * cell - origin[a]) / dir[a]);
        if (dir[a] < 0.0) exitT = min(exitT, (uLo[a] + c * cell - origin[a]) / dir[a]);
    }
    precise float last = exitT - 1e-3 * cell / length(dir);
    return last;
}

void main() {
    const int W = P.size.x, H = P.size.y;
    const int x = int(gl_GlobalInvocationID.x), y = int(gl_GlobalInvocationID.y);
    if (x >= W || y >= H) return;
    const uint k = uint(y) * uint(W) + uint(x);
    const float kInf = uintBitsToFloat(0x7f800000u);
    depthOut[k] = kInf;
    normals[3u * k] = 0.0, normals[3u * k + 1u] = 0.0, normals[3u * k + 2u] = 0.0;
    const float t0 = startDepth[k];
    if (!(t0 < kInf)) return;
    const float f = P.right.w;
    precise float halfW = 0.5 * float(W), halfH = 0.5 * float(H);
    precise float rx = ((float(x) + 0.5) - halfW) / f;
    precise float ry = -((float(y) + 0.5) - halfH) / f;
    const vec3 right = P.right.xyz, up = P.up.xyz, back = P.back.xyz;
    const vec3 dir = sphRayDir(rx, ry, right, up, back);
    const float tMax = uHasScene != 0 ? min(sceneDepth[k], P.back.w) : P.back.w;
    vec3 grad = vec3(0.0);
    const float t = sphRaycast(P.eye.xyz, dir, t0, P.eye.w, tMax, uStep, uMaxSteps, uNewtonSteps, uIso, uInvH2, grad);
    if (!(t < kInf)) return;
    depthOut[k] = t;
    const vec3 n = sphNormalView(grad, right, up, back);
    normals[3u * k] = n.x, normals[3u * k + 1u] = n.y, normals[3u * k + 2u] = n.z;
}
