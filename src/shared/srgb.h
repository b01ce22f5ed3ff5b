// The sRGB transfer function (IEC 61966-2-1), written once for C++ and GLSL
// (src/shared/ is compiled by C++ and included by the GL shaders):
// the PNG writer (src/io/png_writer.cpp) and the viewer's present shader
// (src/gl/shaders/present.frag) both encode with it, so a window shows the
// 8-bit values a PNG of the same frame holds. C++ evaluates it in double, as
// the PNG writer always has; GLSL in float, which can move a value lying
// within ~1e-6 of a rounding boundary by one 8-bit step.
#ifndef MENISCUS_SHARED_SRGB_H
#define MENISCUS_SHARED_SRGB_H

#ifdef __cplusplus
#include <algorithm>
#include <cmath>
namespace meniscus::shared {
using SrgbReal = double;
using std::min;
using std::pow;
#define MENISCUS_SRGB_INLINE inline
#else
#define SrgbReal float
#define MENISCUS_SRGB_INLINE
#endif

// The sRGB-encoded value in [0, 1] of a linear value, which is clamped to
// [0, 1] first (NaN -> 0): no tone mapping beyond the clamp.
MENISCUS_SRGB_INLINE SrgbReal srgbEncode(SrgbReal linear) {
    SrgbReal x = linear > 0.0 ? min(linear, 1.0) : 0.0;
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#else
#undef SrgbReal
#endif
#undef MENISCUS_SRGB_INLINE

#endif  // MENISCUS_SHARED_SRGB_H
