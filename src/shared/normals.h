// The normals' formulas (docs/pipeline.md#normals), written once for C++ and
// GLSL like hole_fill.h: src/cpu/normals.cpp and shaders/normals.comp both
// call them, so the two agree to the rounding of division and sqrt. After van
// der Laan, Green & Sainz 2009 (US 8,947,430, eqs. 3-6) and Cords & Staadt
// 2008 ("Instant Liquids" §2.3, perspective-correct normals): every fluid
// pixel is back-projected with its smoothed eye depth to the view-space point
// P = z * ray(x+1/2, y+1/2), and n = normalize(dP/dx × dP/dy).
//
//  - The exact inverse projection is used (the patent drops the W terms of its
//    eq. 5; keeping them costs nothing and makes a plane's normal exact).
//  - Per axis: the central difference where both neighbours continue the
//    surface; at a discontinuity (neighbour +inf, outside the image, |dz| above
//    the jump) or where the two one-sided differences disagree by more than
//    that, the one-sided difference with the smaller |dz| (patent), so the
//    normals of separate bodies never mix.
//  - With no usable neighbour along an axis, the tangent is the screen axis
//    made perpendicular to the view ray, i.e. the surface is taken to face the
//    camera along that axis (a one-pixel sliver faces the eye exactly).
//  - Image rows grow downward while view-space y grows upward, so the "y"
//    tangent is taken toward the row above: n = tx × tUp then has +z toward
//    the camera for a surface facing it.
// Branch-free (every candidate computed, one selected), so the CPU's row loop
// vectorises; `precise` in GLSL (no FMA contraction or reassociation).
#ifndef MENISCUS_SHARED_NORMALS_H
#define MENISCUS_SHARED_NORMALS_H

#ifdef __cplusplus
#include <cmath>
#include <limits>

