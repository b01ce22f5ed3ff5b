// Scene stage (docs/pipeline.md#scene): the studio's floor depth against the analytic
// ray-plane depth, walls behind the fluid from every side, sky pixels, fluid
// hidden behind a wall, a transparent background, the checker, thread and
// scale invariance, the light direction lighting the planes and placing the
// sky's sun (also through a reused Renderer, whose scene cache must notice it).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "cpu/scene.h"
#include "cpu/sky.h"
#include "cpu/splat.h"
#include "shared/studio_shade.h"
#include "meniscus/renderer.h"
#include "test_util.h"

namespace scene_test_local {

using namespace meniscus;

namespace {

constexpr float kRadius = 0.05f;

// A 1 m x 0.5 m x 0.8 m block of particles at spacing 2r around the origin.
std::vector<glm::vec3> blockParticles() {
    return test::jitteredBlock({10, 5, 8}, 2.0f * kRadius, 0.0f, {-0.45f, 0.0f, -0.35f});
}

Bounds boundsOf(const std::vector<glm::vec3>& pts) {
    Bounds b;
    for (const auto& p : pts) b.extend(p);
    return b;
}

// A camera at azimuth/elevation (degrees) around the box centre, at `dist`.
Camera orbitCamera(const Bounds& box, float azimuthDeg, float elevationDeg, float dist, int w = 320, int h = 240) {
    Camera c;
    const float az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
    c.target = box.center();
    c.eye = c.target + dist * glm::vec3(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
    c.width = w;
    c.height = h;
    c.fovYDegrees = 40.0f;
    c.nearM = 0.01f;
    return c;
}

// World direction of the view ray through the centre of pixel (i, j), double precision.
glm::dvec3 worldRay(const Camera& cam, int i, int j) {
    const double f = 0.5 * cam.height / std::tan(0.5 * glm::radians(double(cam.fovYDegrees)));
    const glm::dvec3 d{(i + 0.5 - 0.5 * cam.width) / f, -(j + 0.5 - 0.5 * cam.height) / f, -1.0};
    const glm::dvec3 back = glm::normalize(glm::dvec3(cam.eye - cam.target));
    const glm::dvec3 right = glm::normalize(glm::cross(glm::dvec3(cam.up), back));
    const glm::dvec3 up = glm::cross(back, right);
    return d.x * right + d.y * up + d.z * back;
}

}  // namespace

TEST(Scene, FloorDepthIsTheAnalyticRayPlaneEyeDepth) {
    const auto pts = blockParticles();
    const Bounds box = boundsOf(pts);
    const Camera cam = orbitCamera(box, 35.0f, 40.0f, 3.0f);
    const shared::Studio studio = shared::makeStudio(box, kRadius, cam, SceneParams{}, ShadingParams{}.lightDirWorld);
    EXPECT_LT(studio.floorY, box.min.y - kRadius);
    EXPECT_GT(studio.floorY, box.min.y - 2.0f * kRadius);
    const cpu::SceneLayer layer = cpu::castScene(cam, studio);
    int checked = 0;
    for (int j = 0; j < cam.height; ++j)
        for (int i = 0; i < cam.width; ++i) {
            const glm::dvec3 D = worldRay(cam, i, j);
            if (D.y >= 0.0) continue;
            const double t = (studio.floorY - cam.eye.y) / D.y;  // eye depth: D has view z = -1
            const glm::dvec3 q = glm::dvec3(cam.eye) + t * D;
            // Well inside the corner (away from the wall edges, where rounding may pick the wall).
            const double margin = 1e-3;
            if ((q.x - studio.wallX) * studio.wallXNormal < margin || (q.z - studio.wallZ) * studio.wallZNormal < margin)
                continue;
            ++checked;
            EXPECT_NEAR(layer.depth.at(i, j), t, 1e-5 * t) << i << "," << j;  // rel 1e-5
            EXPECT_EQ(layer.color.at(i, j).a, 1.0f);
        }
    EXPECT_GT(checked, 5000);
}

TEST(Scene, WallsStandBehindTheFluidFromEveryCamera) {
    const auto pts = blockParticles();
    const Bounds box = boundsOf(pts);
    for (float az = 0.0f; az < 360.0f; az += 45.0f)
        for (float el : {10.0f, 35.0f, 70.0f}) {
            SCOPED_TRACE(testing::Message() << "azimuth " << az << " elevation " << el);
            const Camera cam = orbitCamera(box, az, el, 2.5f);
            const shared::Studio studio =
                shared::makeStudio(box, kRadius, cam, SceneParams{}, ShadingParams{}.lightDirWorld);
            // The eye and every sphere are on the open side of both walls and above the floor.
            EXPECT_GT((cam.eye.x - studio.wallX) * studio.wallXNormal, 0.0f);
            EXPECT_GT((cam.eye.z - studio.wallZ) * studio.wallZNormal, 0.0f);
            EXPECT_GE((box.min.x - kRadius - studio.wallX) * studio.wallXNormal, 0.0f);
            EXPECT_GE((box.max.x + kRadius - studio.wallX) * studio.wallXNormal, 0.0f);
            EXPECT_GE((box.min.z - kRadius - studio.wallZ) * studio.wallZNormal, 0.0f);
            EXPECT_GE((box.max.z + kRadius - studio.wallZ) * studio.wallZNormal, 0.0f);
            // So the studio hides none of the fluid it was built around: exact equality.
            const cpu::SceneLayer layer = cpu::castScene(cam, studio);
            const Image<float> open = cpu::splatDepth(cam, pts, kRadius);
            const Image<float> withScene = cpu::splatDepth(cam, pts, kRadius, &layer.depth);
            int fluid = 0;
            for (std::size_t k = 0; k < open.size(); ++k) {
                fluid += std::isfinite(open.pixels[k]);
                ASSERT_EQ(open.pixels[k], withScene.pixels[k]) << "pixel " << k;
                // Wherever fluid is seen, the scene behind it is opaque (floor or wall, not sky).
                if (std::isfinite(open.pixels[k]) && el > 20.0f) {
                    EXPECT_TRUE(std::isfinite(layer.depth.pixels[k]));
                }
            }
            EXPECT_GT(fluid, 1000);
        }
}

TEST(Scene, SkyPixelsHaveInfiniteDepthAndTheSkyColour) {
    const auto pts = blockParticles();
    const Bounds box = boundsOf(pts);
    const Camera cam = orbitCamera(box, 35.0f, 5.0f, 3.0f);  // low: sky over the walls
    const shared::Studio studio = shared::makeStudio(box, kRadius, cam, SceneParams{}, ShadingParams{}.lightDirWorld);
    const cpu::SceneLayer layer = cpu::castScene(cam, studio);
    int sky = 0, opaque = 0;
    for (int j = 0; j < cam.height; ++j)
        for (int i = 0; i < cam.width; ++i) {
            const glm::vec4 c = layer.color.at(i, j);
            EXPECT_EQ(c.a, 1.0f);
            if (std::isfinite(layer.depth.at(i, j))) {
                ++opaque;
                continue;
            }
            ++sky;
            const glm::vec3 want =
                cpu::skyColor(cam.dirToWorld(cam.pixelRay(i + 0.5f, j + 0.5f)), studio.lightDirWorld);
            // Rays built in a different order than castScene's: 1e-4 absolute.
            EXPECT_NEAR(c.r, want.r, 1e-4f);
            EXPECT_NEAR(c.g, want.g, 1e-4f);
            EXPECT_NEAR(c.b, want.b, 1e-4f);
        }
    EXPECT_GT(sky, 1000);
    EXPECT_GT(opaque, 1000);
    // The top row looks up over the walls: sky; the bottom row looks at the floor.
    EXPECT_TRUE(std::isinf(layer.depth.at(cam.width / 2, 0)));
    EXPECT_TRUE(std::isfinite(layer.depth.at(cam.width / 2, cam.height - 1)));
}

TEST(Scene, ParticleBehindAWallIsHidden) {
    const auto pts = blockParticles();
    const Bounds box = boundsOf(pts);
    const Camera cam = orbitCamera(box, 35.0f, 25.0f, 3.0f);
    const shared::Studio studio = shared::makeStudio(box, kRadius, cam, SceneParams{}, ShadingParams{}.lightDirWorld);
    const cpu::SceneLayer layer = cpu::castScene(cam, studio);
    // A point on the x wall above the floor, and a sphere beyond it on the same sight line.
    const glm::vec3 onWall{studio.wallX, box.center().y, box.center().z};
    const glm::vec3 behind = cam.eye + 1.3f * (onWall - cam.eye);
    ASSERT_LT((behind.x - studio.wallX) * studio.wallXNormal, -2.0f * kRadius);
    const Image<float> open = cpu::splatDepth(cam, std::span(&behind, 1), kRadius);
    const Image<float> hidden = cpu::splatDepth(cam, std::span(&behind, 1), kRadius, &layer.depth);
    int seen = 0;
    for (std::size_t k = 0; k < open.size(); ++k) {
        seen += std::isfinite(open.pixels[k]);
        EXPECT_TRUE(std::isinf(hidden.pixels[k])) << "pixel " << k;
    }
    EXPECT_GT(seen, 20);  // it would be visible without the wall
}

TEST(Scene, NoBackgroundIsTransparent) {
    const auto pts = blockParticles();
    const Bounds box = boundsOf(pts);
    const Camera cam = orbitCamera(box, 35.0f, 25.0f, 3.0f);
    SceneParams params;
    params.background = false;
    const shared::Studio studio = shared::makeStudio(box, kRadius, cam, params, ShadingParams{}.lightDirWorld);
    EXPECT_FALSE(studio.enabled);
    const cpu::SceneLayer layer = cpu::castScene(cam, studio);
    for (const auto& c : layer.color.pixels) ASSERT_EQ(c, glm::vec4(0.0f));
    for (float z : layer.depth.pixels) ASSERT_TRUE(std::isinf(z) && z > 0.0f);
}

TEST(Scene, CheckerAlternates) {
    const auto pts = blockParticles();
    const Bounds box = boundsOf(pts);
    Camera cam;  // straight down onto the floor
    cam.target = {box.center().x, box.min.y - 0.1f, box.center().z};
    cam.eye = cam.target + glm::vec3(0.0f, 3.0f, 0.0f);
    cam.up = {0.0f, 0.0f, -1.0f};
    cam.width = 400;
    cam.height = 400;
    cam.fovYDegrees = 40.0f;
    const shared::Studio studio = shared::makeStudio(box, kRadius, cam, SceneParams{}, ShadingParams{}.lightDirWorld);
    // 1/8 of the extent, a nice round number: 1.0 m + margins -> 0.1 m here.
    EXPECT_FLOAT_EQ(studio.checkerM, 0.1f);
    const cpu::SceneLayer layer = cpu::castScene(cam, studio);
    auto squareColour = [&](int a, int b) {  // centre of square (a, b) counted from the corner
        const glm::vec3 p{studio.wallX + (a + 0.5f) * studio.checkerM * studio.wallXNormal, studio.floorY,
                          studio.wallZ + (b + 0.5f) * studio.checkerM * studio.wallZNormal};
        const glm::vec2 px = cam.projectView(cam.toView(p));
        EXPECT_TRUE(std::isfinite(layer.depth.at(int(px.x), int(px.y))));
        return glm::vec3(layer.color.at(int(px.x), int(px.y)));
    };
    // Past the first square the corner shading is gone: same parity = same colour
    // (1e-5), neighbours differ by a clearly visible step (> 0.1).
    for (int a = 2; a < 7; ++a)
        for (int b = 2; b < 7; ++b) {
            const glm::vec3 c = squareColour(a, b);
            EXPECT_NEAR(glm::length(c - squareColour(a + 2, b)), 0.0f, 1e-5f);
            EXPECT_NEAR(glm::length(c - squareColour(a + 1, b + 1)), 0.0f, 1e-5f);
            EXPECT_GT(std::abs(c.g - squareColour(a + 1, b).g), 0.1f);
            EXPECT_GT(std::abs(c.g - squareColour(a, b + 1).g), 0.1f);
        }
}

TEST(Scene, BitIdenticalForAnyThreadCount) {
    const auto pts = blockParticles();
    const Bounds box = boundsOf(pts);
    const Camera cam = orbitCamera(box, 35.0f, 25.0f, 3.0f, 640, 360);
    const shared::Studio studio = shared::makeStudio(box, kRadius, cam, SceneParams{}, ShadingParams{}.lightDirWorld);
    cpu::SceneLayer one;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = cpu::castScene(cam, studio);
    }
    const cpu::SceneLayer all = cpu::castScene(cam, studio);
    EXPECT_EQ(0, std::memcmp(one.depth.pixels.data(), all.depth.pixels.data(), one.depth.size() * sizeof(float)));
    EXPECT_EQ(0, std::memcmp(one.color.pixels.data(), all.color.pixels.data(), one.color.size() * sizeof(glm::vec4)));
}

TEST(Scene, ScaleInvariant) {
    auto pts = blockParticles();
    const Bounds box = boundsOf(pts);
    const Camera cam = orbitCamera(box, 35.0f, 25.0f, 3.0f);
    const float s = 10.0f;
    Bounds box10 = box;
    box10.min *= s;
    box10.max *= s;
    Camera cam10 = cam;
    cam10.eye *= s;
    cam10.target *= s;
    cam10.nearM *= s;
    cam10.farM *= s;
    const shared::Studio st = shared::makeStudio(box, kRadius, cam, SceneParams{}, ShadingParams{}.lightDirWorld);
    const shared::Studio st10 =
        shared::makeStudio(box10, s * kRadius, cam10, SceneParams{}, ShadingParams{}.lightDirWorld);
    EXPECT_NEAR(st10.checkerM, s * st.checkerM, 1e-5f * s);
    const cpu::SceneLayer a = cpu::castScene(cam, st), b = cpu::castScene(cam10, st10);
    // Float rounding may flip a pixel at a checker or plane edge: all but 0.5% of
    // the pixels match (colour 1e-4 absolute, depth 1e-5 relative).
    int mismatches = 0;
    for (std::size_t k = 0; k < a.depth.size(); ++k) {
        const float za = a.depth.pixels[k], zb = b.depth.pixels[k];
        const bool depthOk = std::isinf(za) ? std::isinf(zb) : std::abs(zb - s * za) <= 1e-5f * s * za;
        const bool colourOk = glm::length(a.color.pixels[k] - b.color.pixels[k]) <= 1e-4f;
        mismatches += !(depthOk && colourOk);
    }
    EXPECT_LE(mismatches, int(a.depth.size() / 200));
}

// The light direction lights the studio (docs/pipeline.md#scene: flat key + ambient per
// plane) and places the sky's sun. A light straight up against one along the
// x wall's normal: the floor goes from ambient + key (1.0) to ambient (0.45),
// the x wall the other way, the z wall stays at ambient; each square's colour
// scales by exactly that ratio (same checker, corner and fade factors), 1e-5.
TEST(Scene, LightDirectionLightsTheStudioPlanes) {
    const auto pts = blockParticles();
    const Bounds box = boundsOf(pts);
    const Camera cam = orbitCamera(box, 35.0f, 25.0f, 3.0f);
    const shared::Studio up = shared::makeStudio(box, kRadius, cam, SceneParams{}, glm::vec3(0.0f, 2.0f, 0.0f));
    const shared::Studio side =
        shared::makeStudio(box, kRadius, cam, SceneParams{}, glm::vec3(up.wallXNormal, 0.0f, 0.0f));
    ASSERT_EQ(up.lightDirWorld, glm::vec3(0.0f, 1.0f, 0.0f));  // normalised
    const cpu::SceneLayer a = cpu::castScene(cam, up), b = cpu::castScene(cam, side);
    // Points in the middle of each plane, away from the corner edges.
    const glm::vec3 c = box.center();
    const glm::vec3 onFloor{c.x, up.floorY, c.z};
    const glm::vec3 onWallX{up.wallX, 0.5f * (up.floorY + up.wallTopY), c.z};
    const glm::vec3 onWallZ{c.x, 0.5f * (up.floorY + up.wallTopY), up.wallZ};
    const std::pair<glm::vec3, float> expected[] = {{onFloor, 0.45f / 1.0f}, {onWallX, 1.0f / 0.45f}, {onWallZ, 1.0f}};
    for (const auto& [p, ratio] : expected) {
        const glm::vec2 px = cam.projectView(cam.toView(p));
        const int i = int(px.x), j = int(px.y);
        ASSERT_TRUE(i >= 0 && i < cam.width && j >= 0 && j < cam.height);
        const float z = -cam.toView(p).z;
        ASSERT_NEAR(a.depth.at(i, j), z, 0.02f * z);  // the plane itself is seen there
        EXPECT_EQ(a.depth.at(i, j), b.depth.at(i, j));          // the light moves no geometry
        for (int ch = 0; ch < 3; ++ch)
            EXPECT_NEAR(b.color.at(i, j)[ch], ratio * a.color.at(i, j)[ch], 1e-5f) << i << "," << j;
    }
}

// The sun glow (0.6 at its centre) sits along the light: a camera looking
// along one light sees it in the middle of the image, and not when the light
// points elsewhere.
TEST(Scene, SkySunFollowsTheLight) {
    const auto pts = blockParticles();
    const Bounds box = boundsOf(pts);
    const glm::vec3 lights[] = {glm::normalize(glm::vec3(-0.4f, 1.0f, 0.55f)),
                                glm::normalize(glm::vec3(0.8f, 0.5f, 0.3f))};
    auto centre = [&](const glm::vec3& lookAlong, const glm::vec3& light) {
        Camera cam;
        cam.eye = box.center() + glm::vec3(0.0f, 20.0f, 0.0f);  // high above the walls: only sky in view
        cam.target = cam.eye + lookAlong;
        cam.width = 64;
        cam.height = 64;
        cam.up = std::abs(lookAlong.y) > 0.9f ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
        const cpu::SceneLayer l = cpu::castScene(cam, shared::makeStudio(box, kRadius, cam, SceneParams{}, light));
        EXPECT_TRUE(std::isinf(l.depth.at(32, 32)));
        return glm::vec3(l.color.at(32, 32));
    };
    for (int k = 0; k < 2; ++k) {
        const glm::vec3 own = centre(lights[k], lights[k]), other = centre(lights[k], lights[1 - k]);
        EXPECT_GT(own.r - other.r, 0.5f) << "light " << k;  // nearly the full glow of 0.6
        const glm::vec3 want = cpu::skyColor(lights[k], lights[k]);
        EXPECT_NEAR(own.r, want.r, 0.01f);  // the pixel centre is a fraction of a degree off the sun
    }
}

// A Renderer keeps its scene cast while camera and studio stay the same; a
// new light must recast it: the second frame equals a fresh renderer's, bit
// for bit, and differs from the first.
TEST(Scene, ReusedRendererRecastsTheSceneWhenTheLightChanges) {
    const auto pts = blockParticles();
    RenderSettings s;
    s.camera = orbitCamera(boundsOf(pts), 35.0f, 25.0f, 3.0f, 160, 120);
    s.radiusM = kRadius;
    s.colorOnly = true;
    Renderer reused;
    auto first = reused.render(pts, s);
    ASSERT_TRUE(first.ok()) << first.error().describe();
    s.shading.lightDirWorld = glm::normalize(glm::vec3(0.9f, 0.3f, -0.4f));
    auto second = reused.render(pts, s);
    auto fresh = Renderer().render(pts, s);
    ASSERT_TRUE(second.ok() && fresh.ok());
    EXPECT_EQ(0, std::memcmp(second->color.pixels.data(), fresh->color.pixels.data(),
                             fresh->color.size() * sizeof(glm::vec4)));
    double maxDiff = 0.0;
    for (std::size_t k = 0; k < first->color.size(); ++k)
        maxDiff = std::max(maxDiff, double(glm::length(first->color.pixels[k] - second->color.pixels[k])));
    EXPECT_GT(maxDiff, 0.1);
}

// The floor-only studio (SceneParams::walls = false, for moving cameras): the
// same floor from every side (its checker and fade centred under the box, so
// it does not slide as the camera turns), no walls (sky where they stood),
// every plane hit on the floor at its analytic depth, squares that alternate
// about the box's centre with no corner darkening (two colours only).
TEST(Scene, FloorOnlyStudioIsTheSameFloorFromEverySide) {
    const auto pts = blockParticles();
    const Bounds box = boundsOf(pts);
    SceneParams floorOnly;
    floorOnly.walls = false;
    const shared::Studio ref =
        shared::makeStudio(box, kRadius, orbitCamera(box, 35.0f, 25.0f, 3.0f), floorOnly, ShadingParams{}.lightDirWorld);
    EXPECT_FALSE(ref.walls);
    EXPECT_EQ(ref.wallX, box.center().x);
    EXPECT_EQ(ref.wallZ, box.center().z);
    for (float az = 0.0f; az < 360.0f; az += 45.0f) {
        SCOPED_TRACE(testing::Message() << "azimuth " << az);
        const Camera cam = orbitCamera(box, az, 10.0f, 3.0f, 160, 120);
        const shared::Studio studio = shared::makeStudio(box, kRadius, cam, floorOnly, ShadingParams{}.lightDirWorld);
        EXPECT_EQ(studio, ref);  // nothing depends on the camera
        // Where the walls' studio shows a wall, the floor-only one shows sky or
        // the floor beyond: every hit is the floor's plane.
        const shared::Studio withWalls = shared::makeStudio(box, kRadius, cam, SceneParams{}, ShadingParams{}.lightDirWorld);
        const cpu::SceneLayer layer = cpu::castScene(cam, studio), walled = cpu::castScene(cam, withWalls);
        int sky = 0, wallGone = 0;
        for (int j = 0; j < cam.height; ++j)
            for (int i = 0; i < cam.width; ++i) {
                const float z = layer.depth.at(i, j);
                const glm::dvec3 D = worldRay(cam, i, j);
                wallGone += walled.depth.at(i, j) < 0.999f * z;  // a wall stood in front of this (or the sky)
                if (!std::isfinite(z)) {
                    ++sky;
                    continue;
                }
                const double t = (studio.floorY - cam.eye.y) / D.y;
                ASSERT_NEAR(z, t, 1e-5 * t) << i << "," << j;
            }
        EXPECT_GT(sky, 1000);
        EXPECT_GT(wallGone, 1000);  // the walls would have stood there
    }
    // Straight down on the centre: the four squares around it alternate, and
    // every floor pixel inside the fade is one of the two lit checker colours.
    Camera down;
    down.target = {box.center().x, ref.floorY, box.center().z};
    down.eye = down.target + glm::vec3(0.0f, 3.0f, 0.0f);
    down.up = {0.0f, 0.0f, -1.0f};
    down.width = 200;
    down.height = 200;
    const cpu::SceneLayer top = cpu::castScene(down, ref);
    const float lit = shared::studioShading(ref).litFloor.x;  // grey without a map
    const glm::vec3 light = lit * shared::kStudioFloorLight, dark = lit * shared::kStudioFloorDark;
    auto colourAt = [&](float dx, float dz) {
        const glm::vec2 px = down.projectView(down.toView(down.target + glm::vec3(dx, 0.0f, dz)));
        return glm::vec3(top.color.at(int(px.x), int(px.y)));
    };
    const float h = 0.5f * ref.checkerM;
    EXPECT_EQ(colourAt(h, h), light);  // squares counted from the centre: (0, 0) is even
    EXPECT_EQ(colourAt(-h, -h), light);
    EXPECT_EQ(colourAt(-h, h), dark);
    EXPECT_EQ(colourAt(h, -h), dark);
    for (const glm::vec4& c : top.color.pixels) ASSERT_TRUE(glm::vec3(c) == light || glm::vec3(c) == dark);
}

// A moving camera that keeps the walls (--background studio) fixes their
// sides with SceneParams::wallsSeenFrom: cameras on opposite sides then get
// the same studio.
TEST(Scene, WallsSeenFromAFixedEyeStayPut) {
    const auto pts = blockParticles();
    const Bounds box = boundsOf(pts);
    const Camera a = orbitCamera(box, 35.0f, 25.0f, 3.0f), b = orbitCamera(box, 215.0f, 25.0f, 3.0f);
    const glm::vec3 light = ShadingParams{}.lightDirWorld;
    EXPECT_NE(shared::makeStudio(box, kRadius, a, SceneParams{}, light),
              shared::makeStudio(box, kRadius, b, SceneParams{}, light));  // per frame: they jump
    SceneParams fixed;
    fixed.wallsSeenFrom = a.eye;
    EXPECT_EQ(shared::makeStudio(box, kRadius, b, fixed, light), shared::makeStudio(box, kRadius, a, SceneParams{}, light));
}
}  // namespace scene_test_local
