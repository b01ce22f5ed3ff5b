// The anisotropic kernels' per-particle formulas (Yu & Turk, "Reconstructing
// surfaces of particle-based fluids using anisotropic kernels", ACM TOG 32(1)
// 2013; docs/pipeline.md#anisotropic-kernels), written once for C++ and GLSL
// like ellipsoid.h: the neighbour weight, the closed-form eigen-decomposition
// of the weighted covariance, the ellipsoid's axes and the free surface's
// shift of its centre. shaders/anisotropy.comp runs them in float on
// covariances in units of R^2; src/core/anisotropy.cpp, the reference, runs
// the same closed forms in double on four particles at a time in its own
// vector code (docs/pipeline.md states the tolerance between the two).
//
// In C++ the functions are templates on the scalar type (T: double on the
// CPU); GLSL runs them on floats.
#ifndef MENISCUS_SHARED_ANISOTROPY_H
#define MENISCUS_SHARED_ANISOTROPY_H

#ifdef __cplusplus
#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>
namespace meniscus::shared {
using std::abs;
using std::acos;
using std::cos;
using std::max;
using std::min;
using std::sin;
using std::sqrt;
#define MENISCUS_ANI_INLINE inline
#define MENISCUS_ANI_TEMPLATE template <class T>
#define MENISCUS_ANI_REAL T
#define MENISCUS_ANI_VEC3 glm::vec<3, T>
#define MENISCUS_ANI_MAT3 glm::mat<3, 3, T>
#define MENISCUS_ANI_OUT(X) X&
#define MENISCUS_ANI_ATAN2(y, x) std::atan2(y, x)
#define MENISCUS_ANI_CBRT(x) std::cbrt(x)
// The smallest scale the eigen-decomposition tells from zero.
#define MENISCUS_ANI_TINY T(sizeof(T) == 8 ? 1e-300 : 1e-30)
#else
#define MENISCUS_ANI_INLINE
#define MENISCUS_ANI_TEMPLATE
#define MENISCUS_ANI_REAL float
#define MENISCUS_ANI_VEC3 vec3
#define MENISCUS_ANI_MAT3 mat3
#define MENISCUS_ANI_OUT(X) out X
#define MENISCUS_ANI_ATAN2(y, x) atan(y, x)
#define MENISCUS_ANI_CBRT(x) pow(x, 1.0 / 3.0)
#define MENISCUS_ANI_TINY 1e-30
#endif

// The weight of a neighbour at distance dist (d2 = dist^2) in a
// neighbourhood of radius R (invR3 = 1 / R^3): 1 - (dist / R)^3 (Yu & Turk
// eq. 11). A template in C++ so the CPU runs it on its float lanes.
MENISCUS_ANI_TEMPLATE
MENISCUS_ANI_INLINE MENISCUS_ANI_REAL anisotropyWeight(MENISCUS_ANI_REAL d2, MENISCUS_ANI_REAL dist, float invR3) {
    return 1.0f - d2 * dist * invR3;
}

// The symmetric matrix of unit axes r (columns) and values v along them:
// r diag(v) r^T.
MENISCUS_ANI_TEMPLATE
MENISCUS_ANI_INLINE MENISCUS_ANI_MAT3 anisotropyFromAxes(MENISCUS_ANI_MAT3 r, MENISCUS_ANI_VEC3 v) {
    MENISCUS_ANI_MAT3 s = MENISCUS_ANI_MAT3(MENISCUS_ANI_REAL(0));
    for (int k = 0; k < 3; ++k) s += v[k] * outerProduct(r[k], r[k]);
    return s;
}

// A unit vector orthogonal to the unit vector v.
MENISCUS_ANI_TEMPLATE
MENISCUS_ANI_INLINE MENISCUS_ANI_VEC3 anisotropyOrthogonal(MENISCUS_ANI_VEC3 v) {
    MENISCUS_ANI_VEC3 other = abs(v.x) < MENISCUS_ANI_REAL(0.6) ? MENISCUS_ANI_VEC3(1, 0, 0) : MENISCUS_ANI_VEC3(0, 1, 0);
    return normalize(cross(v, other));
}

// A unit eigenvector v of a for the eigenvalue lambda: the longest cross
// product of two rows of a - lambda I (they span the orthogonal complement
// when lambda is simple). False when all are ~0 (lambda is not simple).
MENISCUS_ANI_TEMPLATE
MENISCUS_ANI_INLINE bool anisotropyEigenvector(MENISCUS_ANI_MAT3 a, MENISCUS_ANI_REAL lambda, MENISCUS_ANI_REAL scale,
                                               MENISCUS_ANI_OUT(MENISCUS_ANI_VEC3) v) {
    MENISCUS_ANI_MAT3 b = a - lambda * MENISCUS_ANI_MAT3(MENISCUS_ANI_REAL(1));
    MENISCUS_ANI_VEC3 r0 = MENISCUS_ANI_VEC3(b[0][0], b[1][0], b[2][0]);
    MENISCUS_ANI_VEC3 r1 = MENISCUS_ANI_VEC3(b[0][1], b[1][1], b[2][1]);
    MENISCUS_ANI_VEC3 r2 = MENISCUS_ANI_VEC3(b[0][2], b[1][2], b[2][2]);
    MENISCUS_ANI_VEC3 best = cross(r0, r1);
    MENISCUS_ANI_REAL len2 = dot(best, best);
    MENISCUS_ANI_VEC3 c1 = cross(r0, r2);
    if (dot(c1, c1) > len2) best = c1, len2 = dot(c1, c1);
    MENISCUS_ANI_VEC3 c2 = cross(r1, r2);
    if (dot(c2, c2) > len2) best = c2, len2 = dot(c2, c2);
    if (!(len2 > MENISCUS_ANI_REAL(1e-20) * scale * scale * scale * scale)) return false;
    v = best / sqrt(len2);
    return true;
}

// The eigen-decomposition of the symmetric a: eigenvalues in descending
// order, the matching unit eigenvectors the columns of `vectors` (a
// right-handed frame; any frame for a multiple of the identity).
// Eigenvalues in closed form (O. K. Smith, "Eigenvalues of a symmetric 3 x 3
// matrix", CACM 4(4) 1961): with q = tr(a)/3 and p the scale of a - qI,
// B = (a - qI)/p has eigenvalues 2 cos(phi + 2 pi k / 3), where
// cos(3 phi) = det(B) / 2. Eigenvectors after J. Kopp ("Efficient numerical
// diagonalization of hermitian 3x3 matrices", 2008): the one of the
// eigenvalue farthest from the middle one by cross products (it is simple),
// the other two by diagonalising a in the plane orthogonal to it (a 2 x 2
// rotation).
MENISCUS_ANI_TEMPLATE
MENISCUS_ANI_INLINE void anisotropyEigen(MENISCUS_ANI_MAT3 a, MENISCUS_ANI_OUT(MENISCUS_ANI_VEC3) values,
                                         MENISCUS_ANI_OUT(MENISCUS_ANI_MAT3) vectors) {
    MENISCUS_ANI_REAL p1 = a[1][0] * a[1][0] + a[2][0] * a[2][0] + a[2][1] * a[2][1];
    MENISCUS_ANI_REAL q = (a[0][0] + a[1][1] + a[2][2]) / MENISCUS_ANI_REAL(3);
    MENISCUS_ANI_REAL p2 = (a[0][0] - q) * (a[0][0] - q) + (a[1][1] - q) * (a[1][1] - q) +
                           (a[2][2] - q) * (a[2][2] - q) + MENISCUS_ANI_REAL(2) * p1;
    MENISCUS_ANI_REAL p = sqrt(p2 / MENISCUS_ANI_REAL(6));
    MENISCUS_ANI_REAL scale = max(max(max(abs(a[0][0]), abs(a[1][1])), max(abs(a[2][2]), sqrt(p1))), MENISCUS_ANI_TINY);
    if (!(p > MENISCUS_ANI_REAL(1e-12) * scale)) {  // a multiple of the identity: any frame
        values = MENISCUS_ANI_VEC3(q);
        vectors = MENISCUS_ANI_MAT3(MENISCUS_ANI_REAL(1));
        return;
    }
    MENISCUS_ANI_MAT3 bm = (a - q * MENISCUS_ANI_MAT3(MENISCUS_ANI_REAL(1))) / p;
    MENISCUS_ANI_REAL r = min(max(determinant(bm) / MENISCUS_ANI_REAL(2), MENISCUS_ANI_REAL(-1)), MENISCUS_ANI_REAL(1));
    MENISCUS_ANI_REAL phi = acos(r) / MENISCUS_ANI_REAL(3);
    MENISCUS_ANI_REAL third = MENISCUS_ANI_REAL(2.0943951023931954923);  // 2 pi / 3
    MENISCUS_ANI_REAL e1 = q + MENISCUS_ANI_REAL(2) * p * cos(phi);
    MENISCUS_ANI_REAL e3 = q + MENISCUS_ANI_REAL(2) * p * cos(phi + third);
    values = MENISCUS_ANI_VEC3(e1, MENISCUS_ANI_REAL(3) * q - e1 - e3, e3);  // e1 >= e2 >= e3
    bool firstApart = values[0] - values[1] >= values[1] - values[2];
    MENISCUS_ANI_VEC3 v;
    if (!anisotropyEigenvector(a, firstApart ? values[0] : values[2], scale, v)) {
        vectors = MENISCUS_ANI_MAT3(MENISCUS_ANI_REAL(1));
        return;
    }
    MENISCUS_ANI_VEC3 u = anisotropyOrthogonal(v);
    MENISCUS_ANI_VEC3 w = cross(v, u);
    MENISCUS_ANI_REAL auu = dot(u, a * u), auw = dot(u, a * w), aww = dot(w, a * w);
    // The rotation by theta with tan(2 theta) = 2 auw / (auu - aww) diagonalises [[auu, auw], [auw, aww]].
    MENISCUS_ANI_REAL theta = MENISCUS_ANI_REAL(0.5) * MENISCUS_ANI_ATAN2(MENISCUS_ANI_REAL(2) * auw, auu - aww);
    MENISCUS_ANI_REAL c = cos(theta), s = sin(theta);
    MENISCUS_ANI_VEC3 x = c * u + s * w, y = -s * u + c * w;  // eigenvalues: the larger along x
    MENISCUS_ANI_REAL ex = dot(x, a * x), ey = dot(y, a * y);
    if (ex < ey) {
        MENISCUS_ANI_VEC3 t = x;
        x = y, y = t;
    }
    if (firstApart) {
        values[1] = max(ex, ey), values[2] = min(ex, ey);
        vectors = MENISCUS_ANI_MAT3(v, x, y);
    } else {
        values[0] = max(ex, ey), values[1] = min(ex, ey);
        vectors = MENISCUS_ANI_MAT3(x, y, v);
    }
    if (dot(cross(vectors[0], vectors[1]), vectors[2]) < MENISCUS_ANI_REAL(0)) vectors[2] = -vectors[2];
}

// The ellipsoid's half-axes from the covariance's eigenvalues sigma
// (descending, sigma[0] > 0) for a particle of radius `radius` (Yu & Turk
// eq. 13): the smaller at least 1/kr of the largest, then scaled to the
// volume of the sphere of that radius. Scale-free in sigma (any unit).
MENISCUS_ANI_TEMPLATE
MENISCUS_ANI_INLINE MENISCUS_ANI_VEC3 anisotropyAxes(MENISCUS_ANI_VEC3 sigma, MENISCUS_ANI_REAL kr,
                                                     MENISCUS_ANI_REAL radius) {
    MENISCUS_ANI_REAL lowest = sigma[0] / kr;
    MENISCUS_ANI_VEC3 s3 = MENISCUS_ANI_VEC3(sigma[0], max(sigma[1], lowest), max(sigma[2], lowest));
    return s3 * (radius / MENISCUS_ANI_CBRT(s3.x * s3.y * s3.z));
}

// Keeping a free surface where the spheres put it (AnisotropyParams::
// keepSurface), for a flattened ellipsoid (shortest half-axis a2 < radius
// along the unit axis2): at a free surface the neighbours' weighted mean
// offset mu lies inward along the shortest axis, and the ellipsoid would end
// radius - a2 short of the sphere's outer side. The shift of its centre:
// outward by that much, scaled by how one-sided the neighbourhood is (a flat
// half-space's mean offset is 9/28 R, a sheet's or the bulk's ~0: with
// w = 1 - (d/R)^3, E_w[d cos theta] over the half ball =
// (1/2) (R^4/4 - R^4/7) / (R^3/3 - R^3/6) = 9/28 R). mu and R in one unit,
// a2 and radius in another.
MENISCUS_ANI_TEMPLATE
MENISCUS_ANI_INLINE MENISCUS_ANI_VEC3 anisotropySurfaceShift(MENISCUS_ANI_VEC3 mu, MENISCUS_ANI_VEC3 axis2,
                                                             MENISCUS_ANI_REAL a2, MENISCUS_ANI_REAL radius,
                                                             MENISCUS_ANI_REAL R) {
    MENISCUS_ANI_REAL m = dot(mu, axis2);
    MENISCUS_ANI_REAL t = min(abs(m) / (MENISCUS_ANI_REAL(9) / MENISCUS_ANI_REAL(28) * R), MENISCUS_ANI_REAL(1));
    return ((m > MENISCUS_ANI_REAL(0) ? MENISCUS_ANI_REAL(-1) : MENISCUS_ANI_REAL(1)) * t * (radius - a2)) * axis2;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_ANI_INLINE
#undef MENISCUS_ANI_TEMPLATE
#undef MENISCUS_ANI_REAL
#undef MENISCUS_ANI_VEC3
#undef MENISCUS_ANI_MAT3
#undef MENISCUS_ANI_OUT
#undef MENISCUS_ANI_ATAN2
#undef MENISCUS_ANI_CBRT
#undef MENISCUS_ANI_TINY

#endif  // MENISCUS_SHARED_ANISOTROPY_H
