// The velocity whitening's formulas (docs/pipeline.md#noise-and-foam; Cords &
// Staadt, "Instant Liquids", §4: particle velocities projected to the screen as
// a velocity map, the liquid's colour shifted toward white by it; the Chinese
// curvature-flow patent's step S5 weakens colour by particle speed), written
// once for C++ and GLSL like surface_noise.h, whose sprites and culling it
// shares: each surface particle splats its whiteness (its speed through a
// threshold and a ramp) with the sprite's Gaussian and depth weight, and the
// map is the weighted mean, sum(w g white) / sum(w g), both sums in fixed point.
#ifndef MENISCUS_SHARED_VELOCITY_MAP_H
#define MENISCUS_SHARED_VELOCITY_MAP_H

#include "surface_noise.h"

#ifdef __cplusplus
namespace meniscus::shared {
#define MENISCUS_VM_INLINE inline
#define MENISCUS_VM_EXACT const
#define MENISCUS_VM_OUT(T) T&
#else
#define MENISCUS_VM_INLINE
#define MENISCUS_VM_EXACT precise
#define MENISCUS_VM_OUT(T) out T
#endif

// A particle's whiteness from its speed (m/s): 0 up to threshold, rising
// linearly to 1 over ramp (> 0) above it.
MENISCUS_VM_INLINE float whitenessOfSpeed(float speed, float threshold, float ramp) {
    MENISCUS_VM_EXACT float a = (speed - threshold) / ramp;
    return clamp(a, 0.0f, 1.0f);
}

// The fixed-point contributions of a sprite to pixel (px, py): weight times
// its Gaussian times the whiteness (into `white`) and without it (into
// `norm`); both 0 outside the sprite's disc.
MENISCUS_VM_INLINE void whiteningContribution(NoiseSprite sp, int px, int py, float weight, float whiteness,
                                              float sigma, MENISCUS_VM_OUT(int) white, MENISCUS_VM_OUT(int) norm) {
    MENISCUS_VM_EXACT vec2 s = noiseSpriteOffset(sp, px, py);
    MENISCUS_VM_EXACT float s2 = s.x * s.x + s.y * s.y;
    white = 0;
    norm = 0;
    if (!(s2 < 1.0f)) return;
    MENISCUS_VM_EXACT float g = noiseSpriteGaussian(s2, sigma);
    white = noiseToFixed(weight, g, whiteness);
    norm = noiseToFixed(weight, g, 1.0f);
}

// The map's value from the two sums: their ratio, 0 where no sprite reached.
MENISCUS_VM_INLINE float whiteningFromFixed(int white, int norm) {
    MENISCUS_VM_EXACT float v = norm > 0 ? float(white) / float(norm) : 0.0f;
    return v;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_VM_INLINE
#undef MENISCUS_VM_EXACT
#undef MENISCUS_VM_OUT

#endif  // MENISCUS_SHARED_VELOCITY_MAP_H
