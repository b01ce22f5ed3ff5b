#version 430 core
// Depth splat and thickness chords (docs/pipeline.md#depth-splat,
// docs/pipeline.md#thickness) on the GPU: the exact ray-sphere nearest hit of
// src/cpu/splat.cpp (van der Laan et al. 2009; Cords & Staadt 2008 §2.1), one
// invocation per particle over its exact projected bounding box.
//  - Depth: the minimum kept with atomicMin on the float bits (positive IEEE
//    floats order like their unsigned bit patterns), so it is exact and
//    order-independent. The formulas (view-space centre, projected bounds,
//    pixel rays, ray-sphere hit, its depth and clipped chord) are
//    src/shared/splat.h, the CPU's, `precise` here (no FMA contraction or
//    reassociation), so the two agree to rounding of sqrt/division only.
//  - Thickness (uThickness != 0): the chord of the pixel ray inside the sphere,
//    clipped to eye depths [near, scene), summed with atomicAdd in fixed point
//    (GL 4.3 has no float atomics; shared/splat_chords.h, the CPU's formula):
//    units of radius / kChordScale, so the sum does not depend on the order
//    the GPU runs the particles in.
//  - Reduced resolution (uDiv = d > 1; cpu splatTile<.., kDiv>): chords only,
//    one output pixel per d x d block, its ray through the block's centre and
//    its scene depth the nearest of the block's (sceneDepth is then that
//    low-resolution image, thickness_lowres.comp mode 0); a sphere covers the blocks
//    whose centres d (i + 1/2) lie in its rectangle grown by half a pixel.
//  - Ellipsoids (uEllipsoids != 0; anisotropic kernels, core/anisotropy.h):
//    each particle is the ellipsoid of its shapes[] entry instead of the
//    sphere of P.radius: view-space shape, bounds and ray hit from
//    shared/ellipsoid.h, the same functions the CPU calls.
//  - Large spheres (uPass): llvmpipe silently stops an invocation's loops
//    after 65,535 iterations in all (gallivm's LP_MAX_TGSI_LOOP_ITERATIONS),
//    which one invocation walking a near sphere's rectangle of over 65,535
//    pixels would hit. Pass 0 splats the spheres of up to kMaxPixels pixels
//    and lists the others; pass 1 (an indirect dispatch: kBigGroups work
//    groups per listed sphere) spreads each listed rectangle over
//    kBigGroups x 64 invocations. The atomics make the split invisible.
// Depth buffer: W*H uints, row-major, row 0 = the TOP row
// (docs/conventions.md#conventions), set beforehand to +inf; it keeps the
// nearest hit in front of the scene (+inf: no fluid). Chord sums: set to 0
// beforehand, turned into metres by splat_resolve.comp.
#extension GL_GOOGLE_include_directive : require
#include "frame_params.h"
#include "splat_chords.h"
#include "ellipsoid.h"
#include "splat.h"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { float positions[]; };  // world xyz, tightly packed
layout(std430, binding = 1) buffer Depth { uint depthBits[]; };
// The scene depth through a buffer texture: llvmpipe gathers texel fetches in
// SIMD but reads storage buffers lane by lane.
layout(binding = 0) uniform samplerBuffer sceneDepth;  // +inf where nothing
// The depth being splatted, read without synchronisation (see splatPixel).
layout(binding = 1) uniform samplerBuffer depthSoFar;
layout(std430, binding = 3) buffer Chords { uint chordFixed[]; };

layout(location = 0) uniform uint uCount;     // particles
layout(location = 1) uniform int uHasScene;   // sceneDepth is bound and camera-sized
layout(location = 2) uniform int uThickness;  // also sum the chords
layout(location = 3) uniform int uPass;       // 0: small spheres, listing the large; 1: the listed ones
layout(location = 4) uniform int uDiv;        // 1: full resolution; 2 or 4: chords only, one pixel per uDiv x uDiv block
layout(location = 5) uniform int uEllipsoids; // shapes[] holds one ellipsoid per particle

// Per particle three vec4s: m00 m01 m02 m11 | m12 m22 q00 q01 | q02 q11 q12 q22,
// the world-space symmetric m and q of shared/ellipsoid.h.
layout(std430, binding = 5) readonly buffer Shapes { vec4 shapes[]; };

