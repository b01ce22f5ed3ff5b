// The per-frame parameter block, written once for C++ and GLSL (src/shared/ is
// compiled by C++ and included by the GL shaders). The GL backend fills it from
// the same RenderSettings the CPU backend reads (gl::packFrameParams) and
// uploads it as ONE std140 uniform block at binding 0, so every shader sees the
// same camera, radius and stage parameters.
// Layout rule that keeps std140 and the C++ struct identical: vec4/ivec4 first
// (16-byte aligned in both), then 4-byte scalars in groups of four; no vec3.
#ifndef MENISCUS_SHARED_FRAME_PARAMS_H
#define MENISCUS_SHARED_FRAME_PARAMS_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
namespace meniscus::shared {
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
#define MENISCUS_BLOCK_BEGIN(Name) struct alignas(16) Name {
#define MENISCUS_BLOCK_END(Name, instance) };
#else
#define MENISCUS_BLOCK_BEGIN(Name) layout(std140, binding = 0) uniform Name {
#define MENISCUS_BLOCK_END(Name, instance) } instance;
#endif

MENISCUS_BLOCK_BEGIN(FrameParams)
    // ---- camera (docs/conventions.md#conventions): world-space view axes;
    //      pixel rows from the top
    vec4 eye;            // xyz camera position (m); w = nearM
    vec4 right;          // xyz camera.right();  w = focalPx
    vec4 up;             // xyz camera.trueUp(); w = 1 / focalPx (rounded on the CPU)
    vec4 back;           // xyz camera.back();   w = farM
    ivec4 size;          // x = width, y = height (pixels); z, w unused
    // ---- shading (docs/pipeline.md#shading): Material + ShadingParams
    vec4 fluidColor;     // xyz linear RGB; w = opacity
    vec4 absorptionPerM; // xyz Beer-Lambert k (1/m); w = ior
    vec4 lightDirWorld;  // xyz toward the light (unit); w = refraction
    // ---- particles and normals
    float radius;        // particle radius r (m)
    float normalsJumpRadii;  // defaults::kDepthJumpRadii (normals' discontinuity test)
    float specular;      // Material::specular
    float shininess;     // Material::shininess
    // ---- smoothing (docs/pipeline.md#smoothing): the active filter's fields, the others 0
    int filterKind;      // 0 none, 1 gaussian, 2 bilateral, 3 binomial, 4 curvature flow, 5 narrow range
    int filterIterations;
    float filterJumpRadii;   // gaussian/bilateral/binomial/curvature flow jumpRadii
    int filterMaxKernelPx;   // gaussian/bilateral/binomial/narrow range maxKernelPx
    float gaussianSigmaRadii;
    float bilateralSigmaRadii;
    float bilateralRangeSigmaRadii;
    float binomialSizeRadii;
    float cfAlpha;           // curvature flow alpha
    float nrFilterSizeRadii; // narrow range filterSizeRadii
    float nrLambda;
    float nrMu;
    int nrSeparable;         // 1: the 1-D x-then-y approximation
    // ---- thickness (docs/pipeline.md#thickness)
    float thicknessWeight;   // w = s^3 / (4/3 pi r^3), shared::thicknessWeight
    float thicknessBlurSigmaRadii;
    int thicknessMaxKernelPx;
    int thicknessResolutionDivisor;
    float thicknessMinRadii;  // thin liquid: shaded at least this thick, radii (shared/hole_fill.h)
    int pad0;
    int pad1;
MENISCUS_BLOCK_END(FrameParams, P)

#ifdef __cplusplus
static_assert(sizeof(FrameParams) % 16 == 0, "std140 block size");
static_assert(offsetof(FrameParams, radius) == 8 * 16, "vec4s first, scalars after");
}  // namespace meniscus::shared
#endif
#undef MENISCUS_BLOCK_BEGIN
#undef MENISCUS_BLOCK_END

#endif  // MENISCUS_SHARED_FRAME_PARAMS_H
