// The refracted view ray of the shading stage (docs/pipeline.md#shading),
// written once for C++ and GLSL (src/shared/ is compiled by C++ and included
// by the GL shaders): src/cpu/shading.cpp and shaders/shade.comp both call
// these functions, so both backends find the same background point with the
// same bits. In GLSL every intermediate is `precise` (no FMA contraction or
// reassociation), matching the CPU's plain IEEE arithmetic.
//
// The model. At a fluid pixel the view ray d meets the liquid's surface at P
// (the smoothed eye depth z) and bends by Snell's law, n1 sin(theta1) =
// n2 sin(theta2), in its vector form (GLSL's refract, eta = 1/ior; entering
// the denser medium there is no total internal reflection). The refracted ray
// t runs inside the liquid until it reaches the liquid's back, taken at eye
// depth zB = z + T (-d.z) (T, the thickness, is measured along the view ray);
// from that exit point E it goes on parallel to d, as the exit ray of a
// parallel-sided slab does. Material::refraction scales the bend: the ray's
// direction (scaled to z = -1) is d + refraction (t - d), so 1 is Snell's law
// and 0 the background straight behind.
//
// Both segments are straight lines in screen space, and along each the
// inverse eye depth w = 1/z is linear in the screen position (perspective
// projection): the inner one runs from the pixel p0 (w = 1/z) to E's
// projection p0 + e (w = 1/zB), the outer one from there back toward p0,
// reached at infinity (w = 0). So the path is a parameter s in [0, 2]: offset
// e (1 - |1 - s|) from p0, w linear in s on each half. The background seen is
// where that path first goes behind the scene layer's depth Zs (w Zs <= 1):
// a screen-space march after McGuire & Mara 2014 ("Efficient GPU Screen-Space
// Ray Tracing", JCGT 3(4)): a few steps of equal screen length along each
// segment (one per kRefractionStepPx, at most kRefractionMaxSteps), testing
// the nearest scene-depth texel, then kRefractionRefine bisections of the
// step that crossed. Where nothing is crossed (only sky behind) the path ends
// at infinity, whose projection is p0: the sky along the view ray, which the
// parallel exit ray sees.
#ifndef MENISCUS_SHARED_REFRACTION_H
#define MENISCUS_SHARED_REFRACTION_H

