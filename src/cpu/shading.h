// CPU shading and compositing (SPEC §3.8): refraction, Beer-Lambert absorption,
// environment reflection, Schlick Fresnel, specular; composited over the scene.
#pragma once

#include "cpu/scene.h"
#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

// Linear RGBA image: the scene where there is no fluid (alpha from the scene),
// shaded fluid where depth is finite and in front of the scene (alpha 1). Where
// the scene is transparent (no background), refraction samples the sky.
// Bit-identical for any thread count.
Image<glm::vec4> shadeAndComposite(const Camera& camera, const SceneLayer& scene,
                                   const Image<float>& depth, const Image<glm::vec3>& normals,
                                   const Image<float>& thickness, const ShadingParams& params);

}  // namespace meniscus::cpu
