// The key light's camera for the shadows (docs/geometry.md#shadows): the
// directional light emulated by a perspective camera far away along the
// light's direction, its square image just covering the particles and the
// scene geometry. Made once per frame on the host, so both backends draw
// and read the same light maps.
#pragma once

#include "core/backend.h"
#include "meniscus/camera.h"
#include "meniscus/renderer.h"

namespace meniscus {

// Whether the frame draws shadows: RenderSettings::shadows on, or auto with a
// visible scene-geometry object.
bool drawsShadows(const RenderSettings& s);

// The light camera of the frame (its particles, radius, geometry and studio
// light); the Renderer keeps it in FrameSettings::shadow.
ShadowLight shadowLight(const FrameSettings& s);

// The triangles that cast the geometry's shadow, as one mesh: of each
// visible opaque object the faces the scene draws of it (sceneFaces) as seen
// from the light at `lightEye` (a cut-away tank's walls facing the light let
// it in, as they let the camera see in). Glass casts no shadow.
void shadowCasters(const SceneGeometry* geometry, const glm::vec3& lightEye, TriangleMesh& out);

}  // namespace meniscus
