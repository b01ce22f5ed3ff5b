// Reduced-resolution processing (docs/pipeline.md#reduced-resolution; the
// NVIDIA patent's "render the fluid at lower resolution"; Cords & Staadt 2008,
// "Instant Liquids" §5 and Table 1): the splat, smoothing, normals and noise
// run on a camera with 1/d of the pixels per side (d = 2 or 4), and these
// formulas, written once for C++ and GLSL like silhouette.h, bring the result
// back to full resolution without mixing what must not be mixed:
//  - the geometry: the low image is the full one seen through the same
//    pinhole with focal length f/d and ceil(W/d) x ceil(H/d) pixels, centred
//    on the same axis. Low pixel i covers the d full columns from
//    i d - ceil(off/2) (off = ceil(W/d) d - W, the low image's overhang),
//    which is the integer form of u_full = (u_low - W_low/2) d + W/2;
//  - the scene depth the low splat is clipped against: per low pixel the
//    FARTHEST scene depth of its full pixels, so no fluid visible in any of
//    them is lost (each full pixel clips it again against its own);
//  - the upsampling: a full pixel's four nearest low pixels with bilinear
//    weights; its fluid coverage c is the weight of the fluid ones, and it is
//    fluid where c >= 1/2 (the contour runs at full resolution between the
//    low pixels, not in d x d steps). Of the fluid taps only those within a
//    depth jump (kDepthJumpRadii particle radii, the normals' discontinuity
//    test) of the tap nearest the pixel are blended, their weights
//    renormalised: nothing is interpolated across a silhouette or between a
//    near and a far body. Depth is blended as 1/z (perspective-correct, so a
//    plane stays a plane), thickness and noise linearly, the normal as the
//    normalised weighted sum;
//  - the edges: a fluid pixel with c < 1 is blended into the scene behind it
//    by c (the colour blended at edges; c is 1/2 on the contour itself).
// Every operation is written out in one order and `precise` on the GPU, so
// both backends give the same bits.
#ifndef MENISCUS_SHARED_UPSAMPLE_H
#define MENISCUS_SHARED_UPSAMPLE_H

#include "silhouette.h"

