// Several fluids (docs/pipeline.md#several-fluids; Cords & Staadt 2008,
// "Instant Liquids" §5): each fluid is splatted, smoothed and shaded on its own
// (so the contours of different bodies are never smoothed together), then the
// fluids over each pixel are composited front to back. Written once for C++ and
// GLSL like upsample.h: src/cpu/shading.cpp and shaders/shade.comp split each
// fluid's shaded colour into what it sends to the eye itself and what it lets
// through, src/cpu/composite_fluids.cpp and shaders/composite_fluids.comp
// join the layers.
//
// The split: the shading (cpu/shading.cpp, eqs. 18-20) is affine in the
// background S it refracts, C = E + T S per channel, with
//   T = exp(-k thickness) (1 - opacity) (1 - F (1 - g)) (1 - foam) (1 - white)
// (the Beer-Lambert share, the opaque mix, the Fresnel weight with g the
// ground's share of the reflected direction, below the horizon where the
// reflection mirrors the liquid's own transmitted colour (sky.h,
// reflectionRadiance), and the two covers of foam and white water;
// (1 - opacity) only for opaque materials, where it is applied), and E = C - T S. Over a pixel with fluids 1..m
// sorted nearest first, the composite is
//   C = E_1 + T_1 (E_2 + T_2 (... E_{m-1} + T_{m-1} C_m))
// where C_m, the farthest fluid's own colour, refracts the scene as a single
// fluid does; the nearer ones see the fluids behind them unshifted (their
// refraction offset applies to the scene only, the choice Instant Liquids
// makes: it composites the separately shaded layers by depth).
#ifndef MENISCUS_SHARED_FLUIDS_H
#define MENISCUS_SHARED_FLUIDS_H

#ifdef __cplusplus
#include <glm/glm.hpp>
namespace meniscus::shared {
using glm::vec3;
#define MENISCUS_FL_INLINE inline
#define MENISCUS_FL_CONST inline constexpr
#define MENISCUS_FL_EXACT const
#else
#define MENISCUS_FL_INLINE
#define MENISCUS_FL_CONST const
#define MENISCUS_FL_EXACT precise
#endif

// The most fluids one frame may hold (fluid indices 0 .. kMaxFluids - 1): the
// GL composite reads every fluid's images in one pass, six buffer textures
// each, within the 32 texture units GL drivers give a compute shader.
MENISCUS_FL_CONST int kMaxFluids = 4;

// Whether a fluid's pixel of eye depth z lies in front of the scene (depth
// sceneZ, +inf where none): the test the shading uses to draw it.
MENISCUS_FL_INLINE bool fluidInFront(float z, float sceneZ) { return z < sceneZ && z > 0.0f; }

// T, the share of the light behind a fluid pixel that passes it (per channel):
// `absorb` = exp(-k thickness), `keepOpaque` = 1 - opacity (1 for transparent
// materials), F the Fresnel weight after the opaque mix, `ground` the
// reflected direction's groundShare (sky.h), and the foam and white-water
// covers (0 when off).
MENISCUS_FL_INLINE vec3 fluidTransmittance(vec3 absorb, float keepOpaque, float F, float ground, float foam,
                                           float white) {
    MENISCUS_FL_EXACT float k = keepOpaque * (1.0f - F * (1.0f - ground)) * (1.0f - foam) * (1.0f - white);
    MENISCUS_FL_EXACT vec3 t = vec3(absorb.x * k, absorb.y * k, absorb.z * k);
    return t;
}

// E = C - T S: the colour a fluid pixel sends over a black background.
MENISCUS_FL_INLINE vec3 fluidEmission(vec3 c, vec3 t, vec3 s) {
    MENISCUS_FL_EXACT vec3 e = vec3(c.x - t.x * s.x, c.y - t.y * s.y, c.z - t.z * s.z);
    return e;
}

// One step of the front-to-back composite: a fluid (E, T) over what is behind it.
MENISCUS_FL_INLINE vec3 fluidOver(vec3 e, vec3 t, vec3 behind) {
    MENISCUS_FL_EXACT vec3 c = vec3(e.x + t.x * behind.x, e.y + t.y * behind.y, e.z + t.z * behind.z);
    return c;
}

// A layer's split at a fluid-edge pixel of coverage c (reduced resolution:
// its colour is blended into the scene behind it by c, upsampleEdgeBlend):
// behind + c (E + T behind - behind) = c E + (c T + 1 - c) behind, so E' = c E
// and T' = c T + (1 - c); c >= 1 leaves both as they are.
MENISCUS_FL_INLINE vec3 fluidEdgeEmission(vec3 e, float c) {
    MENISCUS_FL_EXACT vec3 r = vec3(c * e.x, c * e.y, c * e.z);
    return c >= 1.0f ? e : r;
}
MENISCUS_FL_INLINE vec3 fluidEdgeTransmittance(vec3 t, float c) {
    MENISCUS_FL_EXACT float k = 1.0f - c;
    MENISCUS_FL_EXACT vec3 r = vec3(c * t.x + k, c * t.y + k, c * t.z + k);
    return c >= 1.0f ? t : r;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_FL_INLINE
#undef MENISCUS_FL_CONST
#undef MENISCUS_FL_EXACT

#endif  // MENISCUS_SHARED_FLUIDS_H
