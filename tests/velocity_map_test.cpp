// The velocity whitening on the CPU (src/cpu/velocity_map.cpp,
// docs/pipeline.md#noise-and-foam; Instant Liquids §4): the map is the weighted
// mean whiteness of the particles near the surface, so a uniform flow gives its
// own whiteness everywhere, fast and slow parts keep theirs, deep particles do
// not count, and the shading lays white water by it.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "cpu/scene.h"
#include "cpu/shading.h"
#include "cpu/splat.h"
#include "cpu/velocity_map.h"
#include "meniscus/renderer.h"
#include "shared/velocity_map.h"
#include "test_util.h"

namespace velocity_map_test_local {

using namespace meniscus;

namespace {

constexpr float kR = 0.01f;

// Looking down -z from the origin: view space is world space.
Camera straightCamera(int w = 160, int h = 120) { return test::faceOnCamera({0.0f, 0.0f, -1.0f}, 1.0f, w, h); }

WhiteningParams onParams() {
    WhiteningParams p;
    p.enabled = true;
    return p;
}

// A slab of spacing 2r, `layers` deep below eye depth zTop, covering the view's centre.
std::vector<glm::vec3> slab(int nx, int ny, int layers, float zTop) {
    std::vector<glm::vec3> p;
    for (int k = 0; k < layers; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                p.push_back({(float(i) - 0.5f * float(nx)) * 2.0f * kR, (float(j) - 0.5f * float(ny)) * 2.0f * kR,
                             -(zTop + 2.0f * kR * float(k))});
    return p;
}

}  // namespace

TEST(VelocityMap, WhitenessRampsFromTheThreshold) {
    EXPECT_EQ(shared::whitenessOfSpeed(1.0f, 2.5f, 2.0f), 0.0f);
    EXPECT_EQ(shared::whitenessOfSpeed(2.5f, 2.5f, 2.0f), 0.0f);
    EXPECT_FLOAT_EQ(shared::whitenessOfSpeed(3.5f, 2.5f, 2.0f), 0.5f);
    EXPECT_EQ(shared::whitenessOfSpeed(9.0f, 2.5f, 2.0f), 1.0f);
}

TEST(VelocityMap, AUniformFlowGivesItsOwnWhitenessEverywhere) {
    const Camera cam = straightCamera();
    const auto p = slab(30, 24, 3, 0.5f);
    const Image<float> depth = cpu::splatDepth(cam, p, kR);
    const std::vector<float> white(p.size(), 0.37f);
    const Image<float> map = cpu::splatWhitening(cam, p, kR, depth, white, onParams());
    int fluid = 0, reached = 0;
    for (std::size_t i = 0; i < map.size(); ++i) {
        if (!(depth.pixels[i] < INFINITY)) {
            EXPECT_EQ(map.pixels[i], 0.0f);
            continue;
        }
        ++fluid;
        if (map.pixels[i] == 0.0f) continue;  // no sprite reached (the slab's outermost rim)
        ++reached;
        EXPECT_NEAR(map.pixels[i], 0.37f, 2e-4f) << i;
    }
    EXPECT_GT(reached, fluid * 9 / 10);
}

TEST(VelocityMap, FastAndSlowPartsKeepTheirOwn) {
    const Camera cam = straightCamera();
    const auto p = slab(30, 24, 2, 0.5f);
    const Image<float> depth = cpu::splatDepth(cam, p, kR);
    std::vector<float> white(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) white[i] = p[i].x > 0.0f ? 1.0f : 0.0f;  // the right half is fast
    const Image<float> map = cpu::splatWhitening(cam, p, kR, depth, white, onParams());
    // Well inside each half: the half's value; across the border: in between.
    const int cy = cam.height / 2, cx = cam.width / 2;
    const float sprite = 2.0f * kR * cam.focalPx() / 0.5f;  // px
    const int far = int(std::ceil(sprite)) + 2;
    EXPECT_NEAR(map.at(cx + far, cy), 1.0f, 1e-4f);
    EXPECT_NEAR(map.at(cx - far - 1, cy), 0.0f, 1e-4f);
    const float mid = map.at(cx, cy);
    EXPECT_GT(mid, 0.05f);
    EXPECT_LT(mid, 0.95f);
    for (int x = cx - far; x < cx + far; ++x) EXPECT_LE(map.at(x, cy), map.at(x + 1, cy) + 1e-6f) << x;
}

TEST(VelocityMap, DeepParticlesDoNotCount) {
    const Camera cam = straightCamera();
    auto p = slab(30, 24, 1, 0.5f);
    const auto deep = slab(30, 24, 1, 0.56f);  // 6 r behind the surface layer
    const std::size_t surface = p.size();
    p.insert(p.end(), deep.begin(), deep.end());
    // The smoothed surface: the surface layer's front (the deep layer shows
    // through no gap, as after smoothing).
    const Image<float> depth(cam.width, cam.height, 0.5f - kR);
    std::vector<float> white(p.size(), 0.0f);
    for (std::size_t i = surface; i < p.size(); ++i) white[i] = 1.0f;  // only the deep layer is fast
    const Image<float> map = cpu::splatWhitening(cam, p, kR, depth, white, onParams());
    for (float v : map.pixels) EXPECT_EQ(v, 0.0f);
}

TEST(VelocityMap, SameImageForAnyThreadCount) {
    const Camera cam = straightCamera(200, 150);
    const auto p = slab(24, 18, 3, 0.6f);
    const Image<float> depth = cpu::splatDepth(cam, p, kR);
    std::vector<float> white(p.size());
    for (std::size_t i = 0; i < white.size(); ++i) white[i] = float((i * 37) % 11) / 10.0f;
    Image<float> one, two;
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
        one = cpu::splatWhitening(cam, p, kR, depth, white, onParams());
    }
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
        two = cpu::splatWhitening(cam, p, kR, depth, white, onParams());
    }
    EXPECT_EQ(0, std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(float)));
}

