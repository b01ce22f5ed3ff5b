// The hole filling's formulas (docs/pipeline.md#hole-filling),
// written once for C++ and GLSL like silhouette.h: src/cpu/hole_fill.cpp and
// shaders/hole_fill.comp both use them, so they fill the same pixels with the
// same bits.
//
// A pixel the splat left uncovered inside a sheet (the gap between spheres
// that are a little too far apart, drawn untinted) is a hole when liquid of
// one surface closes it in on every side: along each of the four lines through
// it (the row, the column and both diagonals) a covered pixel lies on both of
// its sides within reachPx steps, the two ends on one surface (differing in
// depth by at most jumpRadii r, plus the climb of a slanted sheet over the
// line: not a body in front of another); and the gap
// is narrow: along at least three of the four lines the ends lie at most
// maxSpanRadii r apart (in pixels at the depth the line interpolates there: a
// gap that wide in the world, wherever it is). One line may be long: a slit
// between two rows of particles, seen at a slant, is a hole too.
// A filled pixel takes the mean of the four lines' interpolations: of the raw
// depth, and of the thickness where that exceeds the thickness already there
// (the blurred splat reaches a little into a hole). A gap open to one side
// (a bay in the outline, the space between two drops) finds no end toward the
// opening and stays background; so does a gap between layers at different
// depths.
#ifndef MENISCUS_SHARED_HOLE_FILL_H
#define MENISCUS_SHARED_HOLE_FILL_H

#ifdef __cplusplus
#include <algorithm>
#include <cmath>
namespace meniscus::shared {
using std::abs;
using std::max;
#define MENISCUS_HOLE_INLINE inline
#define MENISCUS_HOLE_EXACT const
#define MENISCUS_HOLE_CONST inline constexpr
#else
#define MENISCUS_HOLE_INLINE
#define MENISCUS_HOLE_EXACT precise
#define MENISCUS_HOLE_CONST const
#endif

// The four lines through a pixel, in the order both backends visit them:
// (dx, dy) = (1, 0), (0, 1), (1, 1), (1, -1).
MENISCUS_HOLE_INLINE int holeLineDx(int k) { return k == 1 ? 0 : 1; }
MENISCUS_HOLE_INLINE int holeLineDy(int k) { return k == 0 ? 0 : (k == 3 ? -1 : 1); }

// The value at a pixel a steps from one end (value va) and b steps from the
// other (value vb) of a line: the linear interpolation (b va + a vb) / (a + b).
MENISCUS_HOLE_INLINE float holeInterpolate(float va, float vb, int a, int b) {
    MENISCUS_HOLE_EXACT float s = float(b) * va + float(a) * vb;
    MENISCUS_HOLE_EXACT float v = s / float(a + b);
    return v;
}

// The length in pixels of a line with ends a and b steps away: a + b steps,
// each sqrt 2 pixels on a diagonal.
MENISCUS_HOLE_INLINE float holeLineLengthPx(int a, int b, bool diagonal) {
    MENISCUS_HOLE_EXACT float steps = float(a + b);
    MENISCUS_HOLE_EXACT float length = diagonal ? steps * 1.41421356f : steps;
    return length;
}

// The depth a surface may climb per metre across the view and still count as
// one surface between a line's ends: tan 63 degrees (a sheet seen at a slant).
MENISCUS_HOLE_CONST float kHoleMaxSlope = 2.0f;

// Whether the ends of a line (depths za, zb; lengthPx long, z the depth it
// interpolates between them) lie on one surface: they differ in depth by at
// most jumpRadii r plus what a slope of kHoleMaxSlope climbs over the line's
// length in the world (radiusM: r in metres; focalPx: focal length, pixels).
MENISCUS_HOLE_INLINE bool holeLineSameSurface(float za, float zb, float z, float lengthPx, float radiusM,
                                              float focalPx, float jumpRadii) {
    MENISCUS_HOLE_EXACT float lengthM = lengthPx * z / focalPx;
    MENISCUS_HOLE_EXACT float allowed = jumpRadii * radiusM + kHoleMaxSlope * lengthM;
    MENISCUS_HOLE_EXACT float dz = abs(za - zb);
    return dz <= allowed;
}

// Whether a line lengthPx long is narrow: at most maxSpanRadii r projected at
// the interpolated depth z.
MENISCUS_HOLE_INLINE bool holeLineNarrow(float z, float lengthPx, float radiusM, float focalPx, float maxSpanRadii) {
    MENISCUS_HOLE_EXACT float spanPx = maxSpanRadii * radiusM * focalPx / z;
    return lengthPx <= spanPx;
}

// At least this many of the four lines must be narrow.
MENISCUS_HOLE_CONST int kHoleNarrowLines = 3;

// The filled pixel's value from its four lines' interpolations, summed in a
// fixed order.
MENISCUS_HOLE_INLINE float holeMean(float v0, float v1, float v2, float v3) {
    MENISCUS_HOLE_EXACT float s = (v0 + v1) + (v2 + v3);
    MENISCUS_HOLE_EXACT float m = s * 0.25f;
    return m;
}

// The thickness a fluid pixel is shaded with: at least minRadii r, so thin
// liquid (the rim of a drop, a filled hole, a sheet one particle thick) is
// tinted as liquid and never drawn as the untinted background.
MENISCUS_HOLE_INLINE float thinLiquidThickness(float t, float minRadii, float radiusM) {
    MENISCUS_HOLE_EXACT float tMin = minRadii * radiusM;
    return max(t, tMin);
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_HOLE_INLINE
#undef MENISCUS_HOLE_EXACT
#undef MENISCUS_HOLE_CONST

#endif  // MENISCUS_SHARED_HOLE_FILL_H
