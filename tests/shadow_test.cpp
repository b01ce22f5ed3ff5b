// Shadows (docs/geometry.md#shadows, src/cpu/shadow.cpp): a box over a plane
// darkens the plane where the analytic projection along the light puts its
// shadow, by the key light's share, and nowhere else; a slab of liquid tints
// its shadow by Beer-Lambert (water keeps more blue than red); off, and auto
// without geometry, run no stage; the same bits for any thread count; the
// light's camera covers the bounds and stays put while the particles move a little.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "core/shadow_camera.h"
#include "meniscus/geometry.h"
#include "meniscus/renderer.h"
#include "shared/shadow.h"
#include "shared/studio_shade.h"
#include "test_util.h"

namespace shadow_test_local {

using namespace meniscus;

namespace {

constexpr float kR = 0.02f;
const glm::vec3 kLight = glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f));

// A camera high above the origin looking straight down (+x right, -z up in the image).
Camera topCamera(int w = 128, int h = 128) {
    Camera c;
    c.eye = {0.0f, 4.0f, 0.0f};
    c.target = {0.0f, 0.0f, 0.0f};
    c.up = {0.0f, 0.0f, -1.0f};
    c.fovYDegrees = 30.0f;
    c.width = w;
    c.height = h;
    c.nearM = 0.01f;
    return c;
}

GeometryObject object(const char* name, TriangleMesh mesh) {
    GeometryObject o;
    o.name = name;
    o.mesh = std::move(mesh);
    o.material.baseColor = glm::vec3(0.7f);
    o.material.roughness = 1.0f;
    return o;
}

RenderSettings settings(std::shared_ptr<SceneGeometry> g) {
    RenderSettings s;
    s.radiusM = kR;
    s.camera = topCamera();
    s.anisotropy.enabled = false;
    s.shading.lightDirWorld = kLight;
    s.geometry = std::move(g);
    return s;
}

// Where pixel (x, y)'s ray meets the plane y = 0.
glm::vec3 onPlane(const Camera& c, int x, int y) {
    const glm::vec3 d = c.dirToWorld(c.pixelRay(float(x) + 0.5f, float(y) + 0.5f));
    return c.eye + d * (-c.eye.y / d.y);
}

// Whether the ray from p along d meets the box [lo, hi] (slabs).
bool hitsBox(glm::vec3 p, glm::vec3 d, glm::vec3 lo, glm::vec3 hi) {
    float t0 = 0.0f, t1 = 1e9f;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-9f) {
            if (p[a] < lo[a] || p[a] > hi[a]) return false;
            continue;
        }
        float u = (lo[a] - p[a]) / d[a], v = (hi[a] - p[a]) / d[a];
        if (u > v) std::swap(u, v);
        t0 = std::max(t0, u);
        t1 = std::min(t1, v);
    }
    return t0 <= t1;
}

bool ranStage(const std::vector<StageTime>& times, const char* name) {
    for (const StageTime& t : times)
        if (t.stage == name) return true;
    return false;
}

}  // namespace