#ifdef __cplusplus
#include <algorithm>
#include <cmath>
namespace meniscus::shared {
using std::abs;
using std::max;
using std::min;
using std::sqrt;
#define MENISCUS_REFR_INLINE inline
#define MENISCUS_REFR_EXACT const  // C++: plain IEEE float arithmetic already
#define MENISCUS_REFR_OUT(T) T&
#define MENISCUS_REFR_VAR
#define MENISCUS_REFR_CONST inline constexpr
#else
#define MENISCUS_REFR_INLINE
#define MENISCUS_REFR_EXACT precise
#define MENISCUS_REFR_OUT(T) precise out T
#define MENISCUS_REFR_VAR precise
#define MENISCUS_REFR_CONST const
#endif

// The march: a step per this many pixels of screen length (each segment),
// at most kRefractionMaxSteps steps per segment, then kRefractionRefine
// bisections: a 30 px path ends within 30 / 6 / 2^6 ~ 0.08 px of the crossing.
MENISCUS_REFR_CONST float kRefractionStepPx = 3.0f;
MENISCUS_REFR_CONST int kRefractionMaxSteps = 6;
MENISCUS_REFR_CONST int kRefractionRefine = 5;

// The refracted ray grazes the surface only where the normal is
// turned away from the view axis (silhouettes); its slope is limited there to
// that of a ray 84 degrees off the axis (|t.z| >= 0.1), so the path stays on
// the screen's scale.
MENISCUS_REFR_CONST float kRefractionMinTz = 0.1f;

// The path of one fluid pixel. Inputs: rx, ry, the view ray (z = -1) and
// invLen = 1 / |(rx, ry, -1)|; (nx, ny, nz) the unit view-space normal (turned
// toward the viewer here if it faces away); z the eye depth, T the thickness
// (along the view ray, finite, >= 0); eta = 1 / ior; strength =
// Material::refraction; f the focal length in pixels. Outputs: (ex, ey) the
// exit point's offset from the pixel in pixels (column, row: row 0 is the top,
// hence the sign of ey) and wB = 1 / zB. Branch-free, so the CPU's batch loop
// vectorises it.
MENISCUS_REFR_INLINE void refractionExit(float rx, float ry, float invLen, float nx, float ny, float nz, float z,
                                         float T, float eta, float strength, float f, MENISCUS_REFR_OUT(float) ex,
                                         MENISCUS_REFR_OUT(float) ey, MENISCUS_REFR_OUT(float) wB) {
    MENISCUS_REFR_EXACT float dx = rx * invLen;
    MENISCUS_REFR_EXACT float dy = ry * invLen;
    MENISCUS_REFR_EXACT float dz = -invLen;
    // The normal toward the viewer: n.d <= 0.
    MENISCUS_REFR_EXACT float nd0 = nx * dx + ny * dy + nz * dz;
    bool away = nd0 > 0.0f;
    MENISCUS_REFR_EXACT float mx = away ? -nx : nx;
    MENISCUS_REFR_EXACT float my = away ? -ny : ny;
    MENISCUS_REFR_EXACT float mz = away ? -nz : nz;
    MENISCUS_REFR_EXACT float nd = away ? -nd0 : nd0;
    // Snell's law, refract(d, n, eta): t = eta d - (eta n.d + sqrt(k)) n with
    // k = 1 - eta^2 (1 - (n.d)^2). k > 0 always for eta < 1; k <= 0 (an ior
    // below 1) or NaN (ior 0 or not finite) keeps the view ray.
    MENISCUS_REFR_EXACT float k = 1.0f - eta * eta * (1.0f - nd * nd);
    bool ok = k > 0.0f;
    MENISCUS_REFR_EXACT float c = eta * nd + sqrt(max(k, 0.0f));
    MENISCUS_REFR_EXACT float tx = ok ? eta * dx - c * mx : dx;
    MENISCUS_REFR_EXACT float ty = ok ? eta * dy - c * my : dy;
    MENISCUS_REFR_EXACT float tz = ok ? eta * dz - c * mz : dz;
    // Its direction scaled to z = -1, the bend scaled by the strength.
    MENISCUS_REFR_EXACT float iz = 1.0f / max(-tz, kRefractionMinTz);
    MENISCUS_REFR_EXACT float ax = strength * (tx * iz - rx);
    MENISCUS_REFR_EXACT float ay = strength * (ty * iz - ry);
    // Eye depth travelled inside the liquid, h = T (-d.z); E = P + h (a, -1)
    // + h r projects at p0 + f a h / zB.
    MENISCUS_REFR_EXACT float h = T * invLen;
    MENISCUS_REFR_EXACT float zB = z + h;
    MENISCUS_REFR_EXACT float g = f * h / zB;
    ex = ax * g;
    ey = -(ay * g);
    wB = 1.0f / zB;
}

// The point of the path at parameter s in [0, 2]: its offset from the pixel
// (pixels) and its inverse eye depth w.
MENISCUS_REFR_INLINE void refractionPathAt(float s, float ex, float ey, float wz, float wB,
                                           MENISCUS_REFR_OUT(float) ox, MENISCUS_REFR_OUT(float) oy,
                                           MENISCUS_REFR_OUT(float) w) {
    MENISCUS_REFR_EXACT float q = 1.0f - abs(1.0f - s);
    ox = ex * q;
    oy = ey * q;
    MENISCUS_REFR_EXACT float wIn = wz + s * (wB - wz);
    MENISCUS_REFR_EXACT float wOut = wB * (2.0f - s);
    w = s <= 1.0f ? wIn : wOut;
}

// Steps per segment of a path with exit offset (ex, ey): one per
// kRefractionStepPx of its screen length (Chebyshev, pixels), at least 1, at
// most kRefractionMaxSteps (also for NaN).
MENISCUS_REFR_INLINE int refractionSteps(float ex, float ey) {
    MENISCUS_REFR_EXACT float len = max(abs(ex), abs(ey));
    return len < float(kRefractionMaxSteps - 1) * kRefractionStepPx ? 1 + int(len / kRefractionStepPx)
                                                                     : kRefractionMaxSteps;
}

// The texel holding continuous pixel position (px, py), clamped to the W x H
// image (NaN -> texel 0, as the bilinear fetch): std::min(max, std::max(0,
// v)) in the same form in GLSL.
MENISCUS_REFR_INLINE void refractionTexel(float px, float py, int W, int H, MENISCUS_REFR_OUT(int) ix,
                                          MENISCUS_REFR_OUT(int) iy) {
    float cx = 0.0f < px ? px : 0.0f;
    float cy = 0.0f < py ? py : 0.0f;
    cx = float(W - 1) < cx ? float(W - 1) : cx;
    cy = float(H - 1) < cy ? float(H - 1) : cy;
    ix = int(cx);
    iy = int(cy);
}

// Whether a path point of inverse eye depth w is behind a scene depth zs:
// 1/w >= zs. The sky (+inf) is never crossed (w zs = inf or, at w = 0, NaN).
MENISCUS_REFR_INLINE bool refractionIsBehind(float w, float zs) {
    MENISCUS_REFR_EXACT float wz = w * zs;
    return wz <= 1.0f;
}

#ifdef __cplusplus
// The scene's eye depth at the texel of (px, py) behind the path point?
template <class SceneDepthAt>
inline bool refractionBehind(float px, float py, float w, int W, int H, const SceneDepthAt& sceneDepthAt) {
#define MENISCUS_REFR_SCENE_DEPTH(ix, iy) sceneDepthAt(ix, iy)
#else
// GLSL: the includer defines float refractionSceneDepth(int x, int y) first.
bool refractionBehind(float px, float py, float w, int W, int H) {
#define MENISCUS_REFR_SCENE_DEPTH(ix, iy) refractionSceneDepth(ix, iy)
#endif
    int ix, iy;
    refractionTexel(px, py, W, H, ix, iy);
    return refractionIsBehind(w, MENISCUS_REFR_SCENE_DEPTH(ix, iy));
}
#undef MENISCUS_REFR_SCENE_DEPTH

// The background point the refracted path of pixel (p0x, p0y) (its centre,
// continuous pixel coordinates) sees: (px, py), continuous pixel coordinates
// to sample the scene colour at. wz = 1 / z; ex, ey, wB from refractionExit.
// Scalar: the march stops at the first crossing. (The CPU runs the same
// operations lane by lane over a batch of pixels, src/cpu/shading.cpp.)
#ifdef __cplusplus
template <class SceneDepthAt>
inline void refractionMarch(float p0x, float p0y, float ex, float ey, float wz, float wB, int W, int H,
                            const SceneDepthAt& sceneDepthAt, float& px, float& py) {
#define MENISCUS_REFR_BEHIND(qx, qy, w) refractionBehind(qx, qy, w, W, H, sceneDepthAt)
#else
void refractionMarch(float p0x, float p0y, float ex, float ey, float wz, float wB, int W, int H,
                     precise out float px, precise out float py) {
#define MENISCUS_REFR_BEHIND(qx, qy, w) refractionBehind(qx, qy, w, W, H)
#endif
    // A path that stays on the pixel (no bend, no thickness) sees what lies
    // straight behind, whatever the depths: skip the march.
    if (ex == 0.0f && ey == 0.0f) {
        px = p0x;
        py = p0y;
        return;
    }
    int n = refractionSteps(ex, ey);
    MENISCUS_REFR_EXACT float ds = 1.0f / float(n);
    // The last point (s = 2, w = 0: p0 at infinity) when nothing is crossed.
    float lo = 2.0f, hi = 2.0f;
    for (int i = 1; i <= 2 * n; ++i) {
        MENISCUS_REFR_EXACT float s = float(i) * ds;
        MENISCUS_REFR_VAR float ox, oy, w;
        refractionPathAt(s, ex, ey, wz, wB, ox, oy, w);
        MENISCUS_REFR_EXACT float qx = p0x + ox;
        MENISCUS_REFR_EXACT float qy = p0y + oy;
        if (MENISCUS_REFR_BEHIND(qx, qy, w)) {
            lo = float(i - 1) * ds;
            hi = s;
            break;
        }
    }
    // Bisect the step that crossed; the middle of the last bracket.
    if (lo < hi) {
        for (int j = 0; j < kRefractionRefine; ++j) {
            MENISCUS_REFR_EXACT float mid = 0.5f * (lo + hi);
            MENISCUS_REFR_VAR float ox, oy, w;
            refractionPathAt(mid, ex, ey, wz, wB, ox, oy, w);
            MENISCUS_REFR_EXACT float qx = p0x + ox;
            MENISCUS_REFR_EXACT float qy = p0y + oy;
            if (MENISCUS_REFR_BEHIND(qx, qy, w)) hi = mid;
            else lo = mid;
        }
    }
    MENISCUS_REFR_EXACT float sEnd = 0.5f * (lo + hi);
    MENISCUS_REFR_VAR float ox, oy, w;
    refractionPathAt(sEnd, ex, ey, wz, wB, ox, oy, w);
    px = p0x + ox;
    py = p0y + oy;
}
#undef MENISCUS_REFR_BEHIND

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_REFR_INLINE
#undef MENISCUS_REFR_EXACT
#undef MENISCUS_REFR_OUT
#undef MENISCUS_REFR_VAR
#undef MENISCUS_REFR_CONST

#endif  // MENISCUS_SHARED_REFRACTION_H
