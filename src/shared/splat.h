// The depth splat's formulas (docs/pipeline.md#depth-splat; the chords of
// docs/pipeline.md#thickness), written once for C++ and GLSL like
// ellipsoid.h: src/cpu/splat.cpp and shaders/splat.comp both take a
// particle's view-space centre, the exact pixel bounds of its projection,
// each pixel's view ray, the ray's hit with the sphere, the hit's eye depth
// and its clipped chord from here (`precise` in GLSL: no FMA contraction or
// reassociation), so the two agree to the rounding of sqrt and division.
//
// This is the exact, perspective-correct version of the point-sprite depth of
// van der Laan et al. 2009 (US 8,947,430) and Cords & Staadt 2008 ("Instant
// Liquids", §2.1; its eq. 2 gives the projected radius, here the exact
// projected bounding box is used instead): every pixel whose ray hits the
// sphere of radius r gets the eye depth of the nearest intersection. The
// ellipsoids of the anisotropic kernels take their bounds and ray hit from
// ellipsoid.h and the rest from here.
//
// The per-pixel functions are templated on the scalar type in C++ so the CPU
// can run them over its 4-lane vectors (cpu/splat.cpp); GLSL runs them on
// floats. The square roots stay with the callers (the CPU's lanes take a
// vector square root of their own).
#ifndef MENISCUS_SHARED_SPLAT_H
#define MENISCUS_SHARED_SPLAT_H

#include "ellipsoid.h"

