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
#include <array>
#include <cmath>
#include <cstddef>
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

// The linear value of an sRGB-encoded value in [0, 1] (the inverse of
// srgbEncode): the 8-bit images' decoding (PNG and JPEG textures and
// backdrops, a host application's 8-bit colour).
MENISCUS_SRGB_INLINE SrgbReal srgbDecode(SrgbReal encoded) {
    return encoded <= 0.04045 ? encoded / 12.92 : pow((encoded + 0.055) / 1.055, 2.4);
}

#ifdef __cplusplus
// The linear value of each 8-bit sRGB code k (srgbDecode(k / 255) rounded
// once to float): the one table every 8-bit decoding reads, the CPU's and,
// uploaded, the GL backend's, so both decode to the same bits.
inline const std::array<float, 256>& srgbDecodeTable() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int k = 0; k < 256; ++k) t[std::size_t(k)] = float(srgbDecode(double(k) / 255.0));
        return t;
    }();
    return table;
}
}  // namespace meniscus::shared
#else
#undef SrgbReal
#endif
#undef MENISCUS_SRGB_INLINE

#endif  // MENISCUS_SHARED_SRGB_H