#include <glm/glm.hpp>
namespace meniscus::shared {
using glm::vec3;
using std::abs;
using std::sqrt;
#define MENISCUS_NRM_INLINE inline
#define MENISCUS_NRM_EXACT const
#define MENISCUS_NRM_INF std::numeric_limits<float>::infinity()
// Both tests evaluated, `&` and `|` on bools: GCC then selects instead of
// branching (`&&` and `||` leave it branches or mixed masks).
#define MENISCUS_NRM_AND(a, b) ((a) & (b))
#define MENISCUS_NRM_OR(a, b) ((a) | (b))
#else
#define MENISCUS_NRM_INLINE
#define MENISCUS_NRM_EXACT precise
#define MENISCUS_NRM_INF uintBitsToFloat(0x7f800000u)
#define MENISCUS_NRM_AND(a, b) ((a) && (b))
#define MENISCUS_NRM_OR(a, b) ((a) || (b))
#endif

// The view ray's x (resp. y) per unit depth through the centre of column x
// (resp. row y), exactly as Camera::pixelRay computes it (halfW = W / 2,
// halfH = H / 2, focalPx f), so z * (normalsRayX, normalsRayY, -1) is
// camera.unproject(x + 1/2, y + 1/2, z). Rows grow downward, view y upward.
MENISCUS_NRM_INLINE float normalsRayX(int x, float halfW, float focalPx) {
    MENISCUS_NRM_EXACT float r = ((float(x) + 0.5f) - halfW) / focalPx;
    return r;
}
MENISCUS_NRM_INLINE float normalsRayY(int y, float halfH, float focalPx) {
    MENISCUS_NRM_EXACT float r = -((float(y) + 0.5f) - halfH) / focalPx;
    return r;
}

// a where c holds, else b; per component, so that the CPU's compiler selects
// (blends) instead of branching.
MENISCUS_NRM_INLINE vec3 normalsSelect(bool c, vec3 a, vec3 b) {
    return vec3(c ? a.x : b.x, c ? a.y : b.y, c ? a.z : b.z);
}

// Tangent along one image axis from the point p (depth z) and its two
// neighbours m (previous, depth zm) and q (next, depth zp), +inf depth when
// outside the image or no fluid; the fallback fb when neither is usable.
// Neighbours of infinite depth give non-finite points, but those are never
// selected (rejected by their depth first).
MENISCUS_NRM_INLINE vec3 normalsAxisTangent(vec3 p, float z, vec3 m, float zm, vec3 q, float zp, float jump, vec3 fb) {
    MENISCUS_NRM_EXACT float dzm = z - zm;  // +inf - finite = +inf: never usable
    MENISCUS_NRM_EXACT float dzp = zp - z;
    const bool okm = abs(dzm) <= jump;
    const bool okp = abs(dzp) <= jump;
    // Smooth surface: central difference. A crease (the two sides disagree):
    // the flatter side. One usable side: that one.
    MENISCUS_NRM_EXACT float crease = abs(dzp - dzm);
    const bool central = MENISCUS_NRM_AND(MENISCUS_NRM_AND(okm, okp), crease <= jump);
    const bool plus = MENISCUS_NRM_AND(okp, MENISCUS_NRM_OR(!okm, abs(dzp) < abs(dzm)));
    MENISCUS_NRM_EXACT vec3 qm = q - m;
    MENISCUS_NRM_EXACT vec3 qp = q - p;
    MENISCUS_NRM_EXACT vec3 pm = p - m;
    return normalsSelect(central, qm, normalsSelect(plus, qp, normalsSelect(okm, pm, fb)));
}

// The unit view-space normal (+z toward the camera) of the pixel of depth z
// with column ray rxc and row ray ryc, from its four neighbours' depths (zl,
// zr: left and right; zu, zd: the rows above and below; +inf outside the
// image or no fluid) and the rays of the columns left and right (rxl, rxr)
// and of the rows above and below (ryu, ryd); (0, 0, 0) where z is not fluid.
// jump: the largest |dz| (metres) a neighbour may lie from z and still
// continue the surface.
MENISCUS_NRM_INLINE vec3 normalsAt(float z, float zl, float zr, float zu, float zd, float rxc, float rxl, float rxr,
                                   float ryc, float ryu, float ryd, float jump) {
    MENISCUS_NRM_EXACT vec3 p = vec3(z * rxc, z * ryc, -z);
    // Unit view ray, for the fallback tangents and the orientation.
    // (Reciprocals times components rather than three divisions: divisions
    // dominate the CPU's loop; the difference is an ulp.)
    MENISCUS_NRM_EXACT float invLen = 1.0f / sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    MENISCUS_NRM_EXACT vec3 u = vec3(p.x * invLen, p.y * invLen, p.z * invLen);
    MENISCUS_NRM_EXACT vec3 ml = vec3(zl * rxl, zl * ryc, -zl);
    MENISCUS_NRM_EXACT vec3 qr = vec3(zr * rxr, zr * ryc, -zr);
    MENISCUS_NRM_EXACT vec3 fx = vec3(1.0f - u.x * u.x, 0.0f - u.x * u.y, 0.0f - u.x * u.z);
    MENISCUS_NRM_EXACT vec3 t = normalsAxisTangent(p, z, ml, zl, qr, zr, jump, fx);  // along +x (right)
    MENISCUS_NRM_EXACT vec3 md = vec3(zd * rxc, zd * ryd, -zd);
    MENISCUS_NRM_EXACT vec3 qu = vec3(zu * rxc, zu * ryu, -zu);
    MENISCUS_NRM_EXACT vec3 fy = vec3(0.0f - u.y * u.x, 1.0f - u.y * u.y, 0.0f - u.y * u.z);
    MENISCUS_NRM_EXACT vec3 s = normalsAxisTangent(p, z, md, zd, qu, zu, jump, fy);  // toward the row above (+y view)
    // n = t × s, written out so both sides take the same order.
    MENISCUS_NRM_EXACT vec3 n = vec3(t.y * s.z - s.y * t.z, t.z * s.x - s.z * t.x, t.x * s.y - s.x * t.y);
    MENISCUS_NRM_EXACT float nlen = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    const bool ok = nlen > 0.0f;  // degenerate tangents: face the camera
    MENISCUS_NRM_EXACT float invN = 1.0f / nlen;
    MENISCUS_NRM_EXACT vec3 nn = vec3(n.x * invN, n.y * invN, n.z * invN);
    MENISCUS_NRM_EXACT vec3 unit = normalsSelect(ok, nn, -u);
    MENISCUS_NRM_EXACT float nu = unit.x * u.x + unit.y * u.y + unit.z * u.z;
    const bool flip = MENISCUS_NRM_AND(ok, nu > 0.0f);  // toward the eye
    MENISCUS_NRM_EXACT vec3 facing = normalsSelect(flip, -unit, unit);
    return normalsSelect(z < MENISCUS_NRM_INF, facing, vec3(0.0f));
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_NRM_INLINE
#undef MENISCUS_NRM_EXACT
#undef MENISCUS_NRM_INF
#undef MENISCUS_NRM_AND
#undef MENISCUS_NRM_OR

#endif  // MENISCUS_SHARED_NORMALS_H
