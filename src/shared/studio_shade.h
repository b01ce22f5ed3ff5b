// How the studio's planes look (docs/pipeline.md#scene), written once for C++
// and GLSL (src/shared/ is compiled by C++ and included by the GL shaders):
// checker colours, the flat key + ambient lighting, the far fade into the sky,
// the checker parity, the corner darkening and the floor-only studio's radius.
// cpu::castScene (src/cpu/scene.cpp) and shaders/scene.comp both use these;
// what is constant per image is computed once on the host by
// shared::studioShading (studio.h). In GLSL every intermediate is `precise`, matching the CPU's plain IEEE arithmetic.
#ifndef MENISCUS_SHARED_STUDIO_SHADE_H
#define MENISCUS_SHARED_STUDIO_SHADE_H

#ifdef __cplusplus
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
namespace meniscus::shared {
using vec3 = glm::vec3;
using std::clamp;
using std::max;
using std::sqrt;
#define MENISCUS_STUDIO_CONST inline constexpr
#define MENISCUS_STUDIO_INLINE inline
#define MENISCUS_STUDIO_EXACT const
#else
#define MENISCUS_STUDIO_CONST const
#define MENISCUS_STUDIO_INLINE
#define MENISCUS_STUDIO_EXACT precise
#endif

// Checker colours, linear RGB: a grey floor, cooler walls.
MENISCUS_STUDIO_CONST vec3 kStudioFloorLight = vec3(0.72f, 0.72f, 0.72f);
MENISCUS_STUDIO_CONST vec3 kStudioFloorDark = vec3(0.40f, 0.40f, 0.40f);
MENISCUS_STUDIO_CONST vec3 kStudioWallLight = vec3(0.62f, 0.64f, 0.68f);
MENISCUS_STUDIO_CONST vec3 kStudioWallDark = vec3(0.44f, 0.46f, 0.50f);

// Flat lighting of a plane with unit normal n: ambient + key * max(0, n . light)
// (one directional key light plus a sky-like ambient term).
MENISCUS_STUDIO_CONST float kStudioAmbient = 0.45f;
MENISCUS_STUDIO_CONST float kStudioKey = 0.55f;

// The infinite floor fades into the sky's own colour between these distances
// from the corner, in checker squares (hides the checker's aliasing far away).
MENISCUS_STUDIO_CONST float kStudioFadeStartSquares = 24.0f;
MENISCUS_STUDIO_CONST float kStudioFadeLengthSquares = 56.0f;

// floor(v) as an int; v is clamped first so far-away hits cannot overflow.
MENISCUS_STUDIO_INLINE int studioFloorInt(float v) {
    const float c = clamp(v, -1.0e6f, 1.0e6f);
    const int i = int(c);
    return i - (float(i) > c ? 1 : 0);
}

// Ambient-occlusion-like darkening toward a corner edge at distance d (0 at
// the edge), reaching `scale` (about one checker square).
MENISCUS_STUDIO_INLINE float studioCornerFall(float d, float scale) {
    MENISCUS_STUDIO_EXACT float u = max(0.0f, 1.0f - d / scale);
    MENISCUS_STUDIO_EXACT float uu = u * u;
    return uu;
}

// The floor-only studio's distance from the box's centre (a, b: the floor
// point's x and z from it), where the far fade is measured: radial, so the
// fade looks the same from every side as the camera turns.
MENISCUS_STUDIO_INLINE float studioFloorRadius(float a, float b) {
    MENISCUS_STUDIO_EXACT float aa = a * a;
    MENISCUS_STUDIO_EXACT float bb = b * b;
    MENISCUS_STUDIO_EXACT float r = sqrt(aa + bb);
    return r;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_STUDIO_CONST
#undef MENISCUS_STUDIO_INLINE
#undef MENISCUS_STUDIO_EXACT

#endif  // MENISCUS_SHARED_STUDIO_SHADE_H
