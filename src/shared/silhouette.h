// The silhouette map's formulas (Cords & Staadt 2008, "Instant Liquids" §3;
// docs/pipeline.md#silhouette-reduction), written once for C++ and GLSL like
// spray.h: the window of a fluid pixel, its fluid fraction S from integer
// counts, the fade of S and the blend of the liquid into what lies behind it.
// The counts come from a summed-area table of the fluid mask (exact in 32-bit
// integers for any image the renderer accepts), so both backends get the same S
// bit for bit.
#ifndef MENISCUS_SHARED_SILHOUETTE_H
#define MENISCUS_SHARED_SILHOUETTE_H

#include "kernel_radius.h"

#ifdef __cplusplus
#include <algorithm>

#include <glm/glm.hpp>
namespace meniscus::shared {
using std::max;
using std::min;
using glm::ivec4;
using glm::vec4;
#define MENISCUS_SIL_INLINE inline
#define MENISCUS_SIL_EXACT const
#else
#define MENISCUS_SIL_INLINE
#define MENISCUS_SIL_EXACT precise
#endif

// The window of the pixel (x, y) of eye depth z: the half-width
// projectedRadiusPx(radiusM, f, z, maxPx) clipped to the W x H image, as
// [x0, x1) x [y0, y1).
MENISCUS_SIL_INLINE ivec4 silhouetteWindow(int x, int y, float z, float radiusM, float focalPx, int maxPx, int W,
                                           int H) {
    int R = projectedRadiusPx(radiusM, focalPx, z, maxPx);
    return ivec4(max(x - R, 0), max(y - R, 0), min(x + R + 1, W), min(y + R + 1, H));
}

// S: the fluid pixels `count` over the window's `area` (both > 0).
MENISCUS_SIL_INLINE float silhouetteFraction(int count, int area) {
    MENISCUS_SIL_EXACT float s = float(count) / float(area);
    return s;
}

// The liquid's alpha from S: 1 where the window is all fluid, fading from
// 1 to 0 as S falls from 1 to fadeFrom (fadeFrom = 1: 0 wherever S < 1).
MENISCUS_SIL_INLINE float silhouetteAlpha(float s, float fadeFrom) {
    if (s >= 1.0f) return 1.0f;
    if (fadeFrom >= 1.0f) return 0.0f;
    MENISCUS_SIL_EXACT float a = (s - fadeFrom) / (1.0f - fadeFrom);
    return min(max(a, 0.0f), 1.0f);
}

// The liquid's pixel `liquid` faded by alpha into `behind` (the scene's
// colour there; rgb and alpha alike): behind + alpha (liquid - behind).
MENISCUS_SIL_INLINE vec4 silhouetteBlend(vec4 liquid, vec4 behind, float alpha) {
    MENISCUS_SIL_EXACT vec4 d = liquid - behind;
    MENISCUS_SIL_EXACT vec4 r = behind + alpha * d;
    return r;
}

// Past the contour (anti-aliasing on the background side): a background
// pixel next to the liquid takes the mean colour of its fluid 8-neighbours
// (`sum` of `n` of them, in row order), faded into the scene behind it by the
// alpha of its own window's S, the window sized at the nearest of those
// neighbours' depths. With fadeFrom = 0.5 only pixels in a notch of the
// liquid (S > 0.5) get any; with a lower fadeFrom the fade continues past a
// straight contour, so it ends smoothly instead of at the pixel grid.
MENISCUS_SIL_INLINE vec4 silhouetteOuterColor(vec4 sum, int n) {
    MENISCUS_SIL_EXACT vec4 m = sum / float(n);
    return m;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_SIL_INLINE
#undef MENISCUS_SIL_EXACT

#endif  // MENISCUS_SHARED_SILHOUETTE_H
