// The spray drops' formulas (docs/pipeline.md#classification,
// docs/pipeline.md#noise-and-foam; the NVIDIA SSFR patent's spray, drawn as small
// particles rather than as part of the surface), written once for C++ and GLSL
// like surface_noise.h (whose exp and fixed point it uses), so the CPU reference
// (src/cpu/spray.cpp) and the GL twin draw the same bits. A drop is a soft disc
// swept along its screen-space path over the exposure (a capsule), its optical
// depth (1 - d^2)^2 opacity at distance d (in drop radii) from the path, divided
// by the path's length in diameters so a fast drop is a fainter streak, not a
// brighter one. Optical depths add (in fixed point: exact in any order), and a
// pixel shows the drops' colour over 1 - exp(-sum): order-independent, as drops of
// one colour need.
#ifndef MENISCUS_SHARED_SPRAY_H
#define MENISCUS_SHARED_SPRAY_H

#include "surface_noise.h"

#ifdef __cplusplus
namespace meniscus::shared {
#define MENISCUS_SP_INLINE inline
#define MENISCUS_SP_EXACT const
#else
#define MENISCUS_SP_INLINE
#define MENISCUS_SP_EXACT precise
#endif

// A drop on screen: its path from a to b (pixels, column and row from the
// top-left), its radius in pixels, its eye depth, its optical depth at the
// path (opacity over the path's length in diameters), and the pixels whose
// centres lie within the radius of the path, [x0, x1) x [y0, y1) clipped.
struct SprayDrop {
    vec2 a;
    vec2 b;
    float radiusPx;
    float z;
    float tau;
    ivec4 rect;
};

// The drop of view-space centre c (eye depth -c.z > near) moving at view-space
// velocity v: the path between the projections of c -+ v T / 2, collapsed to
// the centre when an end would reach the near plane; radius sizeM f / z.
MENISCUS_SP_INLINE SprayDrop sprayDrop(vec3 c, vec3 v, float f, int W, int H, float nearM, float sizeM, float streakS,
                                       float opacity) {
    MENISCUS_SP_EXACT float z = -c.z;
    MENISCUS_SP_EXACT float hx = v.x * (0.5f * streakS);
    MENISCUS_SP_EXACT float hy = v.y * (0.5f * streakS);
    MENISCUS_SP_EXACT float hz = v.z * (0.5f * streakS);
    MENISCUS_SP_EXACT float za = -(c.z - hz);
    MENISCUS_SP_EXACT float zb = -(c.z + hz);
    bool ends = za > nearM && zb > nearM;
    MENISCUS_SP_EXACT float ax = ends ? c.x - hx : c.x;
    MENISCUS_SP_EXACT float ay = ends ? c.y - hy : c.y;
    MENISCUS_SP_EXACT float bx = ends ? c.x + hx : c.x;
    MENISCUS_SP_EXACT float by = ends ? c.y + hy : c.y;
    MENISCUS_SP_EXACT float fa = f / (ends ? za : z);
    MENISCUS_SP_EXACT float fb = f / (ends ? zb : z);
    SprayDrop d;
    d.a = vec2(0.5f * float(W) + ax * fa, 0.5f * float(H) - ay * fa);
    d.b = vec2(0.5f * float(W) + bx * fb, 0.5f * float(H) - by * fb);
    MENISCUS_SP_EXACT float R = sizeM * (f / z);
    d.radiusPx = R;
    d.z = z;
    MENISCUS_SP_EXACT float lx = d.b.x - d.a.x;
    MENISCUS_SP_EXACT float ly = d.b.y - d.a.y;
    MENISCUS_SP_EXACT float len = sqrt(lx * lx + ly * ly);
    MENISCUS_SP_EXACT float diameters = len / (2.0f * R);
    d.tau = opacity / (1.0f + diameters);
    MENISCUS_SP_EXACT float x0 = floor(min(d.a.x, d.b.x) - R - 0.5f) + 1.0f;
    MENISCUS_SP_EXACT float x1 = floor(max(d.a.x, d.b.x) + R - 0.5f) + 1.0f;
    MENISCUS_SP_EXACT float y0 = floor(min(d.a.y, d.b.y) - R - 0.5f) + 1.0f;
    MENISCUS_SP_EXACT float y1 = floor(max(d.a.y, d.b.y) + R - 0.5f) + 1.0f;
    d.rect = ivec4(int(clamp(x0, 0.0f, float(W))), int(clamp(y0, 0.0f, float(H))), int(clamp(x1, 0.0f, float(W))),
                   int(clamp(y1, 0.0f, float(H))));
    return d;
}

// The drop's optical depth at pixel (px, py) in fixed point (kNoiseFixedScale
// units): tau (1 - d^2)^2 for the squared distance d^2 < 1 (drop radii) of the
// pixel's centre from the path, else 0.
MENISCUS_SP_INLINE int sprayContribution(SprayDrop d, int px, int py) {
    MENISCUS_SP_EXACT float qx = (float(px) + 0.5f) - d.a.x;
    MENISCUS_SP_EXACT float qy = (float(py) + 0.5f) - d.a.y;
    MENISCUS_SP_EXACT float ex = d.b.x - d.a.x;
    MENISCUS_SP_EXACT float ey = d.b.y - d.a.y;
    MENISCUS_SP_EXACT float ee = ex * ex + ey * ey;
    MENISCUS_SP_EXACT float qe = qx * ex + qy * ey;
    MENISCUS_SP_EXACT float t = ee > 0.0f ? clamp(qe / ee, 0.0f, 1.0f) : 0.0f;
    MENISCUS_SP_EXACT float dx = qx - t * ex;
    MENISCUS_SP_EXACT float dy = qy - t * ey;
    MENISCUS_SP_EXACT float d2 = (dx * dx + dy * dy) / (d.radiusPx * d.radiusPx);
    if (!(d2 < 1.0f)) return 0;
    MENISCUS_SP_EXACT float w = 1.0f - d2;
    return noiseToFixed(d.tau, w * w, 1.0f);
}

// The drops' cover of a pixel from its summed fixed-point optical depth.
MENISCUS_SP_INLINE float sprayCover(int sum) {
    MENISCUS_SP_EXACT float tau = float(sum) / kNoiseFixedScale;
    MENISCUS_SP_EXACT float c = 1.0f - noiseExp(-tau);
    return c;
}

// The colour under cover `cover` of drops of colour `drop` lit by `lit` per
// colour (studio.h's sprayLight, once per image on the host: the ambient,
// the studio's or an HDR map's, plus the key light's share), as the foam is.
MENISCUS_SP_INLINE vec3 sprayOver(vec3 c, float cover, vec3 drop, vec3 lit) {
    return noiseWithFoamLit(c, cover, lit, drop);
}

// The alpha under cover `cover` laid over alpha `a` (the "over" operator's).
MENISCUS_SP_INLINE float sprayAlphaOver(float a, float cover) {
    MENISCUS_SP_EXACT float r = a + cover * (1.0f - a);
    return r;
}

#ifdef __cplusplus
// The drop of world position `p` moving at world velocity `v` (host side,
// both backends, the same floats): view space by the camera's axes (glm::dot,
// eye at `eye`), then sprayDrop. False when its centre is not in front of the
// near plane (nothing to draw).
inline bool sprayDropOfWorld(vec3 p, vec3 v, vec3 eye, vec3 right, vec3 up, vec3 back, float f, int W, int H,
                             float nearM, float sizeM, float streakS, float opacity, SprayDrop& out) {
    const vec3 d = p - eye;
    const vec3 c{glm::dot(d, right), glm::dot(d, up), glm::dot(d, back)};
    if (!(-c.z > nearM)) return false;
    const vec3 vv{glm::dot(v, right), glm::dot(v, up), glm::dot(v, back)};
    out = sprayDrop(c, vv, f, W, H, nearM, sizeM, streakS, opacity);
    return true;
}

// The drops' key-light term (host side, once per frame for both backends,
// through studio.h's sprayLight): the view-space z of the unit light
// direction, as a drop's mean normal faces the eye; `back` is the camera's
// view z axis in world space (Camera::back()). No light direction: lit face on.
inline float sprayLightZ(vec3 lightDirWorld, vec3 back) {
    const float len = glm::length(lightDirWorld);
    return len > 0.0f ? glm::dot(lightDirWorld / len, back) : 1.0f;
}
}  // namespace meniscus::shared
#endif
#undef MENISCUS_SP_INLINE
#undef MENISCUS_SP_EXACT

#endif  // MENISCUS_SHARED_SPRAY_H
