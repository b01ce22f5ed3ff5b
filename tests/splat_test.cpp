// Depth splat (docs/pipeline.md#depth-splat): exact ray-sphere depth, exact
// projected bounds, scene occlusion, near clipping, thread-count independence.
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "cpu/splat.h"

namespace splat_test_local {

using namespace meniscus;

namespace {

Camera testCamera(int w = 320, int h = 240) {
    Camera c;
    c.eye = {0.3f, 0.4f, 2.0f};
    c.target = {0.0f, 0.0f, 0.0f};
    c.width = w;
    c.height = h;
    c.fovYDegrees = 40.0f;
    return c;
}

// Nearest-hit eye depth in double precision; NaN for a miss; `margin` is the
// squared-distance slack (relative) below which a pixel counts as grazing.
double analyticDepth(const Camera& cam, int i, int j, const glm::dvec3& c, double r, bool* grazing) {
    const double f = 0.5 * cam.height / std::tan(0.5 * glm::radians(double(cam.fovYDegrees)));
    const glm::dvec3 d{(i + 0.5 - 0.5 * cam.width) / f, -(j + 0.5 - 0.5 * cam.height) / f, -1.0};
    const double a = glm::dot(d, d), b = glm::dot(d, c), cc = glm::dot(c, c) - r * r;
    const double disc = b * b - a * cc;
    *grazing = std::abs(disc) < 1e-4 * b * b;
    if (disc < 0) return std::nan("");
    return (b - std::sqrt(disc)) / a;  // ray parameter = eye depth since d.z = -1
}

}  // namespace

TEST(Splat, OneParticleMatchesTheAnalyticSphere) {
    const Camera cam = testCamera();
    const glm::vec3 world{0.05f, -0.02f, 0.1f};
    const float r = 0.15f;
    const Image<float> depth = cpu::splatDepth(cam, std::span(&world, 1), r);
    const glm::dvec3 cView = glm::dvec3(cam.toView(world));
    int covered = 0;
    for (int j = 0; j < cam.height; ++j)
        for (int i = 0; i < cam.width; ++i) {
            bool grazing = false;
            const double z = analyticDepth(cam, i, j, cView, r, &grazing);
            const float got = depth.at(i, j);
            if (grazing) continue;
            if (std::isnan(z)) {
                EXPECT_TRUE(std::isinf(got)) << i << "," << j;
            } else {
                ++covered;
                EXPECT_LE(std::abs(got - z) / z, 1e-5) << i << "," << j;
            }
        }
    EXPECT_GT(covered, 1000);
}

TEST(Splat, ProjectedBoundsContainEveryHitPixel) {
    const Camera cam = testCamera(200, 150);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.6f, 0.6f);
    for (int k = 0; k < 200; ++k) {
        const glm::vec3 c = cam.toView({u(rng), u(rng), u(rng)});
        const float r = 0.01f + 0.1f * std::abs(u(rng));
        const cpu::PixelRect rect = cpu::projectedSphereBounds(cam, c, r);
        for (int j = 0; j < cam.height; ++j)
            for (int i = 0; i < cam.width; ++i) {
                const float z = cpu::raySphereEyeDepth(cam.pixelRay(i + 0.5f, j + 0.5f), c, r);
                if (std::isfinite(z)) {
                    ASSERT_TRUE(i >= rect.x0 && i < rect.x1 && j >= rect.y0 && j < rect.y1)
                        << "sphere " << k << " pixel " << i << "," << j;
                }
            }
        // And the box is tight: no more than 2 pixels of slack on a side.
        if (!rect.empty() && rect.x0 > 0 && rect.x1 < cam.width) {
            const float f = cam.focalPx();
            const float projectedDiameter = 2.0f * r * f / -c.z;
            EXPECT_LE(rect.x1 - rect.x0, projectedDiameter * 1.6f + 6.0f);
        }
    }
}

TEST(Splat, NearestSphereWins) {
    const Camera cam = testCamera();
    const glm::vec3 dir = glm::normalize(cam.target - cam.eye);
    const std::vector<glm::vec3> pts{cam.eye + 2.0f * dir, cam.eye + 1.0f * dir};
    const Image<float> depth = cpu::splatDepth(cam, pts, 0.05f);
    EXPECT_NEAR(depth.at(160, 120), 0.95f, 1e-3f);
}

TEST(Splat, SceneDepthHidesFluidBehindIt) {
    const Camera cam = testCamera();
    const glm::vec3 p{0, 0, 0};
    Image<float> scene(cam.width, cam.height, std::numeric_limits<float>::infinity());
    for (int j = 0; j < cam.height; ++j)
        for (int i = 0; i < cam.width / 2; ++i) scene.at(i, j) = 0.5f;  // a wall in front, left half
    const Image<float> depth = cpu::splatDepth(cam, std::span(&p, 1), 0.2f, &scene);
    const Image<float> open = cpu::splatDepth(cam, std::span(&p, 1), 0.2f);
    int hidden = 0, shown = 0;
    for (int j = 0; j < cam.height; ++j)
        for (int i = 0; i < cam.width; ++i) {
            if (!std::isfinite(open.at(i, j))) continue;
            if (i < cam.width / 2) {
                EXPECT_TRUE(std::isinf(depth.at(i, j)));
                ++hidden;
            } else {
                EXPECT_EQ(depth.at(i, j), open.at(i, j));
                ++shown;
            }
        }
    EXPECT_GT(hidden, 100);
    EXPECT_GT(shown, 100);
}

TEST(Splat, NearPlaneClipsAndSpheresBehindTheEyeVanish) {
    Camera cam = testCamera();
    const glm::vec3 behind = cam.eye + 1.0f * glm::normalize(cam.eye - cam.target);
    const Image<float> none = cpu::splatDepth(cam, std::span(&behind, 1), 0.3f);
    for (float z : none.pixels) EXPECT_TRUE(std::isinf(z));
    cam.nearM = 3.0f;  // everything in front of the far side of the sphere at the target
    const glm::vec3 p{0, 0, 0};
    const Image<float> clipped = cpu::splatDepth(cam, std::span(&p, 1), 0.2f);
    for (float z : clipped.pixels) EXPECT_TRUE(std::isinf(z));
}

TEST(Splat, CameraInsideASphereSeesNothingOfIt) {
    const Camera cam = testCamera(64, 48);
    const glm::vec3 p = cam.eye;  // the eye sits at the centre: the nearest hit is behind the eye
    const Image<float> depth = cpu::splatDepth(cam, std::span(&p, 1), 0.5f);
    for (float z : depth.pixels) EXPECT_TRUE(std::isinf(z));
}

TEST(Splat, BitIdenticalForAnyThreadCount) {
    const Camera cam = testCamera(400, 300);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    std::vector<glm::vec3> pts(20000);
    for (auto& p : pts) p = {u(rng), u(rng), u(rng)};
    Image<float> one;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = cpu::splatDepth(cam, pts, 0.01f);
    }
    const Image<float> all = cpu::splatDepth(cam, pts, 0.01f);
    ASSERT_EQ(one.pixels.size(), all.pixels.size());
    EXPECT_EQ(0, std::memcmp(one.pixels.data(), all.pixels.data(), one.pixels.size() * sizeof(float)));
}
}  // namespace splat_test_local
