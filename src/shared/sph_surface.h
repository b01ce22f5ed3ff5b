// The SPH surface of the raycast stage (docs/pipeline.md#ray-cast-surface),
// written once for C++ and GLSL like ellipsoid.h: the cubic-spline kernel and
// the march of one ray to the iso level of the density. Both backends call
// these, so they take the same steps and differ only by the rounding of sqrt
// and division.
//
// Field: F(x) = sum_j W(|x - x_j| / h), W the cubic spline of Monaghan 1992
// (sph_kernels.h; here unnormalised, W(0) = 1; the rest value F0 of a lattice of spacing 2r
// turns it into a fraction of the rest density, shared::sphRestField), and
// its gradient up to the positive factor 1/h^2: grad F ~ sum_j G(q) (x - x_j),
// G(q) = W'(q) / q (finite at q = 0), which only the normal's direction uses.
//
// The march (sphRaycast): from eye depth t0 along the pixel's ray, samples
// every `step` metres until F >= iso (or, when t0 is already inside, back
// toward the eye until F < iso), then the linear interpolation of F between
// the ends of that step (regula falsi) and `newtonSteps` safeguarded Newton
// steps place the crossing; its eye depth is returned (+inf: no surface
// within maxSteps steps or before tMax) with the field's gradient there.
//
// Quiet cells are passed over: where the field's grid knows that F stays
// below iso all over a sample's cell (core/sph_field.h), that sample and the
// ones after it still in the cell are not summed; the F of the last one is
// summed only if the next sample turns out to be inside. The result is the
// same as without the skip, only cheaper.
//
// The caller supplies the field: in C++ a functor with field(p, F, grad),
// field.quiet(p) and field.lastInCell(origin, dir, t) (the ray parameter up
// to which the ray certainly stays in the cell of its point at t; t itself
// when unknown); in GLSL the functions sphFieldAt, sphQuiet and
// sphLastInCell, declared before this header is included.
#ifndef MENISCUS_SHARED_SPH_SURFACE_H
#define MENISCUS_SHARED_SPH_SURFACE_H

#include "sph_kernels.h"

