// The ellipsoid splat's geometry (anisotropic kernels, Yu & Turk 2013;
// docs/pipeline.md#depth-splat), written once for C++ and GLSL like
// kernel_radius.h: the shapes taken into view space, the exact projected bounds
// and the exact ray hit. Both backends call these, so their depth and chords agree
// to the rounding of sqrt and division.
//
// A particle's ellipsoid is E = {x : |M (x - c)| <= 1}: M is symmetric
// (R diag(1/a_k) R^T for axes a_k along the columns of R), Q = M^-2 =
// R diag(a_k^2) R^T its "outer" form (the support function of E is
// h(n) = n.c + sqrt(n^T Q n)). Both are kept per particle in world space
// (core/anisotropy.h) and taken to view space with the camera's axes.
//
// The ray hit is templated on the scalar type in C++ so the CPU can run it
// over its 4-lane vectors (cpu/splat.cpp); GLSL runs it on floats.
#ifndef MENISCUS_SHARED_ELLIPSOID_H
#define MENISCUS_SHARED_ELLIPSOID_H

#ifdef __cplusplus
#include <cmath>

#include <glm/glm.hpp>
namespace meniscus::shared {
using glm::mat3;
using glm::vec3;
using glm::vec4;
using std::sqrt;
#define MENISCUS_ELL_INLINE inline
#define MENISCUS_ELL_EXACT const
#define MENISCUS_ELL_TEMPLATE template <class MENISCUS_ELL_REAL>
#define MENISCUS_ELL_OUT(T) T&
#else
#define MENISCUS_ELL_INLINE
#define MENISCUS_ELL_EXACT precise
#define MENISCUS_ELL_TEMPLATE
#define MENISCUS_ELL_REAL float
#define MENISCUS_ELL_OUT(T) out T
#endif

// a . b, in this order on both backends.
MENISCUS_ELL_INLINE float ellipsoidDot(vec3 a, vec3 b) {
    MENISCUS_ELL_EXACT float d = a.x * b.x + a.y * b.y + a.z * b.z;
    return d;
}

// S v for a symmetric S (columns S[0], S[1], S[2]).
MENISCUS_ELL_INLINE vec3 ellipsoidMul(mat3 s, vec3 v) {
    MENISCUS_ELL_EXACT vec3 r = vec3(s[0].x * v.x + s[1].x * v.y + s[2].x * v.z,
                                     s[0].y * v.x + s[1].y * v.y + s[2].y * v.z,
                                     s[0].z * v.x + s[1].z * v.y + s[2].z * v.z);
    return r;
}

// The symmetric world-space S in view space, V S V^T with V's rows the
// camera's right, up and back axes (x, y, z of view space): entry (i, j) =
// axis_i . (S axis_j), made exactly symmetric.
MENISCUS_ELL_INLINE mat3 ellipsoidToView(mat3 s, vec3 right, vec3 up, vec3 back) {
    vec3 t0 = ellipsoidMul(s, right), t1 = ellipsoidMul(s, up), t2 = ellipsoidMul(s, back);
    float e00 = ellipsoidDot(right, t0), e01 = ellipsoidDot(right, t1), e02 = ellipsoidDot(right, t2);
    float e11 = ellipsoidDot(up, t1), e12 = ellipsoidDot(up, t2), e22 = ellipsoidDot(back, t2);
    return mat3(e00, e01, e02, e01, e11, e12, e02, e12, e22);
}

// The image-plane slopes (x / depth, y / depth; +y up) bounding the
// projection of the ellipsoid of view-space centre c and view-space outer
// form q, as (xlo, xhi, ylo, yhi) in `slopes`. Returns 0 when the ellipsoid
// lies wholly behind the eye, 1 when it reaches the eye plane (unbounded
// projection), 2 when the slopes are set. The bounds are the planes through
// the eye tangent to E: for n = (1, 0, s), (n . c)^2 = n^T q n is
// s^2 (D^2 - qzz) - 2 s (cx D + qxz) + (cx^2 - qxx) = 0 with D = -c.z the
// centre's eye depth; its discriminant is expanded so that no two large
// terms cancel (for the sphere q = r^2 I it is the sphere's r^2 (cx^2 + D^2 - r^2)).
MENISCUS_ELL_INLINE int ellipsoidSlopes(vec3 c, mat3 q, MENISCUS_ELL_OUT(vec4) slopes) {
    slopes = vec4(0.0f);
    MENISCUS_ELL_EXACT float depth = -c.z;
    MENISCUS_ELL_EXACT float qzz = q[2].z;
    MENISCUS_ELL_EXACT float extent = sqrt(qzz);  // E's half-extent along the view axis
    if (depth + extent <= 0.0f) return 0;
    if (depth - extent <= 0.0f) return 1;
    MENISCUS_ELL_EXACT float den = depth * depth - qzz;
    MENISCUS_ELL_EXACT float bx = c.x * depth + q[0].z;
    MENISCUS_ELL_EXACT float by = c.y * depth + q[1].z;
    MENISCUS_ELL_EXACT float qxzqzz = q[0].z * q[0].z - q[0].x * qzz;
    MENISCUS_ELL_EXACT float qyzqzz = q[1].z * q[1].z - q[1].y * qzz;
    MENISCUS_ELL_EXACT float discX = ((2.0f * c.x * depth * q[0].z + depth * depth * q[0].x) + c.x * c.x * qzz) + qxzqzz;
    MENISCUS_ELL_EXACT float discY = ((2.0f * c.y * depth * q[1].z + depth * depth * q[1].y) + c.y * c.y * qzz) + qyzqzz;
    MENISCUS_ELL_EXACT float rootX = sqrt(discX > 0.0f ? discX : 0.0f);
    MENISCUS_ELL_EXACT float rootY = sqrt(discY > 0.0f ? discY : 0.0f);
    slopes = vec4((bx - rootX) / den, (bx + rootX) / den, (by - rootY) / den, (by + rootY) / den);
    return 2;
}

// The ray from the eye along the unit direction u = (ux, uy, uz) against the
// ellipsoid of view-space shape m and e = m c (c its view-space centre):
// with d = m u, the ray parameter t (metres along u) of the point nearest the
// centre in E's metric is b = (d . e) / (d . d), and the ray meets E where
// (t - b)^2 <= q = (1 - |e - b d|^2) / (d . d): a hit when q >= 0, entering at
// b - sqrt(q) and leaving at b + sqrt(q). As in the sphere's test, the miss
// distance comes from the offset vector e - b d (precision for small, far
// ellipsoids). Per pixel: 9 products for d, then the sphere test's work.
MENISCUS_ELL_TEMPLATE
MENISCUS_ELL_INLINE void rayEllipsoid(MENISCUS_ELL_REAL ux, MENISCUS_ELL_REAL uy, MENISCUS_ELL_REAL uz, mat3 m, vec3 e,
                                      MENISCUS_ELL_OUT(MENISCUS_ELL_REAL) b, MENISCUS_ELL_OUT(MENISCUS_ELL_REAL) q) {
    MENISCUS_ELL_EXACT MENISCUS_ELL_REAL dx = (m[0].x * ux + m[1].x * uy) + m[2].x * uz;
    MENISCUS_ELL_EXACT MENISCUS_ELL_REAL dy = (m[0].y * ux + m[1].y * uy) + m[2].y * uz;
    MENISCUS_ELL_EXACT MENISCUS_ELL_REAL dz = (m[0].z * ux + m[1].z * uy) + m[2].z * uz;
    MENISCUS_ELL_EXACT MENISCUS_ELL_REAL dd = (dx * dx + dy * dy) + dz * dz;
    MENISCUS_ELL_EXACT MENISCUS_ELL_REAL de = (dx * e.x + dy * e.y) + dz * e.z;
    b = de / dd;
    MENISCUS_ELL_EXACT MENISCUS_ELL_REAL ox = e.x - b * dx;
    MENISCUS_ELL_EXACT MENISCUS_ELL_REAL oy = e.y - b * dy;
    MENISCUS_ELL_EXACT MENISCUS_ELL_REAL oz = e.z - b * dz;
    MENISCUS_ELL_EXACT MENISCUS_ELL_REAL h2 = 1.0f - ((ox * ox + oy * oy) + oz * oz);
    q = h2 / dd;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#else
#undef MENISCUS_ELL_REAL
#endif
#undef MENISCUS_ELL_INLINE
#undef MENISCUS_ELL_EXACT
#undef MENISCUS_ELL_TEMPLATE
#undef MENISCUS_ELL_OUT

#endif  // MENISCUS_SHARED_ELLIPSOID_H
