// Shadows of the key light (docs/geometry.md#shadows), written once for C++
// and GLSL (src/shared/ is compiled by C++ and included by the GL shaders):
// where a scene point falls in the light's maps, its depth bias, and how much
// of the studio's lighting (ambient + key * n.l, studio_shade.h) is left.
// The geometry's shadow is a shadow map (Williams 1978, "Casting curved
// shadows on curved surfaces"): a point farther from the light than the
// nearest opaque surface there (plus a bias) does not see the key light. The
// liquid's shadow is coloured by Beer-Lambert's law: the key light crossing a
// chord T of liquid (its thickness seen from the light) keeps exp(-k T) per
// channel, as the FleX demo's coloured shadows do. In GLSL every
// intermediate is `precise`, matching the CPU's plain IEEE arithmetic.
#ifndef MENISCUS_SHARED_SHADOW_H
#define MENISCUS_SHARED_SHADOW_H

#ifdef __cplusplus
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
namespace meniscus::shared {
using vec3 = glm::vec3;
using ivec3 = glm::ivec3;
using std::abs;
using std::exp;
using std::floor;
using std::max;
using std::min;
using std::sqrt;
#define MENISCUS_SHADOW_CONST inline constexpr
#define MENISCUS_SHADOW_INLINE inline
#define MENISCUS_SHADOW_EXACT const
#define MENISCUS_SHADOW_OUT(T) T&
#else
#define MENISCUS_SHADOW_CONST const
#define MENISCUS_SHADOW_INLINE
#define MENISCUS_SHADOW_EXACT precise
#define MENISCUS_SHADOW_OUT(T) out T
#endif

// The light's maps' side (pixels): square, the camera just covering the
// bounds of the particles and the geometry (core/shadow_camera.h).
MENISCUS_SHADOW_CONST int kShadowMapPx = 1024;
// The depth bias: this many of the map's texels (metres at the bounds'
// centre), and as many again per unit of the slope tan(angle to the light),
// up to kShadowMaxSlope.
MENISCUS_SHADOW_CONST float kShadowBiasTexels = 1.5f;
MENISCUS_SHADOW_CONST float kShadowMaxSlope = 4.0f;

// The texel of the light's map (x, y; -1 outside) a world point P falls in,
// and its eye depth from the light (*depth, m), on the light camera of world
// axes right, up, back, eye `eye`, focal length f (pixels) and side `side`
// (pixels): the nearest texel, the same one on both backends.
MENISCUS_SHADOW_INLINE ivec3 shadowTexel(vec3 p, vec3 eye, vec3 right, vec3 up, vec3 back, float f, int side,
                                         MENISCUS_SHADOW_OUT(float) depth) {
    MENISCUS_SHADOW_EXACT vec3 d = p - eye;
    MENISCUS_SHADOW_EXACT float vx = d.x * right.x + d.y * right.y + d.z * right.z;
    MENISCUS_SHADOW_EXACT float vy = d.x * up.x + d.y * up.y + d.z * up.z;
    MENISCUS_SHADOW_EXACT float z = -(d.x * back.x + d.y * back.y + d.z * back.z);
    depth = z;
    if (!(z > 0.0f)) return ivec3(-1, -1, 0);
    MENISCUS_SHADOW_EXACT float halfSide = 0.5f * float(side);
    MENISCUS_SHADOW_EXACT float px = halfSide + f * vx / z;
    MENISCUS_SHADOW_EXACT float py = halfSide - f * vy / z;
    if (!(px >= 0.0f && px < float(side) && py >= 0.0f && py < float(side))) return ivec3(-1, -1, 0);
    return ivec3(int(floor(px)), int(floor(py)), 1);
}

// The view-space point of pixel (x, y) at eye depth z, for a camera of
// 1/focal `invF` and size W x H (docs/conventions.md#conventions).
MENISCUS_SHADOW_INLINE vec3 shadowViewPoint(float x, float y, float z, float invF, int W, int H) {
    MENISCUS_SHADOW_EXACT float vx = (x + 0.5f - 0.5f * float(W)) * invF;
    MENISCUS_SHADOW_EXACT float vy = -(y + 0.5f - 0.5f * float(H)) * invF;
    return vec3(vx * z, vy * z, -z);
}

// A scene pixel's view-space point *p and unit normal *n (facing the
// camera) from its eye depth z and its neighbours' (left, right, above,
// below; not finite where none): per axis the neighbour nearer in depth, so
// an edge does not bend the normal. False when no neighbour on an axis has
// a depth.
MENISCUS_SHADOW_INLINE bool shadowSurface(int x, int y, float z, float zl, float zr, float zu, float zd, float invF,
                                          int W, int H, MENISCUS_SHADOW_OUT(vec3) p, MENISCUS_SHADOW_OUT(vec3) n) {
    const float kBig = 3.0e38f;
    p = shadowViewPoint(float(x), float(y), z, invF, W, H);
    n = vec3(0.0f);
    const bool hasL = zl < kBig, hasR = zr < kBig, hasU = zu < kBig, hasD = zd < kBig;
    if (!(hasL || hasR) || !(hasU || hasD)) return false;
    MENISCUS_SHADOW_EXACT vec3 dx = (hasR && (!hasL || abs(zr - z) <= abs(z - zl)))
                                        ? shadowViewPoint(float(x + 1), float(y), zr, invF, W, H) - p
                                        : p - shadowViewPoint(float(x - 1), float(y), zl, invF, W, H);
    MENISCUS_SHADOW_EXACT vec3 dy = (hasD && (!hasU || abs(zd - z) <= abs(z - zu)))
                                        ? shadowViewPoint(float(x), float(y + 1), zd, invF, W, H) - p
                                        : p - shadowViewPoint(float(x), float(y - 1), zu, invF, W, H);
    MENISCUS_SHADOW_EXACT vec3 c = vec3(dx.y * dy.z - dx.z * dy.y, dx.z * dy.x - dx.x * dy.z, dx.x * dy.y - dx.y * dy.x);
    MENISCUS_SHADOW_EXACT float len2 = c.x * c.x + c.y * c.y + c.z * c.z;
    if (!(len2 > 0.0f)) return false;
    MENISCUS_SHADOW_EXACT float facing = -(c.x * p.x + c.y * p.y + c.z * p.z);
    MENISCUS_SHADOW_EXACT float s = (facing < 0.0f ? -1.0f : 1.0f) / sqrt(len2);
    n = c * s;
    return true;
}

// The depth bias (m) for a surface at n.l = nl (> 0) and texels of
// `texelM` metres: a few texels, more on slopes seen grazing by the light.
MENISCUS_SHADOW_INLINE float shadowBias(float nl, float texelM) {
    MENISCUS_SHADOW_EXACT float s = sqrt(max(0.0f, 1.0f - nl * nl)) / max(nl, 1.0f / kShadowMaxSlope);
    MENISCUS_SHADOW_EXACT float slope = min(s, kShadowMaxSlope);
    MENISCUS_SHADOW_EXACT float bias = texelM * kShadowBiasTexels * (1.0f + slope);
    return bias;
}

// The colour c of a scene point lit by the studio's ambient a and key k at
// n.l = nl (>= 0), with the key light's share scaled by `lit` (its
// visibility times the liquid's transmittance, per channel): c (a + k nl
// lit) / (a + k nl). Only the key light's share is taken away.
MENISCUS_SHADOW_INLINE vec3 shadowedColor(vec3 c, float a, float k, float nl, vec3 lit) {
    MENISCUS_SHADOW_EXACT float full = a + k * nl;
    MENISCUS_SHADOW_EXACT vec3 kept = (vec3(a) + (k * nl) * lit) / full;
    MENISCUS_SHADOW_EXACT vec3 out_ = c * kept;
    return out_;
}

// shadowedColor with the ambient given per colour (an HDR map's E(n) / pi:
// environment.h, docs/pipeline.md#environment-map): c (a + k nl lit) /
// (a + k nl) per channel. A channel with no light at all (a + k nl = 0) keeps c.
MENISCUS_SHADOW_INLINE vec3 shadowedColorRgb(vec3 c, vec3 a, float k, float nl, vec3 lit) {
    MENISCUS_SHADOW_EXACT float key = k * nl;
    MENISCUS_SHADOW_EXACT vec3 full = a + vec3(key, key, key);
    MENISCUS_SHADOW_EXACT vec3 part = a + key * lit;
    MENISCUS_SHADOW_EXACT vec3 out_ = vec3(full.x > 0.0f ? c.x * (part.x / full.x) : c.x,
                                           full.y > 0.0f ? c.y * (part.y / full.y) : c.y,
                                           full.z > 0.0f ? c.z * (part.z / full.z) : c.z);
    return out_;
}

// Beer-Lambert: the key light's transmittance through `thickness` metres of
// liquid of absorption k (1/m, per channel).
MENISCUS_SHADOW_INLINE vec3 liquidTransmittance(vec3 k, float thickness) {
    MENISCUS_SHADOW_EXACT vec3 t = vec3(exp(-k.x * thickness), exp(-k.y * thickness), exp(-k.z * thickness));
    return t;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_SHADOW_CONST
#undef MENISCUS_SHADOW_INLINE
#undef MENISCUS_SHADOW_EXACT
#undef MENISCUS_SHADOW_OUT

#endif  // MENISCUS_SHARED_SHADOW_H
