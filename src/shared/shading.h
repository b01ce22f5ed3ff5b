// Constants and host-side formulas of the shading stage
// (docs/pipeline.md#shading), written once for C++ and GLSL (src/shared/ is
// compiled by C++ and included by the GL shaders): src/cpu/shading.cpp and
// shaders/shade.comp both use them.
#ifndef MENISCUS_SHARED_SHADING_H
#define MENISCUS_SHARED_SHADING_H

#ifdef __cplusplus
#include <cmath>
namespace meniscus::shared {
#define MENISCUS_SHADING_CONST inline constexpr
#else
#define MENISCUS_SHADING_CONST const
#endif

// Share of the diffuse lighting of opaque materials that does not depend on the
// light direction (sky fill), so faces turned away from the key light are not black.
MENISCUS_SHADING_CONST float kOpaqueAmbient = 0.35f;

// The Blinn-Phong highlight k_s (n.h)^s is skipped where it is below this
// (invisible in any output format).
MENISCUS_SHADING_CONST float kHighlightCutoff = 1e-6f;

#ifdef __cplusplus
// The n.h below which the highlight is under kHighlightCutoff:
// (kHighlightCutoff / k_s)^(1/s); 2 (never reached) when there is none.
// Computed once per image on the host (a uniform on GL), so both backends
// skip the same pixels.
inline float highlightMinNh(float specular, float shininess) {
    return specular > kHighlightCutoff && shininess > 0.0f ? std::pow(kHighlightCutoff / specular, 1.0f / shininess)
                                                           : 2.0f;
}

}  // namespace meniscus::shared
#endif
#undef MENISCUS_SHADING_CONST

#endif  // MENISCUS_SHARED_SHADING_H
