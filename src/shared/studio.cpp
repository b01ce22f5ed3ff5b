// The studio of docs/pipeline.md#scene: a checker floor and two back walls forming the
// inside corner of a box around the particles, or the floor alone for a
// moving camera. Every length comes from the
// particles' box and radius (checker size, wall margins, corner shading,
// distance fade), so the studio scales with the scene. Built here once for
// both backends (cpu::castScene, gl::SceneCaster).
#include "shared/studio.h"

#include <algorithm>
#include <cmath>

#include "shared/shading.h"
#include "shared/sky.h"
#include "shared/spray.h"
#include "shared/studio_shade.h"

namespace meniscus::shared {

namespace {

// Gap between the lowest sphere and the floor, and between the outermost
// spheres and the walls, in radii: the fluid sits just in front of the studio
// but never intersects it.
constexpr float kFloorGapRadii = 0.25f;
constexpr float kWallGapRadii = 1.0f;

// Checker square ≈ 1/8 of the box's largest horizontal extent, rounded to a
// "nice" 1, 2 or 5 times a power of ten (a readable scale in the picture).
float niceChecker(float extentM) {
    const float raw = extentM / 8.0f;
    if (!(raw > 0.0f) || !std::isfinite(raw)) return 1.0f;  // degenerate box: any size will do
    const float decade = std::pow(10.0f, std::floor(std::log10(raw)));
    const float m = raw / decade;  // in [1, 10)
    const float nice = m < 1.5f ? 1.0f : m < 3.5f ? 2.0f : m < 7.5f ? 5.0f : 10.0f;
    return nice * decade;
}

}  // namespace

Studio makeStudio(const Bounds& particleBox, float radius, const Camera& camera, const SceneParams& params,
                  const glm::vec3& lightDirWorld) {
    Studio s;
    s.enabled = params.background;
    s.lightDirWorld = sunDirection(lightDirWorld);
    Bounds box = params.studioBounds.empty() ? particleBox : params.studioBounds;
    if (box.empty()) box.extend(camera.target);  // no particles: a corner around the target
    const float r = (radius > 0.0f && std::isfinite(radius)) ? radius
                                                             : 0.01f * glm::length(camera.eye - camera.target);
    s.floorY = box.min.y - r - kFloorGapRadii * r;
    // Each wall on the far side of the box from the eye, so it stands behind the fluid.
    const glm::vec3 c = box.center();
    const float wallGap = r + kWallGapRadii * r;
    const glm::vec3 eye = params.wallsSeenFrom.value_or(camera.eye);
    s.walls = params.walls;
    s.wallXNormal = !s.walls || eye.x >= c.x ? 1.0f : -1.0f;
    s.wallX = !s.walls ? c.x : s.wallXNormal > 0.0f ? box.min.x - wallGap : box.max.x + wallGap;
    s.wallZNormal = !s.walls || eye.z >= c.z ? 1.0f : -1.0f;
    s.wallZ = !s.walls ? c.z : s.wallZNormal > 0.0f ? box.min.z - wallGap : box.max.z + wallGap;
    const glm::vec3 e = box.extent();
    const float horizontal = std::max(e.x, e.z) + 2.0f * wallGap;
    s.checkerM = niceChecker(horizontal);
    // Walls 1.5 times the fluid's height or half the floor's size, whichever is
    // taller, ending on a whole square: a backdrop, with sky above.
    const float height = std::max(1.5f * (box.max.y + r - s.floorY), 0.5f * horizontal);
    s.wallTopY = s.floorY + std::ceil(height / s.checkerM) * s.checkerM;
    return s;
}

StudioShading studioShading(const Studio& studio, const EnvironmentMap& environment) {
    StudioShading sh;
    sh.invChecker = 1.0f / studio.checkerM;
    sh.aoScale = studio.checkerM;
    sh.fadeStart = kStudioFadeStartSquares * studio.checkerM;
    sh.invFade = 1.0f / (kStudioFadeLengthSquares * studio.checkerM);
    // Flat: each plane has one normal (+y; +-x and +-z toward the camera side).
    const glm::vec3 l = studio.lightDirWorld;
    // The ambient: the studio's constant, or the map's irradiance at the
    // plane's normal (docs/pipeline.md#environment-map).
    auto lit = [&](glm::vec3 n, float nl) {
        const float key = kStudioKey * std::max(0.0f, nl);
        return environment.enabled() ? environmentAmbient(n.x, n.y, n.z, environment) + glm::vec3(key)
                                     : glm::vec3(kStudioAmbient + key);
    };
    sh.litFloor = lit({0.0f, 1.0f, 0.0f}, l.y);
    sh.litWallX = lit({studio.wallXNormal, 0.0f, 0.0f}, studio.wallXNormal * l.x);
    sh.litWallZ = lit({0.0f, 0.0f, studio.wallZNormal}, studio.wallZNormal * l.z);
    sh.sunDir = studio.lightDirWorld;
    return sh;
}

glm::vec3 sprayLight(const glm::vec3& lightDirWorld, const glm::vec3& back, const EnvironmentMap& environment) {
    const float key = (1.0f - kOpaqueAmbient) * std::max(sprayLightZ(lightDirWorld, back), 0.0f);
    return environment.enabled() ? environmentAmbient(back.x, back.y, back.z, environment) + glm::vec3(key)
                                 : glm::vec3(kOpaqueAmbient + key);
}

}  // namespace meniscus::shared