// The indirect dispatch of pass 1 and its list (the host sets x = kBigGroups,
// y = 0, z = 1, count = 0 before pass 0).
layout(std430, binding = 4) buffer Big {
    uint groupsX, groupsY, groupsZ;  // pass 1's work groups: y = listed spheres, at most kMaxGroups
    uint bigCount;                   // listed spheres
    uint bigList[];                  // their particle indices
};

const int kMaxPixels = 4096;      // largest rectangle one invocation walks in pass 0
const uint kMaxGroups = 65535u;   // the minimum GL_MAX_COMPUTE_WORK_GROUP_COUNT

// The CPU's sphereBounds: exact projected rectangle [x0, x1) x [y0, y1) of the
// sphere (view centre c, radius r), clipped to the image; empty: x0 >= x1.
ivec4 sphereBounds(vec3 c, float r) {
    vec4 s;
    const int kind = splatSphereSlopes(c, r, s);
    if (kind == 0) return ivec4(0);
    if (kind == 1) return ivec4(0, 0, P.size.x, P.size.y);
    return splatRectFromSlopes(s, P.size.x, P.size.y, P.right.w);
}

// The CPU's ellipsoidBounds (view centre c, view-space outer form q).
ivec4 ellipsoidBounds(vec3 c, mat3 q) {
    vec4 s;
    const int kind = ellipsoidSlopes(c, q, s);
    if (kind == 0) return ivec4(0);
    if (kind == 1) return ivec4(0, 0, P.size.x, P.size.y);
    return splatRectFromSlopes(s, P.size.x, P.size.y, P.right.w);
}

// Particle i's shape in view space as binParticles takes it: m, e = m c and
// the outer form q (identity matrices when the particles are spheres).
struct Shape {
    mat3 m, q;
    vec3 e;
};
Shape viewShape(uint i, vec3 c) {
    Shape s;
    s.m = mat3(1.0);
    s.q = mat3(1.0);
    s.e = c;
    if (uEllipsoids == 0) return s;
    const vec4 a = shapes[3u * i], b = shapes[3u * i + 1u], d = shapes[3u * i + 2u];
    const mat3 mw = mat3(a.x, a.y, a.z, a.y, a.w, b.x, a.z, b.x, b.y);
    const mat3 qw = mat3(b.z, b.w, d.x, b.w, d.y, d.z, d.x, d.z, d.w);
    s.m = ellipsoidToView(mw, P.right.xyz, P.up.xyz, P.back.xyz);
    s.q = ellipsoidToView(qw, P.right.xyz, P.up.xyz, P.back.xyz);
    s.e = ellipsoidMul(s.m, c);
    return s;
}

// The view-space centre of particle i (Camera::toView).
vec3 viewCentre(uint i) {
    const vec3 p = vec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
    return splatViewCentre(p, P.eye.xyz, P.right.xyz, P.up.xyz, P.back.xyz);
}

