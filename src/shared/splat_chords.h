// The thickness chords' fixed point (docs/pipeline.md#thickness; exact sums for sort-last rendering),
// written once for C++ and GLSL: src/cpu/splat.cpp and shaders/splat.comp turn
// each clipped chord into whole units with chordFixedUnits, add the units per
// pixel in 32-bit wrapping integers, and src/cpu/thickness.cpp and
// shaders/splat_resolve.comp turn a pixel's sum into metres with
// chordSumToMetres (`precise` in GLSL: no FMA contraction or reassociation).
//
// Why fixed point: a sum of integers is exact and does not depend on the
// order of its terms, so the GPU's atomics (GL 4.3 has no float atomics), the
// CPU's tiles and the sort-last compositor (include/meniscus/sort_last.h,
// which adds the partial sums of several processes) all give the same bits,
// however the particles were ordered or split.
//
// One unit is radius / kChordScale (the frame's radius r, also for
// ellipsoids and the particles' own radii): a uint then holds 2^32 / 2^15 / 2
// = 65,536 whole diameters per pixel (hundreds are typical), and one chord is
// rounded by at most 1.5e-5 r.
//
// chordFixedUnits is templated on the scalar type in C++ so the CPU can run
// it over its 4-lane vectors (cpu/splat.cpp); GLSL runs it on floats.
#ifndef MENISCUS_SHARED_SPLAT_CHORDS_H
#define MENISCUS_SHARED_SPLAT_CHORDS_H

#ifdef __cplusplus
#include <cstdint>
namespace meniscus::shared {
#define MENISCUS_CHORD_INLINE inline
#define MENISCUS_CHORD_CONST inline constexpr
#define MENISCUS_CHORD_EXACT const
#define MENISCUS_CHORD_TEMPLATE template <class MENISCUS_CHORD_REAL>
#define MENISCUS_CHORD_SPLAT(x) (MENISCUS_CHORD_REAL{} + (x))  // a scalar in every lane
#define MENISCUS_CHORD_UINT std::uint32_t
#else
#define MENISCUS_CHORD_INLINE
#define MENISCUS_CHORD_CONST const
#define MENISCUS_CHORD_EXACT precise
#define MENISCUS_CHORD_TEMPLATE
#define MENISCUS_CHORD_REAL float
#define MENISCUS_CHORD_SPLAT(x) (x)
#define MENISCUS_CHORD_UINT uint
#endif

// Units per radius.
MENISCUS_CHORD_CONST float kChordScale = 32768.0f;
// The largest float below 2^31 (2^31 - 128): a chord's units are clamped to it
// before the conversion to an integer, because converting a float at or past
// the integer type's range is undefined behaviour in C++ (and undefined in
// GLSL), and the CPU's vector lanes convert through signed 32-bit integers
// (x86's SSE2 has no unsigned conversion). Reached only by a chord of over
// 65,536 radii, which the spheres of the radius never have (at most 2 r); an
// own radius or an ellipsoid that large is clamped alike on both backends.
MENISCUS_CHORD_CONST float kChordMaxUnits = 2147483520.0f;

// A clipped chord of `chord` metres (> 0; the callers add nothing else) in
// units of radius / kChordScale, plus one half: its integer part (a
// conversion that truncates) is the chord rounded to the nearest unit.
MENISCUS_CHORD_TEMPLATE
MENISCUS_CHORD_INLINE MENISCUS_CHORD_REAL chordFixedUnits(MENISCUS_CHORD_REAL chord, float radius) {
    MENISCUS_CHORD_EXACT float scale = kChordScale / radius;
    MENISCUS_CHORD_EXACT MENISCUS_CHORD_REAL units = chord * scale + 0.5f;
    return units < kChordMaxUnits ? units : MENISCUS_CHORD_SPLAT(kChordMaxUnits);
}

// One chord as the integer that the per-pixel sums add.
MENISCUS_CHORD_INLINE MENISCUS_CHORD_UINT chordToFixed(float chord, float radius) {
    return MENISCUS_CHORD_UINT(chordFixedUnits(chord, radius));
}

// A pixel's summed units in metres, times the calibration weight `weight`
// (shared::thicknessWeight): its thickness before the blur.
MENISCUS_CHORD_INLINE float chordSumToMetres(MENISCUS_CHORD_UINT sum, float radius, float weight) {
    MENISCUS_CHORD_EXACT float toMetres = radius / kChordScale;
    MENISCUS_CHORD_EXACT float metres = (float(sum) * toMetres) * weight;
    return metres;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#else
#undef MENISCUS_CHORD_REAL
#endif
#undef MENISCUS_CHORD_INLINE
#undef MENISCUS_CHORD_CONST
#undef MENISCUS_CHORD_EXACT
#undef MENISCUS_CHORD_TEMPLATE
#undef MENISCUS_CHORD_SPLAT
#undef MENISCUS_CHORD_UINT

#endif  // MENISCUS_SHARED_SPLAT_CHORDS_H
