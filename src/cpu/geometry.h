// CPU geometry stage (docs/geometry.md#how-it-is-drawn): the user's scene
// geometry drawn into the scene layer, after the studio and before the
// liquid, so the liquid is depth-tested against it and refracts it.
#pragma once

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/geometry.h"
#include "meniscus/types.h"
#include "cpu/raster_mesh.h"
#include "shared/environment.h"
#include "shared/studio.h"

namespace meniscus::cpu {

// Draws every visible object of `geometry` (the faces sceneFaces keeps,
// core/geometry_draw.h) seen by `camera` over `color` and `depth`
// (camera-sized; the studio's layer): each object's triangles are rasterised
// (rasteriseMesh: the nearest triangle's eye depth and interpolated normal
// per pixel centre, nothing at or behind `depth`), shaded by
// shared::geometryRadiance in the studio's light (`studio.lightDirWorld`) and
// written with their depth where nearer, objects in their list's order;
// then glass objects' back faces blended over the colour by
// shared::glassRadiance, the depth left as it is (the liquid inside shows).
// Bit-identical for any thread count. `reuse`: the rasteriser's images, kept
// by the caller across frames (their memory reused). Preconditions as rasteriseMesh's (the
// Renderer checks them): every mesh valid with normals.
void drawGeometry(const Camera& camera, const SceneGeometry& geometry, const shared::Studio& studio,
                  Image<glm::vec4>& color, Image<float>& depth, const shared::EnvironmentMap& environment = {},
                  MeshRaster* reuse = nullptr);

// The glass stage: the front faces of every drawn glass object over the
// finished picture `color` where they are nearer than both the liquid
// (`liquidDepth`, +inf where none) and the scene (`sceneDepth`), blended by
// shared::glassRadiance. (drawGeometry draws glass's back faces into the
// scene layer the same way, without writing its depth: the liquid inside a
// glass is seen through its walls, front faces over it, back faces behind.)
void drawGlassFronts(const Camera& camera, const SceneGeometry& geometry, const shared::Studio& studio,
                     const Image<float>& liquidDepth, const Image<float>& sceneDepth, Image<glm::vec4>& color,
                     const shared::EnvironmentMap& environment = {}, MeshRaster* reuse = nullptr);

}  // namespace meniscus::cpu