TEST(Shadows, ABoxShadowsThePlaneWhereItsProjectionAlongTheLightFalls) {
    const glm::vec3 lo(-0.2f, 0.3f, -0.2f), hi(0.2f, 0.4f, 0.2f);
    auto g = std::make_shared<SceneGeometry>();
    g->objects.push_back(object("plane", makePlaneMesh({0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 2.0f)));
    g->objects.push_back(object("box", makeBoxMesh(lo, hi)));
    // A little liquid far from the shadow.
    const std::vector<glm::vec3> pts = test::jitteredBlock({4, 2, 4}, 2.0f * kR, 0.0f, {0.7f, kR, 0.5f});
    RenderSettings s = settings(g);
    std::vector<StageTime> times;
    auto on = renderFrame(pts, s, &times);
    ASSERT_TRUE(on.ok()) << on.error().describe();
    EXPECT_TRUE(ranStage(times, "shadow-map"));
    EXPECT_TRUE(ranStage(times, "shadows"));
    s.shadows = ShadowMode::Off;
    times.clear();
    auto off = renderFrame(pts, s, &times);
    ASSERT_TRUE(off.ok());
    EXPECT_FALSE(ranStage(times, "shadows"));

    const Camera& c = s.camera;
    const float nl = kLight.y;  // the plane's normal is +y
    const float kept = shared::kStudioAmbient / (shared::kStudioAmbient + shared::kStudioKey * nl);
    auto shadowed = [&](int x, int y) { return hitsBox(onPlane(c, x, y), kLight, lo, hi); };
    auto seesBox = [&](int x, int y) {
        const glm::vec3 p = onPlane(c, x, y);
        return hitsBox(p, glm::normalize(c.eye - p), lo, hi);
    };
    int inside = 0, outside = 0;
    for (int y = 2; y < c.height - 2; ++y)
        for (int x = 2; x < c.width - 2; ++x) {
            const glm::vec3 q = onPlane(c, x, y);
            if (q.x > 0.5f && q.z > 0.35f) continue;  // the liquid and its own shadow
            // Away from the edges of the box and of its shadow (two pixels).
            bool uniform = true;
            const bool sh = shadowed(x, y);
            for (int dy = -2; dy <= 2; ++dy)
                for (int dx = -2; dx <= 2; ++dx)
                    uniform = uniform && !seesBox(x + dx, y + dy) && shadowed(x + dx, y + dy) == sh;
            if (!uniform) continue;
            const glm::vec4 a = on->color.at(x, y), b = off->color.at(x, y);
            if (sh) {
                ++inside;
                for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k] * kept, 2e-3f) << x << "," << y;
            } else {
                ++outside;
                for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-6f) << x << "," << y;
            }
            if (::testing::Test::HasFailure()) return;
        }
    EXPECT_GT(inside, 200);
    EXPECT_GT(outside, 2000);
}

