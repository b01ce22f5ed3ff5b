// A backdrop's depth as linear eye depth (include/meniscus/backdrop.h says
// what each kind means), written once for C++ and GLSL (src/shared/ is
// compiled by C++ and included by the GL shaders), so a backdrop from a file
// and a host application's depth texture are read by the same formula.
//
// The eye depth z of a point is its distance from the camera's plane along
// the view axis (docs/conventions.md). A ray distance r along the pixel's
// view ray d = (x, y, -1) (Camera::pixelRay, whose z is -1, so the point at
// eye depth z is z d) is z |d|: z = r / |d|. An OpenGL perspective projection
// with planes n and f maps eye depth z to window depth
// d = (f / (f - n)) (1 - n / z) (glDepthRange 0..1), whose inverse is
// z = n f / (f - d (f - n)).
#ifndef MENISCUS_SHARED_BACKDROP_H
#define MENISCUS_SHARED_BACKDROP_H

#ifdef __cplusplus
#include <cmath>
#include <limits>
namespace meniscus::shared {
using std::isinf;
using std::isnan;
#define MENISCUS_BACKDROP_CONST inline constexpr
#define MENISCUS_BACKDROP_INLINE inline
#define MENISCUS_BACKDROP_INF std::numeric_limits<float>::infinity()
#else
#define MENISCUS_BACKDROP_CONST const
#define MENISCUS_BACKDROP_INLINE
#define MENISCUS_BACKDROP_INF uintBitsToFloat(0x7F800000u)
#endif

// The kinds, as BackdropDepthKind numbers them.
MENISCUS_BACKDROP_CONST int kBackdropLinear = 0;
MENISCUS_BACKDROP_CONST int kBackdropRay = 1;
MENISCUS_BACKDROP_CONST int kBackdropBlender = 2;
MENISCUS_BACKDROP_CONST int kBackdropWindow = 3;
// A depth at or beyond this (metres) is a renderer's "nothing here" (Blender
// writes about 1e10 for its background).
MENISCUS_BACKDROP_CONST float kBackdropFarthestM = 1e9f;

// The eye depth (metres, +inf: nothing) of a backdrop value `raw` of kind
// `kind` at a pixel whose view ray (z = -1) has length `rayLength`; `nearM`
// and `farM` are the window kind's planes.
MENISCUS_BACKDROP_INLINE float backdropEyeDepth(float raw, int kind, float rayLength, float nearM, float farM) {
    if (isnan(raw) || isinf(raw)) return MENISCUS_BACKDROP_INF;
    if (kind == kBackdropWindow) {
        if (!(raw >= 0.0f) || !(raw < 1.0f)) return MENISCUS_BACKDROP_INF;
        return nearM * farM / (farM - raw * (farM - nearM));
    }
    if (!(raw > 0.0f) || raw >= kBackdropFarthestM) return MENISCUS_BACKDROP_INF;
    return kind == kBackdropRay ? raw / rayLength : raw;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_BACKDROP_CONST
#undef MENISCUS_BACKDROP_INLINE
#undef MENISCUS_BACKDROP_INF

#endif  // MENISCUS_SHARED_BACKDROP_H