// Pixel (x, y) against the sphere of view centre c (or the ellipsoid sh):
// the nearest hit into the depth bits, the clipped chord into the sums.
void splatPixel(vec3 c, Shape sh, int x, int y) {
    const int W = P.size.x, d = uDiv;
    const int outW = (W + d - 1) / d;
    const float invF = P.up.w, zNear = P.eye.w, r = P.radius;
    precise float halfW = 0.5 * float(P.size.x), halfH = 0.5 * float(P.size.y);
    precise float r2 = r * r;
    // The CPU's rays: pixel (or block) centres d x + d / 2 (x + 1/2 at full
    // resolution), along the unit ray u.
    precise float centreY = float(d * y) + 0.5 * float(d), centreX = float(d * x) + 0.5 * float(d);
    const float ry = splatRayY(centreY, halfH, invF), rx = splatRayX(centreX, halfW, invF);
    precise float len = sqrt(splatRayLength2(rx, ry));
    precise vec3 u;
    precise float invLen;
    splatUnitRay(rx, ry, len, u.x, u.y, u.z, invLen);
    precise float b, h2;
    if (uEllipsoids != 0)
        rayEllipsoid(u.x, u.y, u.z, sh.m, sh.e, b, h2);
    else
        raySphere(u.x, u.y, u.z, c, r2, b, h2);
    if (!(h2 >= 0.0)) return;
    precise float h = sqrt(h2);
    const uint k = uint(y * outW + x);
    const float zScene = uHasScene != 0 ? texelFetch(sceneDepth, int(k)).x : 1.0 / 0.0;
    if (uThickness != 0) {
        // The CPU's clip: [max(t0, near len), min(t1, scene len)) along the ray.
        precise float tn = P.eye.w * len;
        precise float tf = zScene * len;
        const float chord = splatChord(b, h, tn, tf);
        if (chord > 0.0) atomicAdd(chordFixed[k], chordToFixed(chord, r));
    }
    if (d != 1) return;  // chords only
    const float z = splatHitDepth(b, h, invLen);
    // Nearest hit only: one nearer than the near plane is clipped, not
    // replaced by the exit (zNear > 0 also rejects hits behind the eye); one
    // at or behind the scene is hidden (so is any, when the scene depth is
    // not positive or NaN), as the CPU's min starting at the scene depth.
    if (!(z >= zNear) || !(z < zScene)) return;
    // Most hits lie behind a nearer one already splatted: skip their atomic
    // (on llvmpipe atomics run lane by lane, texel fetches in SIMD). The read
    // may be stale, but the stored depth only ever decreases after the host's
    // fill, so z >= any value read means z >= the final minimum too.
    if (!(z < texelFetch(depthSoFar, int(k)).x)) return;
    atomicMin(depthBits[k], floatBitsToUint(z));
}

// The output pixels the sphere of view centre c covers: its rectangle, or at
// reduced resolution the blocks i with d (i + 1/2) in (x0 - 1/2, x1 + 1/2)
// (splatLowBegin / splatLowEnd).
ivec4 outputRect(vec3 c, Shape sh) {
    const ivec4 rect = uEllipsoids != 0 ? ellipsoidBounds(c, sh.q) : sphereBounds(c, P.radius);
    const int d = uDiv;
    if (d == 1) return rect;
    const ivec2 lo = ivec2(splatLowBegin(rect.x, d), splatLowBegin(rect.y, d));
    const ivec2 hi = ivec2(splatLowEnd(rect.z, d), splatLowEnd(rect.w, d));
    return ivec4(lo, min(hi, (P.size.xy + d - 1) / d));
}

void main() {
    if (uPass == 0) {
        // Grid-stride loop: any particle count with a bounded dispatch size.
        for (uint i = gl_GlobalInvocationID.x; i < uCount; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
            const vec3 c = viewCentre(i);
            const Shape sh = viewShape(i, c);
            const ivec4 rect = outputRect(c, sh);
            if (rect.x >= rect.z || rect.y >= rect.w) continue;
            if ((rect.z - rect.x) * (rect.w - rect.y) > kMaxPixels) {
                const uint slot = atomicAdd(bigCount, 1u);
                bigList[slot] = i;
                if (slot < kMaxGroups) atomicAdd(groupsY, 1u);
                continue;
            }
            // One loop over the rectangle's pixels, not rows x columns: lanes
            // run as long as the largest rectangle of the vector, not as its
            // tallest times its widest.
            const int n = (rect.z - rect.x) * (rect.w - rect.y);
            int x = rect.x, y = rect.y;
            for (int p = 0; p < n; ++p) {
                splatPixel(c, sh, x, y);
                const bool wrap = x + 1 == rect.z;
                x = wrap ? rect.x : x + 1;
                y = wrap ? y + 1 : y;
            }
        }
    } else {
        // Work group (gx, gy): listed spheres gy, gy + kMaxGroups, ...; its
        // invocations take every (groupsX * 64)-th pixel of the rectangle.
        const uint stride = groupsX * gl_WorkGroupSize.x;
        const uint first = gl_WorkGroupID.x * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
        for (uint s = gl_WorkGroupID.y; s < bigCount; s += kMaxGroups) {
            const vec3 c = viewCentre(bigList[s]);
            const Shape sh = viewShape(bigList[s], c);
            const ivec4 rect = outputRect(c, sh);
            const uint w = uint(rect.z - rect.x), n = w * uint(rect.w - rect.y);
            for (uint p = first; p < n; p += stride) splatPixel(c, sh, rect.x + int(p % w), rect.y + int(p / w));
        }
    }
}