TEST(Shadows, ALiquidSlabTintsItsShadowByBeerLambert) {
    auto g = std::make_shared<SceneGeometry>();
    g->objects.push_back(object("plane", makePlaneMesh({0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 2.0f)));
    // A slab 0.4 m wide, 0.12 m thick, 0.3 m above the plane: its shadow
    // falls 0.3 m to the -x side.
    const std::vector<glm::vec3> pts = test::jitteredBlock({10, 3, 10}, 2.0f * kR, 0.0f, {-0.2f, 0.3f, -0.2f});
    RenderSettings s = settings(g);
    auto on = renderFrame(pts, s);
    s.shadows = ShadowMode::Off;
    auto off = renderFrame(pts, s);
    ASSERT_TRUE(on.ok() && off.ok());
    const Camera& c = s.camera;
    // The plane's point (-0.45, 0, 0): under the slab's shadow, not under the slab.
    const glm::vec2 px = c.projectView(c.toView({-0.48f, 0.0f, 0.0f}));
    const int x = int(px.x), y = int(px.y);
    ASSERT_FALSE(std::isfinite(on->depth.at(x, y)));
    const glm::vec4 a = on->color.at(x, y), b = off->color.at(x, y);
    const glm::vec3 ratio = glm::vec3(a) / glm::vec3(b);
    EXPECT_LT(ratio.r, 0.97f);
    EXPECT_GT(ratio.b, ratio.r + 0.02f) << ratio.r << " " << ratio.g << " " << ratio.b;
    EXPECT_GE(ratio.g, ratio.r);
    // Not a full shadow: some light goes through.
    const float kept = shared::kStudioAmbient / (shared::kStudioAmbient + shared::kStudioKey * kLight.y);
    EXPECT_GT(ratio.b, kept + 0.05f);
}

TEST(Shadows, OffOrWithoutGeometryRunsNoStageAndOnDrawsTheLiquidsShadow) {
    const std::vector<glm::vec3> pts = test::jitteredBlock({8, 3, 8}, 2.0f * kR, 0.0f, {-0.2f, 0.3f, -0.2f});
    RenderSettings s = settings(nullptr);
    std::vector<StageTime> times;
    auto plain = renderFrame(pts, s, &times);
    ASSERT_TRUE(plain.ok());
    EXPECT_FALSE(ranStage(times, "shadow-map"));
    EXPECT_FALSE(ranStage(times, "shadows"));
    s.shadows = ShadowMode::On;  // the liquid's shadow on the studio's floor
    times.clear();
    auto on = renderFrame(pts, s, &times);
    ASSERT_TRUE(on.ok());
    EXPECT_TRUE(ranStage(times, "shadows"));
    EXPECT_NE(std::memcmp(plain->color.pixels.data(), on->color.pixels.data(),
                          plain->color.pixels.size() * sizeof(glm::vec4)),
              0);
}

TEST(Shadows, TheSameBitsForAnyThreadCount) {
    auto g = std::make_shared<SceneGeometry>();
    g->objects.push_back(object("plane", makePlaneMesh({0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 2.0f)));
    g->objects.push_back(object("box", makeBoxMesh({-0.2f, 0.3f, -0.2f}, {0.2f, 0.4f, 0.2f})));
    const std::vector<glm::vec3> pts = test::jitteredBlock({8, 3, 8}, 2.0f * kR, 0.3f, {0.3f, 0.5f, -0.2f});
    const RenderSettings s = settings(g);
    Image<glm::vec4> first;
    for (const int threads : {1, 3, 8}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        auto a = renderFrame(pts, s);
        ASSERT_TRUE(a.ok());
        if (first.empty()) {
            first = a->color;
            continue;
        }
        EXPECT_EQ(std::memcmp(first.pixels.data(), a->color.pixels.data(), first.pixels.size() * sizeof(glm::vec4)), 0)
            << threads;
    }
}

// One Renderer keeps the geometry's depth seen from the light while the
// geometry object and the light's camera stay (CpuBackend::casterDepth): its
// frames are those of a fresh Renderer when the camera moves, when the
// geometry is replaced and when the first geometry comes back.
TEST(Shadows, TheKeptCasterDepthFollowsTheGeometryAndTheCamera) {
    auto withBox = std::make_shared<SceneGeometry>();
    withBox->objects.push_back(object("plane", makePlaneMesh({0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 2.0f)));
    withBox->objects.push_back(object("box", makeBoxMesh({-0.2f, 0.3f, -0.2f}, {0.2f, 0.4f, 0.2f})));
    auto moved = std::make_shared<SceneGeometry>(*withBox);
    moved->objects[1].mesh = makeBoxMesh({-0.5f, 0.3f, 0.1f}, {-0.1f, 0.5f, 0.4f});
    const std::vector<glm::vec3> pts = test::jitteredBlock({6, 3, 6}, 2.0f * kR, 0.3f, {0.5f, 0.5f, -0.3f});
    Renderer kept;
    auto same = [](const Image<glm::vec4>& a, const Image<glm::vec4>& b) {
        return a.width == b.width && a.height == b.height &&
               std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec4)) == 0;
    };
    RenderSettings s = settings(withBox);
    Image<glm::vec4> firstBox;
    for (int step = 0; step < 4; ++step) {
        s.geometry = step == 2 ? moved : withBox;
        s.camera.eye.x = step == 1 ? 0.3f : 0.0f;
        auto a = kept.render(ParticleView(pts), s);
        auto fresh = renderFrame(pts, s);
        ASSERT_TRUE(a.ok() && fresh.ok());
        EXPECT_TRUE(same(a->color, fresh->color)) << "step " << step;
        if (step == 0) firstBox = a->color;
        if (step == 2) {
            EXPECT_FALSE(same(a->color, firstBox));  // the moved box's shadow is elsewhere
        }
    }
}

TEST(Shadows, TheLightCameraCoversTheBoundsAndStaysPutForSmallMoves) {
    std::vector<glm::vec3> pts = test::jitteredBlock({8, 3, 8}, 2.0f * kR, 0.3f, {0.3f, 0.5f, -0.2f});
    FrameSettings f;
    f.radius = kR;
    f.particles = ParticleView(pts);
    f.studio.lightDirWorld = kLight;
    const ShadowLight a = shadowLight(f);
    EXPECT_EQ(a.camera.width, shared::kShadowMapPx);
    EXPECT_EQ(a.camera.height, shared::kShadowMapPx);
    EXPECT_TRUE(validateCamera(a.camera).ok());
    // Every particle inside the image and between the near and far planes.
    for (const glm::vec3& p : pts) {
        const glm::vec3 v = a.camera.toView(p);
        ASSERT_LT(v.z, 0.0f);
        EXPECT_GT(-v.z, a.camera.nearM);
        EXPECT_LT(-v.z, a.camera.farM);
        const glm::vec2 px = a.camera.projectView(v);
        EXPECT_GT(px.x, 0.0f);
        EXPECT_LT(px.x, float(shared::kShadowMapPx));
        EXPECT_GT(px.y, 0.0f);
        EXPECT_LT(px.y, float(shared::kShadowMapPx));
    }
    for (glm::vec3& p : pts) p += glm::vec3(1e-4f, -1e-4f, 0.0f);
    f.particles = ParticleView(pts);
    EXPECT_EQ(shadowLight(f).camera, a.camera);
}
}  // namespace shadow_test_local
