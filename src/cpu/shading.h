// CPU shading and compositing (docs/pipeline.md#shading): refraction,
// Beer-Lambert absorption, environment reflection, Schlick Fresnel, specular;
// composited over the scene.
#pragma once

#include "cpu/scene.h"
#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

// Schlick's reflectance at normal incidence for an interface air -> ior.
inline float fresnelF0(float ior) {
    const float q = (ior - 1.0f) / (ior + 1.0f);
    return q * q;
}

// Schlick's approximation of the Fresnel reflectance, cosTheta = n·v in [0, 1].
inline float schlickFresnel(float f0, float cosTheta) {
    const float m = 1.0f - cosTheta, m2 = m * m;
    return f0 + (1.0f - f0) * (m2 * m2 * m);
}

// Linear RGBA image: the scene where there is no fluid (alpha from the scene),
// shaded fluid where depth is finite and in front of the scene (alpha 1). Where
// the scene is transparent (no background), refraction samples the sky.
// Bit-identical for any thread count.
// With `noise` (the surface noise N, docs/pipeline.md#noise-and-foam) and its
// parameters, foam of cover shared::noiseFoamCover(N) is laid over the shaded
// fluid; with `whitening` (the velocity whitening map) and its parameters, then
// white water of cover strength * map.
// Several fluids (shared/fluids.h): where to put each fluid pixel's split of
// its colour C = E + T S, E (rgb, a = 1) and T (rgb, a = 0); both W x H,
// zero where this fluid is not drawn.
struct LayerSplit {
    Image<glm::vec4>* emission = nullptr;
    Image<glm::vec4>* transmit = nullptr;
};

Image<glm::vec4> shadeAndComposite(const Camera& camera, const SceneLayer& scene,
                                   const Image<float>& depth, const Image<glm::vec3>& normals,
                                   const Image<float>& thickness, const ShadingParams& params,
                                   const Image<float>* noise = nullptr, const NoiseParams* noiseParams = nullptr,
                                   const Image<float>* whitening = nullptr,
                                   const WhiteningParams* whiteningParams = nullptr,
                                   const LayerSplit* split = nullptr, float minThicknessRadii = 0.0f,
                                   float radiusM = 0.0f, const shared::EnvironmentMap& environment = {});

}  // namespace meniscus::cpu
