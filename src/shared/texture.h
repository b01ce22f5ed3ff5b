// A scene object's base colour map (GeometryMaterial::baseColorTexture),
// sampled once for C++ and GLSL like environment.h: bilinear between the
// four nearest texel centres (bilinear.h's mix), repeated beyond [0, 1] in
// both directions (the wrap glTF and OBJ files assume by default).
//
// Convention: texture coordinates (u, v) with (0, 0) at the image's
// bottom-left corner and (1, 1) at its top-right (Assimp's, for every format);
// the texels are stored row after row from the top, so texel (i, j) of a
// W x H image has its centre at u = (i + 0.5) / W, v = 1 - (j + 0.5) / H.
// No mipmaps: a texture seen from far away aliases (it is sampled at the
// pixel centre only).
//
// Texel reads differ between the languages: C++ reads TextureMap::texels,
// GLSL the storage buffer `textureTexels` that a shader including this header
// declares first. Both are RGB floats, 3 W H of them. In GLSL every
// intermediate is `precise`, matching the CPU's plain IEEE arithmetic.
#ifndef MENISCUS_SHARED_TEXTURE_H
#define MENISCUS_SHARED_TEXTURE_H

#include "bilinear.h"  // bilinearMix

#ifdef __cplusplus
#include <cmath>
#include <glm/glm.hpp>
namespace meniscus::shared {
using vec3 = glm::vec3;
using std::abs;
using std::floor;
struct TextureMap {
    const float* texels = nullptr;
    int width = 0, height = 0;
    bool enabled() const { return texels != nullptr && width > 0 && height > 0; }
};
#define MENISCUS_TEX_INLINE inline
#define MENISCUS_TEX_EXACT const
#define MENISCUS_TEX_TEXEL(tex, i) (tex).texels[i]
#else
struct TextureMap {
    int width, height;
};
#define MENISCUS_TEX_INLINE
#define MENISCUS_TEX_EXACT precise
#define MENISCUS_TEX_TEXEL(tex, i) textureTexels[i]
#endif

// A coordinate wrapped into [0, 1): its fractional part; not finite or
// beyond 2^23 (where a float has no fraction left), 0.
MENISCUS_TEX_INLINE float textureWrap(float t) {
    bool usable = abs(t) < 8388608.0f;  // false for NaN too
    MENISCUS_TEX_EXACT float s = usable ? t : 0.0f;
    return s - floor(s);
}

// The texel (i, j), i and j already wrapped.
MENISCUS_TEX_INLINE vec3 textureTexel(TextureMap tex, int i, int j) {
    const int k = 3 * (j * tex.width + i);
    return vec3(MENISCUS_TEX_TEXEL(tex, k), MENISCUS_TEX_TEXEL(tex, k + 1), MENISCUS_TEX_TEXEL(tex, k + 2));
}

// Linear RGB of the map at texture coordinates (u, v): bilinear, repeated.
MENISCUS_TEX_INLINE vec3 textureSample(TextureMap tex, float u, float v) {
    // Continuous texel coordinates with the texel centres at integers, x
    // rightward from the left edge, y downward from the top row.
    MENISCUS_TEX_EXACT float fx = textureWrap(u) * float(tex.width) - 0.5f;
    MENISCUS_TEX_EXACT float fy = textureWrap(1.0f - textureWrap(v)) * float(tex.height) - 0.5f;
    MENISCUS_TEX_EXACT float ix = floor(fx);
    MENISCUS_TEX_EXACT float iy = floor(fy);
    MENISCUS_TEX_EXACT float tx = fx - ix;
    MENISCUS_TEX_EXACT float ty = fy - iy;
    // ix, iy in [-1, size - 1]: -1 wraps to the last column or row, and a
    // float rounding of the wrapped coordinate to 1 is caught the same way.
    int i0 = int(ix);
    int j0 = int(iy);
    i0 = i0 < 0 ? i0 + tex.width : (i0 >= tex.width ? i0 - tex.width : i0);
    j0 = j0 < 0 ? j0 + tex.height : (j0 >= tex.height ? j0 - tex.height : j0);
    const int i1 = i0 + 1 >= tex.width ? 0 : i0 + 1;
    const int j1 = j0 + 1 >= tex.height ? 0 : j0 + 1;
    MENISCUS_TEX_EXACT vec3 c00 = textureTexel(tex, i0, j0);
    MENISCUS_TEX_EXACT vec3 c10 = textureTexel(tex, i1, j0);
    MENISCUS_TEX_EXACT vec3 c01 = textureTexel(tex, i0, j1);
    MENISCUS_TEX_EXACT vec3 c11 = textureTexel(tex, i1, j1);
    return bilinearMix(c00, c10, c01, c11, tx, ty);
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_TEX_INLINE
#undef MENISCUS_TEX_EXACT
#undef MENISCUS_TEX_TEXEL

#endif  // MENISCUS_SHARED_TEXTURE_H
