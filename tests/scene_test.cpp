// Scene stage (SPEC §3.1): the studio's floor depth against the analytic
// ray-plane depth, walls behind the fluid from every side, sky pixels, fluid
// hidden behind a wall, a transparent background, the checker, thread and
// scale invariance.
#include <cmath>
#include <cstring>
#include <limits>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "cpu/scene.h"
#include "cpu/splat.h"
#include "test_util.h"

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
    const cpu::Studio studio = cpu::makeStudio(box, kRadius, cam, SceneParams{});
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
            const cpu::Studio studio = cpu::makeStudio(box, kRadius, cam, SceneParams{});
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
    const cpu::SceneLayer layer = cpu::castScene(cam, cpu::makeStudio(box, kRadius, cam, SceneParams{}));
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
            const glm::vec3 want = cpu::skyColor(cam.dirToWorld(cam.pixelRay(i + 0.5f, j + 0.5f)));
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
    const cpu::Studio studio = cpu::makeStudio(box, kRadius, cam, SceneParams{});
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
    const cpu::Studio studio = cpu::makeStudio(box, kRadius, cam, params);
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
    const cpu::Studio studio = cpu::makeStudio(box, kRadius, cam, SceneParams{});
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
    const cpu::Studio studio = cpu::makeStudio(box, kRadius, cam, SceneParams{});
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
    const cpu::Studio st = cpu::makeStudio(box, kRadius, cam, SceneParams{});
    const cpu::Studio st10 = cpu::makeStudio(box10, s * kRadius, cam10, SceneParams{});
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
