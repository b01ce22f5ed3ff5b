// The separable depth filters' formulas (Gaussian, bilateral and binomial;
// docs/pipeline.md#smoothing), written once for C++ and GLSL like
// splat_chords.h: one 1-D pass (x or y) averages the taps around a centre
// pixel of depth z0, and src/cpu/filter_separable.h and
// shaders/filter_separable_pass.glsl both take its kernel radius, its tap
// weights and its result from here (`precise` in GLSL: no FMA contraction or
// reassociation), so the two give the same bits.
//
//  - The kernel radius s = kernelWorldM * f / z0 is the world length projected
//    at the centre depth z0 (constant width in world space; van der Laan,
//    Green & Sainz, patent "System and method for rendering a particle-based
//    fluid surface"), capped at the tables' largest radius.
//  - Weights come from the tables of shared::KernelTable, one normalised row
//    per integer radius n; a real radius s = n + t uses (1 - t) row(n) +
//    t row(n + 1) = row(n) + t diff(n). Rounding s instead would make the
//    smoothing jump where ceil(s) changes, which shows up as contour lines in
//    the normals of sloped fluid; blending keeps the output continuous in
//    depth (and so in scale).
//  - The bilateral filter (the thesis' eq. 4.3, split into passes as Pham &
//    van Vliet 2005) multiplies each weight by a Gaussian of the tap's depth
//    difference dz, exp(-dz^2 / (2 sigma^2)) = 2^-x with x = dz^2 / (2 sigma^2
//    ln 2): 2^-trunc(x) from the exponent bits times 2^-frac(x) =
//    2^-1/2 exp((1/2 - frac(x)) ln 2), a degree-5 Taylor series on |arg| <=
//    0.35 (relative error < 3e-6). Here the series; the truncation and the
//    exponent bits are each backend's (vector conversions and bit casts are
//    spelled differently in GLSL and in GCC's vector types).
//  - Taps that are +inf or further than the jump from z0 get weight 0 (each
//    backend masks them its own way) and the rest are renormalised: the
//    result is z0 plus the weighted mean of the taps' differences dz (not of
//    z: precision far from the eye).
// The taps are summed in groups of four (kTapGroup), one sum per lane, the
// lanes added in order at the end, so the sums see the same operands in the
// same order on both backends. The per-lane formulas are templated on the
// four-lane type in C++ (the CPU's lanes::FloatV); GLSL runs them on vec4.
#ifndef MENISCUS_SHARED_SEPARABLE_FILTER_H
#define MENISCUS_SHARED_SEPARABLE_FILTER_H

#ifdef __cplusplus
namespace meniscus::shared {
#define MENISCUS_SEP_INLINE inline
#define MENISCUS_SEP_EXACT const
#define MENISCUS_SEP_CONST inline constexpr
#define MENISCUS_SEP_TEMPLATE template <class MENISCUS_SEP_LANES>
#else
#define MENISCUS_SEP_INLINE
#define MENISCUS_SEP_EXACT precise
#define MENISCUS_SEP_CONST const
#define MENISCUS_SEP_TEMPLATE
#define MENISCUS_SEP_LANES vec4
#endif

// The kernel radius in pixels (not rounded) of the pass at centre depth z0 >
// 0: kernelPxDepth / z0 with kernelPxDepth = kernelWorldM * f, at most maxS
// (a NaN quotient gives maxS), and 0 where it is not positive.
MENISCUS_SEP_INLINE float separableKernelPx(float kernelPxDepth, float z0, float maxS) {
    MENISCUS_SEP_EXACT float q = kernelPxDepth / z0;
    float s = q < maxS ? q : maxS;
    if (!(s > 0.0f)) s = 0.0f;
    return s;
}

// The blend between the table rows n = int(s) and n + 1: t = s - n.
MENISCUS_SEP_INLINE float separableBlend(float s, int n) {
    MENISCUS_SEP_EXACT float t = s - float(n);
    return t;
}

// The spatial weights of four taps: row(n) + t diff(n) (a: the taps' entries
// of row(n), d: of diff(n)).
MENISCUS_SEP_TEMPLATE
MENISCUS_SEP_INLINE MENISCUS_SEP_LANES separableSpatialWeight(MENISCUS_SEP_LANES a, MENISCUS_SEP_LANES d, float t) {
    MENISCUS_SEP_EXACT MENISCUS_SEP_LANES w = a + t * d;
    return w;
}

// The bilateral range weight's exponent before its cap: x = dz^2 * scale,
// scale = 1 / (2 sigma^2 ln 2).
MENISCUS_SEP_TEMPLATE
MENISCUS_SEP_INLINE MENISCUS_SEP_LANES separableRangeExponent(MENISCUS_SEP_LANES dz, float scale) {
    MENISCUS_SEP_EXACT MENISCUS_SEP_LANES x = dz * dz * scale;
    return x;
}

// The cap of the exponent (dz > 9 sigma, e.g. excluded far taps): weights of
// 2^-60 and their products stay clear of denormals, which are very slow on x86.
MENISCUS_SEP_CONST float kSeparableRangeCap = 60.0f;

// The range weight 2^-x from the capped exponent x in [0, 60], its integer part
// whole = trunc(x) as a float and pow2 = 2^-trunc(x) (the exponent bits
// (127 - trunc(x)) << 23): pow2 times 2^-1/2 exp((1/2 - frac(x)) ln 2), the
// exponential by its Taylor series. The constants are the floats nearest
// 1/6, 1/24 and 1/120.
MENISCUS_SEP_TEMPLATE
MENISCUS_SEP_INLINE MENISCUS_SEP_LANES separableRangeWeight(MENISCUS_SEP_LANES x, MENISCUS_SEP_LANES whole,
                                                            MENISCUS_SEP_LANES pow2) {
    MENISCUS_SEP_EXACT MENISCUS_SEP_LANES y = (whole - x + 0.5f) * 0.69314718f;
    MENISCUS_SEP_EXACT MENISCUS_SEP_LANES p =
        1.0f + y * (1.0f + y * (0.5f + y * (0.166666672f + y * (0.0416666679f + y * 0.00833333377f))));
    MENISCUS_SEP_EXACT MENISCUS_SEP_LANES w = 0.70710678f * p * pow2;
    return w;
}

// The filtered depth from the centre depth z0 and the per-lane sums of the
// included taps' weights (sw, > 0 in all: the centre tap always counts) and
// weighted differences (sd), the lanes added in order.
MENISCUS_SEP_TEMPLATE
MENISCUS_SEP_INLINE float separableResult(float z0, MENISCUS_SEP_LANES sw, MENISCUS_SEP_LANES sd) {
    MENISCUS_SEP_EXACT float sumW = (((0.0f + sw[0]) + sw[1]) + sw[2]) + sw[3];
    MENISCUS_SEP_EXACT float sumD = (((0.0f + sd[0]) + sd[1]) + sd[2]) + sd[3];
    MENISCUS_SEP_EXACT float z = z0 + sumD / sumW;
    return z;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#else
#undef MENISCUS_SEP_LANES
#endif
#undef MENISCUS_SEP_INLINE
#undef MENISCUS_SEP_EXACT
#undef MENISCUS_SEP_CONST
#undef MENISCUS_SEP_TEMPLATE

#endif  // MENISCUS_SHARED_SEPARABLE_FILTER_H
