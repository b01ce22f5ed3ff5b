// The bilinear mix of four texels, written once for C++ and GLSL like sky.h,
// for every map the stages sample between texel centres: the environment map
// (environment.h) and an object's base colour map (texture.h). Each caller
// finds its four texels and the fractions by its own wrap (the environment
// wraps in u and clamps in v, a base colour map repeats in both); the mix is
// this one. In GLSL every intermediate is `precise` (no fused multiply-add),
// matching the CPU's plain IEEE arithmetic, so both backends weigh the four
// texels to the same bits.
#ifndef MENISCUS_SHARED_BILINEAR_H
#define MENISCUS_SHARED_BILINEAR_H

#ifdef __cplusplus
#include <glm/glm.hpp>
namespace meniscus::shared {
using vec3 = glm::vec3;
#define MENISCUS_BILINEAR_INLINE inline
#define MENISCUS_BILINEAR_EXACT const
#else
#define MENISCUS_BILINEAR_INLINE
#define MENISCUS_BILINEAR_EXACT precise
#endif

// c00 at (0, 0), c10 one texel along x, c01 one along y, c11 diagonal; tx,
// ty in [0, 1] the fractions along x and y: first along x on both rows, then
// between the rows.
MENISCUS_BILINEAR_INLINE vec3 bilinearMix(vec3 c00, vec3 c10, vec3 c01, vec3 c11, float tx, float ty) {
    MENISCUS_BILINEAR_EXACT vec3 top = c00 * (1.0f - tx) + c10 * tx;
    MENISCUS_BILINEAR_EXACT vec3 bottom = c01 * (1.0f - tx) + c11 * tx;
    MENISCUS_BILINEAR_EXACT vec3 mixed = top * (1.0f - ty) + bottom * ty;
    return mixed;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_BILINEAR_INLINE
#undef MENISCUS_BILINEAR_EXACT

#endif  // MENISCUS_SHARED_BILINEAR_H
