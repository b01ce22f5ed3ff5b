// CPU scene stage (SPEC §3.1): the default studio (checker floor, two back
// walls) ray-cast per pixel into colour and eye depth, and the procedural sky
// that serves as background and environment map.
#pragma once

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/types.h"
#include "cpu/sky.h"

namespace meniscus::cpu {

// The studio's geometry, built once from a box (the particles' bounds) and the
// camera. All lengths in metres, world space.
struct Studio {
    bool enabled = true;       // false: sky only, transparent background
    float floorY = 0.0f;       // floor plane y = floorY, facing +y
    float wallX = 0.0f;        // back wall plane x = wallX, facing the camera side
    float wallXNormal = 1.0f;  // +1 or -1: the side of the wall the camera is on
    float wallZ = 0.0f;        // back wall plane z = wallZ
    float wallZNormal = 1.0f;
    float wallTopY = 1.0f;     // the walls end at this height; the sky shows above them
    float checkerM = 0.1f;     // checker square size

    bool operator==(const Studio&) const = default;
};

// The studio around `box` (params.studioBounds instead when not empty): floor
// just under the lowest sphere, walls ~1 radius outside the spheres on the far
// side of the box from the eye, checker ~1/8 of the horizontal extent rounded
// to 1, 2 or 5 x 10^k metres. params.background == false: enabled = false.
Studio makeStudio(const Bounds& box, float radius, const Camera& camera, const SceneParams& params);

struct SceneLayer {
    Image<glm::vec4> color;  // linear RGB; alpha 1 where opaque, 0 for a transparent background
    Image<float> depth;      // eye depth of the studio geometry, +inf where only sky is seen
};

// Ray-casts the studio for every pixel centre: colour (checker, flat lambert +
// ambient, corner darkening, far fade into the sky) and eye depth of the
// nearest plane; skyColor and +inf depth where none is hit; all (0,0,0,0) and
// +inf when the studio is disabled. Bit-identical for any thread count.
SceneLayer castScene(const Camera& camera, const Studio& studio);

}  // namespace meniscus::cpu