#ifdef __cplusplus
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>
namespace meniscus::shared {
using std::floor;
using std::max;
using std::min;
using std::sqrt;
using glm::abs;
using glm::ivec2;
using glm::vec2;
using glm::vec3;
using glm::vec4;
#define MENISCUS_UP_INLINE inline
#define MENISCUS_UP_EXACT const
#define MENISCUS_UP_OUT(T) T&
#define MENISCUS_UP_INF std::numeric_limits<float>::infinity()
#else
#define MENISCUS_UP_INLINE
#define MENISCUS_UP_EXACT precise
#define MENISCUS_UP_OUT(T) out T
#define MENISCUS_UP_INF uintBitsToFloat(0x7f800000u)
#endif

// The low image's side for a full side `full` and divisor d: ceil(full / d).
MENISCUS_UP_INLINE int lowSide(int full, int d) { return (full + d - 1) / d; }

// The full pixels [x0, x1) that low pixel `i` covers along an axis of `full`
// full and `low` low pixels (clamped to the image; a low pixel wholly outside
// it takes the nearest edge pixel).
MENISCUS_UP_INLINE ivec2 lowPixelSpan(int i, int full, int low, int d) {
    int off = low * d - full;
    int x0 = i * d - (off + 1) / 2;
    int x1 = x0 + d;
    x0 = min(max(x0, 0), full - 1);
    x1 = max(min(x1, full), x0 + 1);
    return ivec2(x0, x1);
}

// The continuous low-image coordinate of full pixel x's centre, in units
// where low pixel centres are the integers: (2x + 1 + off) / (2d) - 1/2,
// exact in float (d is a power of two).
MENISCUS_UP_INLINE float lowCoordinate(int x, int full, int low, int d) {
    int off = low * d - full;
    MENISCUS_UP_EXACT float u = float(2 * x + 1 + off) / float(2 * d) - 0.5f;
    return u;
}

// The low pixel nearest full pixel x (the one whose span holds it).
MENISCUS_UP_INLINE int nearestLowPixel(int x, int full, int low, int d) {
    int off = low * d - full;
    return min((x + (off + 1) / 2) / d, low - 1);
}

// The bilinear footprint of a low coordinate u on an axis of `low` pixels:
// the two taps (clamped to the image) and the weight of the second.
MENISCUS_UP_INLINE void upsampleTaps(float u, int low, MENISCUS_UP_OUT(ivec2) taps, MENISCUS_UP_OUT(float) t) {
    MENISCUS_UP_EXACT float fl = floor(u);
    int i0 = int(fl);
    MENISCUS_UP_EXACT float frac = u - fl;
    t = frac;
    taps = ivec2(min(max(i0, 0), low - 1), min(max(i0 + 1, 0), low - 1));
}

// The four taps' bilinear weights (00, 10, 01, 11) for the fractions tx, ty.
MENISCUS_UP_INLINE vec4 upsampleWeights(float tx, float ty) {
    MENISCUS_UP_EXACT float sx = 1.0f - tx;
    MENISCUS_UP_EXACT float sy = 1.0f - ty;
    MENISCUS_UP_EXACT vec4 w = vec4(sx * sy, tx * sy, sx * ty, tx * ty);
    return w;
}

// The coverage c: the weight of the taps with fluid (depth < +inf).
MENISCUS_UP_INLINE float upsampleCoverage(vec4 z, vec4 w) {
    MENISCUS_UP_EXACT float c0 = z.x < MENISCUS_UP_INF ? w.x : 0.0f;
    MENISCUS_UP_EXACT float c1 = z.y < MENISCUS_UP_INF ? w.y : 0.0f;
    MENISCUS_UP_EXACT float c2 = z.z < MENISCUS_UP_INF ? w.z : 0.0f;
    MENISCUS_UP_EXACT float c3 = z.w < MENISCUS_UP_INF ? w.w : 0.0f;
    MENISCUS_UP_EXACT float c = ((c0 + c1) + c2) + c3;
    return c;
}

// Whether a pixel of coverage c is fluid.
MENISCUS_UP_INLINE bool upsampleIsFluid(float c) { return c >= 0.5f; }

// The weights of the taps blended (0 for the others): the fluid taps within
// `jump` metres of the depth of the fluid tap with the largest weight (the
// first of equals, in the order 00, 10, 01, 11). Needs a fluid tap.
MENISCUS_UP_INLINE vec4 upsampleBlendWeights(vec4 z, vec4 w, float jump) {
    float best = -1.0f;
    float zr = 0.0f;
    if (z.x < MENISCUS_UP_INF && w.x > best) { best = w.x; zr = z.x; }
    if (z.y < MENISCUS_UP_INF && w.y > best) { best = w.y; zr = z.y; }
    if (z.z < MENISCUS_UP_INF && w.z > best) { best = w.z; zr = z.z; }
    if (z.w < MENISCUS_UP_INF && w.w > best) { best = w.w; zr = z.w; }
    MENISCUS_UP_EXACT vec4 dz = abs(z - vec4(zr));
    return vec4(dz.x <= jump ? w.x : 0.0f, dz.y <= jump ? w.y : 0.0f, dz.z <= jump ? w.z : 0.0f,
                dz.w <= jump ? w.w : 0.0f);
}

// The weight sum of the blended taps (> 0: the reference tap's own weight is
// in it, and the largest of four bilinear weights is at least 1/4).
MENISCUS_UP_INLINE float upsampleWeightSum(vec4 b) {
    MENISCUS_UP_EXACT float s = ((b.x + b.y) + b.z) + b.w;
    return s;
}

// A scalar blended linearly: sum b_k v_k / sum b_k (taps with b_k = 0 are
// left out, so their values, +inf included, never enter).
MENISCUS_UP_INLINE float upsampleLinear(vec4 v, vec4 b, float sum) {
    MENISCUS_UP_EXACT float p0 = b.x > 0.0f ? b.x * v.x : 0.0f;
    MENISCUS_UP_EXACT float p1 = b.y > 0.0f ? b.y * v.y : 0.0f;
    MENISCUS_UP_EXACT float p2 = b.z > 0.0f ? b.z * v.z : 0.0f;
    MENISCUS_UP_EXACT float p3 = b.w > 0.0f ? b.w * v.w : 0.0f;
    MENISCUS_UP_EXACT float r = (((p0 + p1) + p2) + p3) / sum;
    return r;
}

// Eye depth blended as 1/z (perspective-correct: 1/z is affine in the image
// over a plane).
MENISCUS_UP_INLINE float upsampleDepth(vec4 z, vec4 b, float sum) {
    MENISCUS_UP_EXACT vec4 inv = vec4(1.0f / z.x, 1.0f / z.y, 1.0f / z.z, 1.0f / z.w);
    MENISCUS_UP_EXACT float r = 1.0f / upsampleLinear(inv, b, sum);
    return r;
}

// The normal: the blended taps' normals weighted, normalised (the first
// blended tap's normal when they cancel).
MENISCUS_UP_INLINE vec3 upsampleNormal(vec3 n0, vec3 n1, vec3 n2, vec3 n3, vec4 b) {
    MENISCUS_UP_EXACT vec3 s = ((b.x * n0 + b.y * n1) + b.z * n2) + b.w * n3;
    MENISCUS_UP_EXACT float len2 = (s.x * s.x + s.y * s.y) + s.z * s.z;
    if (!(len2 > 0.0f)) return b.x > 0.0f ? n0 : b.y > 0.0f ? n1 : b.z > 0.0f ? n2 : n3;
    MENISCUS_UP_EXACT float inv = 1.0f / sqrt(len2);
    MENISCUS_UP_EXACT vec3 n = vec3(s.x * inv, s.y * inv, s.z * inv);
    return n;
}

// The colour of a fluid pixel of coverage c blended into the scene behind
// it (rgb and alpha alike) as the silhouette reduction blends:
// behind + c (fluid - behind); c >= 1: unchanged.
MENISCUS_UP_INLINE vec4 upsampleEdgeBlend(vec4 fluid, vec4 behind, float c) {
    return c >= 1.0f ? fluid : silhouetteBlend(fluid, behind, c);
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_UP_INLINE
#undef MENISCUS_UP_EXACT
#undef MENISCUS_UP_OUT
#undef MENISCUS_UP_INF

#endif  // MENISCUS_SHARED_UPSAMPLE_H