#ifdef __cplusplus
#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>
namespace meniscus::shared {
using glm::ivec4;
using glm::vec3;
using glm::vec4;
using std::ceil;
using std::clamp;
using std::floor;
using std::max;
using std::min;
using std::sqrt;
#define MENISCUS_SPLAT_INLINE inline
#define MENISCUS_SPLAT_EXACT const
#define MENISCUS_SPLAT_TEMPLATE template <class MENISCUS_SPLAT_REAL>
#define MENISCUS_SPLAT_OUT(T) T&
#else
#define MENISCUS_SPLAT_INLINE
#define MENISCUS_SPLAT_EXACT precise
#define MENISCUS_SPLAT_TEMPLATE
#define MENISCUS_SPLAT_REAL float
#define MENISCUS_SPLAT_OUT(T) out T
#endif

// The view-space centre of the world-space point p seen from eye with the
// camera's right, up and back axes (Camera::toView; each dot product summed
// (x + y) + z, as glm::dot).
MENISCUS_SPLAT_INLINE vec3 splatViewCentre(vec3 p, vec3 eye, vec3 right, vec3 up, vec3 back) {
    MENISCUS_SPLAT_EXACT vec3 d = p - eye;
    return vec3(ellipsoidDot(d, right), ellipsoidDot(d, up), ellipsoidDot(d, back));
}

// The image-plane slopes (x / depth, y / depth; +y up) bounding the
// projection of the sphere of view-space centre c and radius r, as (xlo, xhi,
// ylo, yhi) in `slopes`; returns 0, 1 or 2 as ellipsoidSlopes. The tangent
// lines from the eye to the sphere's cross-section in the xz (resp. yz) plane
// bound the projection exactly: the slopes are
// (a depth -+ r sqrt(a^2 + depth^2 - r^2)) / (depth^2 - r^2) for a = c.x or c.y.
MENISCUS_SPLAT_INLINE int splatSphereSlopes(vec3 c, float r, MENISCUS_SPLAT_OUT(vec4) slopes) {
    slopes = vec4(0.0f);
    MENISCUS_SPLAT_EXACT float depth = -c.z;  // eye depth of the centre
    if (depth + r <= 0.0f) return 0;          // wholly behind the eye
    if (depth - r <= 0.0f) return 1;          // reaches the eye plane: unbounded projection
    MENISCUS_SPLAT_EXACT float den = depth * depth - r * r;
    MENISCUS_SPLAT_EXACT float rootX = r * sqrt(max(c.x * c.x + den, 0.0f));
    MENISCUS_SPLAT_EXACT float rootY = r * sqrt(max(c.y * c.y + den, 0.0f));
    slopes = vec4((c.x * depth - rootX) / den, (c.x * depth + rootX) / den, (c.y * depth - rootY) / den,
                  (c.y * depth + rootY) / den);
    return 2;
}

// The pixels of a W x H image (focal length f, pixels) whose centres lie
// within the image-plane slopes (xlo, xhi, ylo, yhi), clipped to the image, as
// [x0, x1) x [y0, y1) in (x, y, z, w); empty when x0 >= x1 or y0 >= y1.
MENISCUS_SPLAT_INLINE ivec4 splatRectFromSlopes(vec4 slopes, int W, int H, float f) {
    MENISCUS_SPLAT_EXACT float cx = 0.5f * float(W);
    MENISCUS_SPLAT_EXACT float cy = 0.5f * float(H);
    // Pixel centres are at +0.5: pixel i is inside when i + 0.5 is in [lo, hi].
    MENISCUS_SPLAT_EXACT float xlo = cx + f * slopes.x;
    MENISCUS_SPLAT_EXACT float xhi = cx + f * slopes.y;
    MENISCUS_SPLAT_EXACT float ylo = cy - f * slopes.w;  // +y view is up, rows go down
    MENISCUS_SPLAT_EXACT float yhi = cy - f * slopes.z;
    // A hundredth of a pixel of slack against rounding in the slopes (float
    // error here is ~1e-3 px at 16k pixels); the exact ray test decides coverage.
    MENISCUS_SPLAT_EXACT float eps = 0.01f;
    MENISCUS_SPLAT_EXACT float x0 = ceil(xlo - 0.5f - eps);
    MENISCUS_SPLAT_EXACT float x1 = floor(xhi - 0.5f + eps);
    MENISCUS_SPLAT_EXACT float y0 = ceil(ylo - 0.5f - eps);
    MENISCUS_SPLAT_EXACT float y1 = floor(yhi - 0.5f + eps);
    return ivec4(max(0, int(clamp(x0, -1.0f, float(W) + 1.0f))),
                 max(0, int(clamp(y0, -1.0f, float(H) + 1.0f))),
                 min(W, int(clamp(x1, -1.0f, float(W) + 1.0f)) + 1),
                 min(H, int(clamp(y1, -1.0f, float(H) + 1.0f)) + 1));
}

// At reduced resolution (one output pixel per d x d block, its centre at
// d (i + 1/2)), the blocks whose centres lie in the projection of a rectangle
// [x0, x1) of full pixels, i.e. in (x0 - 1/2, x1 + 1/2): i in
// [splatLowBegin(x0, d), splatLowEnd(x1, d)) (numerators shifted to stay
// positive, so that the division floors).
MENISCUS_SPLAT_INLINE int splatLowBegin(int x0, int d) { return (2 * x0 - 1 - d + 8 * d) / (2 * d) - 3; }
MENISCUS_SPLAT_INLINE int splatLowEnd(int x1, int d) { return (2 * x1 + 1 - d + 2 * d - 1) / (2 * d); }

// The view ray's x (resp. y) per unit depth through a pixel whose centre lies
// at `centre` pixels along the row (resp. down the column); halfW = W / 2,
// halfH = H / 2, invF = 1 / f. Rows grow downward, view y upward.
MENISCUS_SPLAT_TEMPLATE
MENISCUS_SPLAT_INLINE MENISCUS_SPLAT_REAL splatRayX(MENISCUS_SPLAT_REAL centre, float halfW, float invF) {
    MENISCUS_SPLAT_EXACT MENISCUS_SPLAT_REAL r = (centre - halfW) * invF;
    return r;
}
MENISCUS_SPLAT_TEMPLATE
MENISCUS_SPLAT_INLINE MENISCUS_SPLAT_REAL splatRayY(MENISCUS_SPLAT_REAL centre, float halfH, float invF) {
    MENISCUS_SPLAT_EXACT MENISCUS_SPLAT_REAL r = -(centre - halfH) * invF;
    return r;
}

// The squared length of the ray (rx, ry, -1); its square root len makes the
// unit ray u = (rx, ry, -1) / len, along which a ray parameter t lies at eye
// depth t / len.
MENISCUS_SPLAT_TEMPLATE
MENISCUS_SPLAT_INLINE MENISCUS_SPLAT_REAL splatRayLength2(MENISCUS_SPLAT_REAL rx, MENISCUS_SPLAT_REAL ry) {
    MENISCUS_SPLAT_EXACT MENISCUS_SPLAT_REAL l2 = (rx * rx + ry * ry) + 1.0f;
    return l2;
}

// The unit ray u = (rx, ry, -1) / len (len: the square root of
// splatRayLength2) and 1 / len.
MENISCUS_SPLAT_TEMPLATE
MENISCUS_SPLAT_INLINE void splatUnitRay(MENISCUS_SPLAT_REAL rx, MENISCUS_SPLAT_REAL ry, MENISCUS_SPLAT_REAL len,
                                        MENISCUS_SPLAT_OUT(MENISCUS_SPLAT_REAL) ux,
                                        MENISCUS_SPLAT_OUT(MENISCUS_SPLAT_REAL) uy,
                                        MENISCUS_SPLAT_OUT(MENISCUS_SPLAT_REAL) uz,
                                        MENISCUS_SPLAT_OUT(MENISCUS_SPLAT_REAL) invLen) {
    ux = rx / len;
    uy = ry / len;
    uz = -1.0f / len;
    invLen = 1.0f / len;
}

// The ray from the eye along the unit direction u = (ux, uy, uz) against the
// sphere of view-space centre c and squared radius r2: the ray parameter b of
// the closest approach (u . c) and h2 = r2 - |c - b u|^2, the squared
// half-chord (a hit when h2 >= 0, entering at b - sqrt(h2) and leaving at
// b + sqrt(h2)). The miss distance comes from the offset vector, not
// c . c - b^2: precision for small spheres far away.
MENISCUS_SPLAT_TEMPLATE
MENISCUS_SPLAT_INLINE void raySphere(MENISCUS_SPLAT_REAL ux, MENISCUS_SPLAT_REAL uy, MENISCUS_SPLAT_REAL uz, vec3 c,
                                     float r2, MENISCUS_SPLAT_OUT(MENISCUS_SPLAT_REAL) b,
                                     MENISCUS_SPLAT_OUT(MENISCUS_SPLAT_REAL) h2) {
    // (Through locals: `precise` reaches what computes a precise variable, so
    // the out parameters take finished values.)
    MENISCUS_SPLAT_EXACT MENISCUS_SPLAT_REAL along = ux * c.x + uy * c.y + uz * c.z;
    MENISCUS_SPLAT_EXACT MENISCUS_SPLAT_REAL ox = c.x - along * ux;
    MENISCUS_SPLAT_EXACT MENISCUS_SPLAT_REAL oy = c.y - along * uy;
    MENISCUS_SPLAT_EXACT MENISCUS_SPLAT_REAL oz = c.z - along * uz;
    MENISCUS_SPLAT_EXACT MENISCUS_SPLAT_REAL miss = r2 - (ox * ox + oy * oy + oz * oz);
    b = along;
    h2 = miss;
}

// The eye depth of the nearest hit b - h (h = sqrt(h2)) along a ray whose
// direction has 1 / len = invLen.
MENISCUS_SPLAT_TEMPLATE
MENISCUS_SPLAT_INLINE MENISCUS_SPLAT_REAL splatHitDepth(MENISCUS_SPLAT_REAL b, MENISCUS_SPLAT_REAL h,
                                                        MENISCUS_SPLAT_REAL invLen) {
    MENISCUS_SPLAT_EXACT MENISCUS_SPLAT_REAL t0 = b - h;
    MENISCUS_SPLAT_EXACT MENISCUS_SPLAT_REAL z = t0 * invLen;
    return z;
}

// The chord of the hit [b - h, b + h] clipped to the ray parameters [tn, tf)
// (the near plane and the scene, each its eye depth times len): its length,
// not positive where nothing is left.
MENISCUS_SPLAT_TEMPLATE
MENISCUS_SPLAT_INLINE MENISCUS_SPLAT_REAL splatChord(MENISCUS_SPLAT_REAL b, MENISCUS_SPLAT_REAL h,
                                                     MENISCUS_SPLAT_REAL tn, MENISCUS_SPLAT_REAL tf) {
    MENISCUS_SPLAT_EXACT MENISCUS_SPLAT_REAL t0 = b - h;
    MENISCUS_SPLAT_EXACT MENISCUS_SPLAT_REAL t1 = b + h;
    MENISCUS_SPLAT_EXACT MENISCUS_SPLAT_REAL chord = (tf < t1 ? tf : t1) - (t0 < tn ? tn : t0);
    return chord;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#else
#undef MENISCUS_SPLAT_REAL
#endif
#undef MENISCUS_SPLAT_INLINE
#undef MENISCUS_SPLAT_EXACT
#undef MENISCUS_SPLAT_TEMPLATE
#undef MENISCUS_SPLAT_OUT

#endif  // MENISCUS_SHARED_SPLAT_H