#ifdef __cplusplus
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>
namespace meniscus::shared {
using glm::vec3;
using std::floor;
using std::max;
using std::min;
using std::sqrt;
#define MENISCUS_SPH_INLINE inline
#define MENISCUS_SPH_EXACT const
#define MENISCUS_SPH_PRECISE
#define MENISCUS_SPH_TEMPLATE template <class Field>
#define MENISCUS_SPH_FIELD_PARAM , const Field& field
#define MENISCUS_SPH_FIELD(p, f, g) field(p, f, g)
#define MENISCUS_SPH_LAST_IN_CELL(o, d, t) field.lastInCell(o, d, t)
#define MENISCUS_SPH_QUIET(p) field.quiet(p)
#define MENISCUS_SPH_OUT(T) T&
#define MENISCUS_SPH_INF std::numeric_limits<float>::infinity()
#else
#define MENISCUS_SPH_INLINE
#define MENISCUS_SPH_EXACT precise
#define MENISCUS_SPH_PRECISE precise
#define MENISCUS_SPH_TEMPLATE
#define MENISCUS_SPH_FIELD_PARAM
#define MENISCUS_SPH_FIELD(p, f, g) sphFieldAt(p, f, g)
#define MENISCUS_SPH_LAST_IN_CELL(o, d, t) sphLastInCell(o, d, t)
#define MENISCUS_SPH_QUIET(p) sphQuiet(p)
#define MENISCUS_SPH_OUT(T) out T
#define MENISCUS_SPH_INF uintBitsToFloat(0x7f800000u)
#endif

// W(q) and G(q) = W'(q) / q: sphKernel and sphKernelGradient (sph_kernels.h).

// The point at eye depth t of the ray from `origin` along `dir`.
MENISCUS_SPH_INLINE vec3 sphRayPoint(vec3 origin, vec3 dir, float t) {
    MENISCUS_SPH_EXACT vec3 p = vec3(origin.x + t * dir.x, origin.y + t * dir.y, origin.z + t * dir.z);
    return p;
}

// The world-space ray of the pixel whose view ray (Camera::pixelRay) is
// (rx, ry, -1): its point at eye depth t is eye + t dir.
MENISCUS_SPH_INLINE vec3 sphRayDir(float rx, float ry, vec3 right, vec3 up, vec3 back) {
    MENISCUS_SPH_EXACT vec3 d = vec3(rx * right.x + ry * up.x - back.x, rx * right.y + ry * up.y - back.y,
                                     rx * right.z + ry * up.z - back.z);
    return d;
}

// The unit view-space outward normal -grad F / |grad F| (grad in world
// space); facing the eye when the gradient is zero (a ray that starts and
// stays inside may end where the field is flat).
MENISCUS_SPH_INLINE vec3 sphNormalView(vec3 grad, vec3 right, vec3 up, vec3 back) {
    MENISCUS_SPH_EXACT vec3 v = vec3(-(grad.x * right.x + grad.y * right.y + grad.z * right.z),
                                     -(grad.x * up.x + grad.y * up.y + grad.z * up.z),
                                     -(grad.x * back.x + grad.y * back.y + grad.z * back.z));
    MENISCUS_SPH_EXACT float len = sqrt((v.x * v.x + v.y * v.y) + v.z * v.z);
    return len > 0.0f ? vec3(v.x / len, v.y / len, v.z / len) : vec3(0.0f, 0.0f, 1.0f);
}

// The ray's eye depth where F first reaches `iso` (see the header comment).
// origin, dir: world-space eye and the pixel's ray scaled so that the point at
// eye depth t is origin + t dir. tNear: the march never comes nearer the eye.
MENISCUS_SPH_TEMPLATE
MENISCUS_SPH_INLINE float sphRaycast(vec3 origin, vec3 dir, float t0, float tNear, float tMax, float step,
                                     int maxSteps, int newtonSteps, float iso, float invH2,
                                     MENISCUS_SPH_OUT(vec3) grad MENISCUS_SPH_FIELD_PARAM) {
    if (!(t0 < tMax)) return MENISCUS_SPH_INF;  // starts behind the scene: nothing to see
    float f = 0.0f;
    vec3 g = vec3(0.0f);
    MENISCUS_SPH_FIELD(sphRayPoint(origin, dir, t0), f, g);
    // [a, b]: a outside (F < iso, fa), b inside (F >= iso, fb).
    MENISCUS_SPH_PRECISE float a = t0, b = t0, fa = f, fb = f;
    bool found = false;
    if (f >= iso) {
        // Inside already: back toward the eye until outside (or the near plane).
        for (int k = 1; k < maxSteps; ++k) {
            MENISCUS_SPH_EXACT float t = t0 - float(k) * step;
            if (t < tNear) break;
            MENISCUS_SPH_FIELD(sphRayPoint(origin, dir, t), f, g);
            if (f < iso) {
                a = t, fa = f, found = true;
                break;
            }
            b = t, fb = f;
        }
        if (!found) {  // inside up to the near plane or the last step: the surface is there
            MENISCUS_SPH_FIELD(sphRayPoint(origin, dir, b), f, grad);
            return b;
        }
    } else {
        bool aSummed = true;  // fa is F(a); false after passing over a quiet cell
        for (int k = 1; k < maxSteps; ++k) {
            MENISCUS_SPH_EXACT float t = t0 + float(k) * step;
            if (t > tMax) break;
            if (MENISCUS_SPH_QUIET(sphRayPoint(origin, dir, t))) {
                MENISCUS_SPH_EXACT float last = floor((MENISCUS_SPH_LAST_IN_CELL(origin, dir, t) - t0) / step);
                k = int(max(float(k), min(last, float(maxSteps - 1))));
                MENISCUS_SPH_EXACT float tk = t0 + float(k) * step;
                a = tk, aSummed = false;
                continue;
            }
            MENISCUS_SPH_FIELD(sphRayPoint(origin, dir, t), f, g);
            if (f >= iso) {
                b = t, fb = f, found = true;
                break;
            }
            a = t, fa = f, aSummed = true;
        }
        if (!found) return MENISCUS_SPH_INF;
        if (!aSummed) MENISCUS_SPH_FIELD(sphRayPoint(origin, dir, a), fa, g);
    }
    // The linear interpolation of F across the bracket (regula falsi), then
    // Newton steps on F along the ray, each kept inside the bracket (else
    // its middle): dF/dt = (grad . dir) / h^2 with grad as summed here.
    MENISCUS_SPH_PRECISE float t = a + (b - a) * ((iso - fa) / (fb - fa));
    MENISCUS_SPH_FIELD(sphRayPoint(origin, dir, t), f, g);
    for (int i = 0; i < newtonSteps; ++i) {
        if (f >= iso) b = t;
        else a = t;
        MENISCUS_SPH_EXACT float slope = ((g.x * dir.x + g.y * dir.y) + g.z * dir.z) * invH2;
        MENISCUS_SPH_EXACT float next = t + (iso - f) / slope;
        t = next > a && next < b ? next : 0.5f * (a + b);  // also when the slope is 0 (next not finite)
        MENISCUS_SPH_FIELD(sphRayPoint(origin, dir, t), f, g);
    }
    grad = g;
    return t;
}

#ifdef __cplusplus
// F0: the raw field at a particle inside a simple cubic lattice of spacing 2r
// (refsurf's rest density), for support h = supportRadii r. It depends on the
// ratio only; summed in double over the kernel evaluated in float.
inline double sphRestField(float supportRadii) {
    const float h = supportRadii, spacing = 2.0f;
    const int m = int(std::ceil(h / spacing));
    double rest = 0.0;
    for (int i = -m; i <= m; ++i)
        for (int j = -m; j <= m; ++j)
            for (int k = -m; k <= m; ++k) {
                const float q = spacing * std::sqrt(float(i * i + j * j + k * k)) / h;
                if (q < 1.0f) rest += sphKernel(q);
            }
    return rest;
}
}  // namespace meniscus::shared
#endif
#undef MENISCUS_SPH_INLINE
#undef MENISCUS_SPH_EXACT
#undef MENISCUS_SPH_PRECISE
#undef MENISCUS_SPH_TEMPLATE
#undef MENISCUS_SPH_FIELD_PARAM
#undef MENISCUS_SPH_FIELD
#undef MENISCUS_SPH_LAST_IN_CELL
#undef MENISCUS_SPH_QUIET
#undef MENISCUS_SPH_OUT
#undef MENISCUS_SPH_INF

#endif  // MENISCUS_SHARED_SPH_SURFACE_H
