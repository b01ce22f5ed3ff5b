// The default studio (docs/pipeline.md#scene) both backends ray-cast: its
// geometry, built once per frame from the particles' box, the camera and the
// light, and the lighting constants derived from it once per image. C++ only
// (the GL scene stage uploads what studioShading computes); the per-pixel
// formulas both backends evaluate are in studio_shade.h.
#pragma once

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/types.h"
#include "shared/environment.h"

namespace meniscus::shared {

// The studio's geometry and key light. All lengths in metres, world space.
struct Studio {
    bool enabled = true;       // false: sky only, transparent background
    // false: the floor alone (SceneParams::walls), no corner: wallX and wallZ
    // are then the box's centre, the origin of the checker and of the radial
    // far fade, with normals +1; wallTopY is unused.
    bool walls = true;
    float floorY = 0.0f;       // floor plane y = floorY, facing +y
    float wallX = 0.0f;        // back wall plane x = wallX, facing the camera side
    float wallXNormal = 1.0f;  // +1 or -1: the side of the wall the camera is on
    float wallZ = 0.0f;        // back wall plane z = wallZ
    float wallZNormal = 1.0f;
    float wallTopY = 1.0f;     // the walls end at this height; the sky shows above them
    float checkerM = 0.1f;     // checker square size
    // Unit, toward the key light that lights the planes and the sky's sun
    // (sunDirection of ShadingParams::lightDirWorld).
    glm::vec3 lightDirWorld{0.0f, 1.0f, 0.0f};

    bool operator==(const Studio&) const = default;
};

// The studio around `box` (params.studioBounds instead when not empty): floor
// just under the lowest sphere, walls ~1 radius outside the spheres on the far
// side of the box from the eye, checker ~1/8 of the horizontal extent rounded
// to 1, 2 or 5 x 10^k metres, lit from `lightDirWorld` (toward the light, need
// not be unit). params.background == false: enabled = false. The walls' sides
// are picked from params.wallsSeenFrom when set; params.walls == false: the
// floor alone, centred under the box.
Studio makeStudio(const Bounds& box, float radius, const Camera& camera, const SceneParams& params,
                  const glm::vec3& lightDirWorld);

// What the studio's shading needs besides the ray, constant per image.
struct StudioShading {
    float invChecker;              // 1 / checkerM
    float aoScale;                 // corner darkening reach (one square), metres
    float fadeStart, invFade;      // far fade into the sky: start (metres) and 1 / length
    // Flat lighting per plane, per colour: ambient + kStudioKey * n.l, the
    // ambient kStudioAmbient, or with an HDR map its irradiance E(n) / pi
    // (environment.h's environmentAmbient at the plane's normal).
    glm::vec3 litFloor, litWallX, litWallZ;
    glm::vec3 sunDir;              // the sky's sun (unit, world)
};
StudioShading studioShading(const Studio& studio, const EnvironmentMap& environment = {});

// The spray drops' light per colour (spray.h's sprayOver), once per image for
// both backends, as the liquid's foam is lit (docs/pipeline.md#noise-and-foam):
// a drop's mean normal n faces the eye (`back`, Camera::back()), so the
// ambient is the map's E(n) / pi at that normal with an HDR map (environment.h's
// environmentAmbient; the studio's kOpaqueAmbient without one), plus the key
// light's share (1 - kOpaqueAmbient) max(n.l, 0) (spray.h's sprayLightZ).
glm::vec3 sprayLight(const glm::vec3& lightDirWorld, const glm::vec3& back, const EnvironmentMap& environment = {});

}  // namespace meniscus::shared
