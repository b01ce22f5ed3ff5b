#version 430 core
#extension GL_GOOGLE_include_directive : require
// Anisotropic kernels (Yu & Turk, "Reconstructing surfaces of particle-based
// fluids using anisotropic kernels", ACM TOG 32(1) 2013;
// docs/pipeline.md#anisotropic-kernels) on the GPU: the GL twin of
// src/core/anisotropy.cpp. One invocation per particle, taken in the grid's
// order (anisotropy_grid.comp's `sorted`), walks the 27 cells around its
// own (their buckets' particles of that cell), in a fixed order, and sums over the neighbours
// j with |x_j - x_i| < R (itself included) the weights w = 1 - (|d| / R)^3,
// w d and w d d^T (d = x_j - x_i in units of R, floats). Then, as the CPU:
// the weighted mean offset mu, the covariance C = E_w[d d^T] - mu mu^T, its
// closed-form eigen-decomposition, the axes (eq. 13, volume-preserving), the
// smoothed centre x + lambda mu and the free surface's shift, all by the
// formulas of src/shared/anisotropy.h; a particle with fewer than
// uMinNeighbours neighbours is a sphere of kn times its radius. Written:
// the centres (packed xyz, splat.comp's Positions) and the shapes
// (splat.comp's Shapes: m and q, 6 floats each, times uShapeScale).
// The distance test is the CPU's float arithmetic (`precise`), so both find
// the same neighbours; the sums and the eigen-decomposition run in float
// here, in double there (docs/pipeline.md has the tolerance).
#include "anisotropy_grid.glsl"
#include "anisotropy.h"

layout(local_size_x = 64) in;

// Through buffer textures: llvmpipe gathers texel fetches in SIMD but reads
// storage buffers lane by lane.
layout(binding = 0) uniform samplerBuffer sorted;   // xyz, particle index bits in w
layout(binding = 1) uniform usamplerBuffer starts;  // uBuckets + 1
layout(std430, binding = 2) readonly buffer Radii { float radii[]; };     // own radii (uOwnRadii != 0)
layout(std430, binding = 3) writeonly buffer Centres { float centres[]; };  // packed xyz
layout(std430, binding = 4) writeonly buffer Shapes { vec4 shapes[]; };

layout(location = 3) uniform float uR2;     // R^2 (float, as the CPU's)
layout(location = 4) uniform float uInvR3;  // 1 / R^3
layout(location = 5) uniform int uMinNeighbours;
layout(location = 6) uniform float uKr;
layout(location = 7) uniform float uKn;
layout(location = 8) uniform float uSmoothingR;  // lambda R (metres)
layout(location = 9) uniform int uKeepSurface;
layout(location = 10) uniform float uRadius;
layout(location = 11) uniform int uOwnRadii;
layout(location = 12) uniform float uShapeScale;  // every shape's half-axes times this (the ray cast's cover)

void writeShape(uint i, mat3 m, mat3 q) {
    const float inv = 1.0 / uShapeScale, sq = uShapeScale * uShapeScale;
    m *= inv;
    q *= sq;
    shapes[3u * i] = vec4(m[0][0], m[0][1], m[0][2], m[1][1]);
    shapes[3u * i + 1u] = vec4(m[1][2], m[2][2], q[0][0], q[0][1]);
    shapes[3u * i + 2u] = vec4(q[0][2], q[1][1], q[1][2], q[2][2]);
}

void main() {
    const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint s = gl_GlobalInvocationID.x; s < uCount; s += stride) {
        const vec4 self = texelFetch(sorted, int(s));
        const vec3 p = self.xyz;
        const uint i = floatBitsToUint(self.w);
        const float radius = uOwnRadii != 0 ? radii[i] : uRadius;
        const ivec3 cell = anisotropyCell(p);
        float W = 0.0;
        vec3 sd = vec3(0.0);
        float sxx = 0.0, sxy = 0.0, sxz = 0.0, syy = 0.0, syz = 0.0, szz = 0.0;
        int count = 0;
        for (int z = -1; z <= 1; ++z)
            for (int y = -1; y <= 1; ++y)
                for (int x = -1; x <= 1; ++x) {
                    const ivec3 at = cell + ivec3(x, y, z);
                    const uint b = anisotropyBucket(at);
                    const int end = int(texelFetch(starts, int(b + 1u)).x);
                    for (int t = int(texelFetch(starts, int(b)).x); t < end; ++t) {
                        const vec3 xj = texelFetch(sorted, t).xyz;
                        // Only this cell's particles: cells sharing a bucket count once each.
                        if (anisotropyCell(xj) != at) continue;
                        precise const vec3 d = xj - p;
                        precise const float d2 = (d.x * d.x + d.y * d.y) + d.z * d.z;
                        if (!(d2 < uR2)) continue;
                        precise const float w = anisotropyWeight(d2, sqrt(d2), uInvR3);
                        const vec3 e = d * uInvR;
                        const vec3 we = w * e;
                        ++count;
                        W += w;
                        sd += we;
                        sxx += we.x * e.x, sxy += we.x * e.y, sxz += we.x * e.z;
                        syy += we.y * e.y, syz += we.y * e.z, szz += we.z * e.z;
                    }
                }
        const vec3 mu = sd / W;  // units of R; W >= 1 (the particle itself)
        vec3 centre = p + uSmoothingR * mu;  // Yu & Turk eq. 6
        mat3 m = mat3(1.0 / (uKn * radius)), q = mat3((uKn * radius) * (uKn * radius));  // the lone sphere
        if (count - 1 >= uMinNeighbours) {
            mat3 cov;  // Yu & Turk eq. 9, about the weighted mean, units of R^2
            cov[0] = vec3(sxx, sxy, sxz) / W - mu.x * mu;
            cov[1] = vec3(sxy, syy, syz) / W - mu.y * mu;
            cov[2] = vec3(sxz, syz, szz) / W - mu.z * mu;
            vec3 sigma;
            mat3 axes;
            anisotropyEigen(cov, sigma, axes);
            if (sigma[0] > 0.0) {
                const vec3 a = anisotropyAxes(sigma, uKr, radius);
                m = anisotropyFromAxes(axes, 1.0 / a);
                q = anisotropyFromAxes(axes, a * a);
                if (uKeepSurface != 0 && a.z < radius) centre += anisotropySurfaceShift(mu, axes[2], a.z, radius, 1.0);
            }
        }
        centres[3u * i] = centre.x;
        centres[3u * i + 1u] = centre.y;
        centres[3u * i + 2u] = centre.z;
        writeShape(i, m, q);
    }
}