TEST(VelocityMap, ShadingLaysWhiteWaterByTheMap) {
    const Camera cam = straightCamera(32, 24);
    const Image<float> depth(cam.width, cam.height, 0.5f);
    const Image<glm::vec3> normals(cam.width, cam.height, glm::vec3(0.0f, 0.0f, 1.0f));
    const Image<float> thickness(cam.width, cam.height, 0.05f);
    Image<float> map(cam.width, cam.height, 0.0f);
    for (int y = 0; y < cam.height; ++y)
        for (int x = 16; x < cam.width; ++x) map.at(x, y) = 1.0f;
    const cpu::SceneLayer none;
    const ShadingParams sp;
    WhiteningParams wp = onParams();
    wp.strength = 1.0f;
    const Image<glm::vec4> plain = cpu::shadeAndComposite(cam, none, depth, normals, thickness, sp);
    const Image<glm::vec4> white =
        cpu::shadeAndComposite(cam, none, depth, normals, thickness, sp, nullptr, nullptr, &map, &wp);
    const glm::vec3 L = glm::normalize(glm::vec3(glm::dot(sp.lightDirWorld, cam.right()),
                                                 glm::dot(sp.lightDirWorld, cam.trueUp()),
                                                 glm::dot(sp.lightDirWorld, cam.back())));
    const float lit = 0.35f + 0.65f * std::max(L.z, 0.0f);
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            if (x < 16) {
                EXPECT_EQ(white.at(x, y), plain.at(x, y));
            } else {
                EXPECT_NEAR(white.at(x, y).x, wp.color.x * lit, 1e-3f);
                EXPECT_NEAR(white.at(x, y).y, wp.color.y * lit, 1e-3f);
            }
        }
}

TEST(VelocityMap, ParametersOutOfRangeAreNamed) {
    WhiteningParams p = onParams();
    EXPECT_EQ(checkWhiteningParams(p), "");
    p.rampMps = 0.0f;
    EXPECT_NE(checkWhiteningParams(p).find("rampMps"), std::string::npos);
    p = onParams();
    p.strength = 1.5f;
    EXPECT_NE(checkWhiteningParams(p).find("strength"), std::string::npos);
}

TEST(VelocityMapRenderer, ReadsTheVelocitiesAndShowsTheMap) {
    RenderSettings s;
    s.camera = straightCamera(120, 90);
    s.radiusM = kR;
    s.scene.background = false;
    s.whitening = onParams();
    const auto p = slab(20, 16, 2, 0.5f);
    std::vector<glm::vec3> v(p.size(), glm::vec3(0.0f, 0.0f, 0.0f));
    for (std::size_t i = 0; i < v.size(); ++i)
        if (p[i].x > 0.0f) v[i] = {0.0f, -6.0f, 0.0f};  // the right half falls fast
    ParticleView view(p);
    view.velocity = StridedView<glm::vec3>(std::span<const glm::vec3>(v));
    Renderer r;
    auto a = r.render(view, s);
    ASSERT_TRUE(a.ok()) << a.error().describe();
    ASSERT_EQ(a->whitening.width, 120);
    const float right = a->whitening.at(90, 45), left = a->whitening.at(30, 45);
    EXPECT_NEAR(right, 1.0f, 1e-4f);
    EXPECT_EQ(left, 0.0f);
    // Without velocities nothing is whitened: the colour is the plain render's.
    RenderSettings off = s;
    off.whitening.enabled = false;
    auto plain = r.render(p, off);
    auto noVel = r.render(p, s);
    ASSERT_TRUE(plain.ok() && noVel.ok());
    EXPECT_EQ(0, std::memcmp(plain->color.pixels.data(), noVel->color.pixels.data(),
                             plain->color.pixels.size() * sizeof(glm::vec4)));
    // The whitening view, and its error without the whitening on.
    s.view = View::Whitening;
    EXPECT_TRUE(r.render(view, s).ok());
    off.view = View::Whitening;
    auto bad = r.render(view, off);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("whitening"), std::string::npos);
}
}  // namespace velocity_map_test_local
