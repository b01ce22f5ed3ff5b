// Silhouette reduction (Cords & Staadt 2008, "Instant Liquids" §3;
// docs/pipeline.md#silhouette-reduction; src/cpu/silhouette.cpp): the
// silhouette map of a disc against a brute-force count, a plane filling the
// image stays untouched, the fade and the clip, nothing outside a convex
// contour changes at the default fade, the fade continued past the contour (and
// a notch filled), the same bits for any thread count, and through the Renderer
// the edges get fractional alpha (without it, a stair-step of 0 or 1).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "cpu/silhouette.h"
#include "meniscus/renderer.h"
#include "shared/kernel_radius.h"
#include "test_util.h"

namespace silhouette_test_local {

using namespace meniscus;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kW = 96, kH = 80;

Camera camera() { return test::faceOnCamera({0.0f, 0.0f, 0.0f}, 1.0f, kW, kH); }

// A disc of fluid of radius `rPx` pixels round (cx, cy) at eye depth z.
Image<float> disc(float cx, float cy, float rPx, float z) {
    Image<float> d(kW, kH, kInf);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            if (std::hypot(x + 0.5f - cx, y + 0.5f - cy) < rPx) d.at(x, y) = z;
    return d;
}

// The particle radius that makes the window's half-width R pixels at depth z.
float radiusFor(int R, float z, const SilhouetteParams& p) { return float(R) * z / (camera().focalPx() * p.radiusRadii) - 1e-6f; }

TEST(Silhouette, MapOfADiscIsItsWindowsFluidFraction) {
    SilhouetteParams p;
    p.enabled = true;
    const float z = 1.0f;
    const float radius = radiusFor(4, z, p);
    ASSERT_EQ(shared::projectedRadiusPx(p.radiusRadii * radius, camera().focalPx(), z, p.maxPx), 4);
    const Image<float> d = disc(48.0f, 40.0f, 20.0f, z);
    const Image<float> s = cpu::silhouetteMap(camera(), d, radius, p);
    int inner = 0, edge = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            if (!(d.at(x, y) < kInf)) {
                EXPECT_EQ(s.at(x, y), 0.0f);
                continue;
            }
            int count = 0, area = 0;
            for (int v = std::max(0, y - 4); v < std::min(kH, y + 5); ++v)
                for (int u = std::max(0, x - 4); u < std::min(kW, x + 5); ++u) {
                    ++area;
                    count += d.at(u, v) < kInf;
                }
            ASSERT_EQ(s.at(x, y), float(count) / float(area)) << x << "," << y;
            const float r = std::hypot(x + 0.5f - 48.0f, y + 0.5f - 40.0f);
            if (r < 20.0f - 4.0f * std::sqrt(2.0f) - 1.0f) {
                EXPECT_EQ(s.at(x, y), 1.0f);
                ++inner;
            }
            if (r > 19.0f) {  // about half the window, a little less (convex)
                EXPECT_NEAR(s.at(x, y), 0.45f, 0.2f);
                ++edge;
            }
        }
    EXPECT_GT(inner, 500);
    EXPECT_GT(edge, 50);
}

TEST(Silhouette, APlaneFillingTheImageIsUntouched) {
    SilhouetteParams p;
    p.enabled = true;
    const Image<float> d(kW, kH, 2.0f);
    Image<glm::vec4> color(kW, kH, glm::vec4(0.1f, 0.5f, 0.7f, 1.0f));
    const Image<glm::vec4> before = color, behind(kW, kH, glm::vec4(0.9f, 0.9f, 0.9f, 1.0f));
    const Image<float> s = cpu::reduceSilhouettes(camera(), d, behind, 0.02f, p, color);
    for (float v : s.pixels) ASSERT_EQ(v, 1.0f);  // windows clipped at the border: all fluid
    EXPECT_EQ(std::memcmp(color.pixels.data(), before.pixels.data(), color.size() * sizeof(glm::vec4)), 0);
}

TEST(Silhouette, FadesAndClipsOnlyTheFluidNearItsContour) {
    const float z = 1.0f;
    const Image<float> d = disc(40.0f, 40.0f, 16.0f, z);
    const glm::vec4 liquid(0.1f, 0.4f, 0.8f, 1.0f), scene(0.8f, 0.8f, 0.8f, 0.0f);
    for (float fadeFrom : {0.5f, 1.0f}) {
        SilhouetteParams p;
        p.enabled = true;
        p.fadeFrom = fadeFrom;
        const float radius = radiusFor(3, z, p);
        Image<glm::vec4> color(kW, kH, glm::vec4(0.3f, 0.2f, 0.1f, 1.0f));  // the scene's own pixels outside
        for (std::size_t i = 0; i < d.size(); ++i)
            if (d.pixels[i] < kInf) color.pixels[i] = liquid;
        const Image<glm::vec4> before = color, behind(kW, kH, scene);
        const Image<float> s = cpu::reduceSilhouettes(camera(), d, behind, radius, p, color);
        int faded = 0, gone = 0;
        for (std::size_t i = 0; i < d.size(); ++i) {
            if (!(d.pixels[i] < kInf)) {  // (a convex contour: its outside keeps S under 0.5)
                ASSERT_EQ(std::memcmp(&color.pixels[i], &before.pixels[i], sizeof(glm::vec4)), 0);  // not fluid: untouched
                continue;
            }
            const float S = s.pixels[i];
            if (S == 1.0f) {
                ASSERT_EQ(color.pixels[i], liquid);
            } else if (fadeFrom == 1.0f || S <= fadeFrom) {
                ASSERT_EQ(color.pixels[i], scene) << "S " << S;  // the paper's clip, or below the fade
                ++gone;
            } else {
                const float a = (S - fadeFrom) / (1.0f - fadeFrom);
                ASSERT_NEAR(color.pixels[i].r, scene.r + a * (liquid.r - scene.r), 1e-6f);
                ASSERT_NEAR(color.pixels[i].a, a, 1e-6f);  // alpha fades too: anti-aliased over no background
                ++faded;
            }
        }
        if (fadeFrom == 1.0f) {
            EXPECT_GT(gone, 100);
        } else {
            EXPECT_GT(faded, 50);
            EXPECT_GT(gone, 0);
        }
    }
}

// Past the contour: with a fade starting below 0.5 the background pixels next
// to a disc take the mean of their fluid neighbours' colours faded by their
// own window's S (sized at the nearest neighbour's depth), so the contour
// ends in a ramp of alpha instead of at the pixel grid; farther pixels stay
// the scene. With the default 0.5 a convex contour's outside stays as it was,
// and a one-pixel notch in the liquid (S above 0.5 there) is filled.
TEST(Silhouette, PastTheContourTheFadeContinues) {
    const float z = 1.0f;
    Image<float> d = disc(40.0f, 40.0f, 16.0f, z);
    d.at(40, 40) = kInf;  // a one-pixel hole in the middle
    const glm::vec4 scene(0.8f, 0.8f, 0.8f, 0.0f), outside(0.3f, 0.2f, 0.1f, 1.0f);
    for (float fadeFrom : {0.2f, 0.5f}) {
        SilhouetteParams p;
        p.enabled = true;
        p.fadeFrom = fadeFrom;
        const float radius = radiusFor(3, z, p);
        Image<glm::vec4> color(kW, kH, outside);
        for (std::size_t i = 0; i < d.size(); ++i)
            if (d.pixels[i] < kInf) color.pixels[i] = {0.1f + 0.001f * float(i % 97), 0.4f, 0.8f, 1.0f};
        const Image<glm::vec4> before = color, behind(kW, kH, scene);
        const Image<float> s = cpu::reduceSilhouettes(camera(), d, behind, radius, p, color);
        int ramp = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                if (d.at(x, y) < kInf) continue;
                EXPECT_EQ(s.at(x, y), 0.0f);  // the map stays the liquid's
                glm::vec4 sum(0.0f);
                int n = 0, count = 0, area = 0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int u = x + dx, v = y + dy;
                        if ((dx || dy) && u >= 0 && v >= 0 && u < kW && v < kH && d.at(u, v) < kInf)
                            sum += before.at(u, v), ++n;
                    }
                for (int v = std::max(0, y - 3); v < std::min(kH, y + 4); ++v)
                    for (int u = std::max(0, x - 3); u < std::min(kW, x + 4); ++u) ++area, count += d.at(u, v) < kInf;
                const float S = float(count) / float(area);
                const float a = n == 0 ? 0.0f : std::clamp((S - fadeFrom) / (1.0f - fadeFrom), 0.0f, 1.0f);
                if (a <= 0.0f) {
                    ASSERT_EQ(color.at(x, y), outside) << x << "," << y;
                    continue;
                }
                const glm::vec4 want = scene + a * (sum / float(n) - scene);
                for (int c = 0; c < 4; ++c) ASSERT_NEAR(color.at(x, y)[c], want[c], 1e-6f) << x << "," << y;
                if (x == 40 && y == 40) {
                    EXPECT_GT(a, 0.9f);  // the hole: nearly all liquid
                } else {
                    ++ramp;
                    EXPECT_LT(a, 0.5f);
                }
            }
        if (fadeFrom < 0.5f) {
            EXPECT_GT(ramp, 50);  // the ring just outside the disc
        } else {
            EXPECT_EQ(ramp, 0);
        }
    }
}

TEST(Silhouette, SameBitsForAnyThreadCount) {
    SilhouetteParams p;
    Image<float> d(kW, kH, kInf);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            if ((x * 7 + y * 13) % 5 != 0 && x > 10) d.at(x, y) = 0.5f + 0.02f * float(x);  // ragged, depth-varying
    auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        return cpu::silhouetteMap(camera(), d, 0.01f, p);
    };
    const Image<float> one = run(1), two = run(2);
    EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.size() * sizeof(float)), 0);
}

// The real frame without a background: off, alpha is 0 or 1; on, the edges
// get fractional alpha, and the liquid inside is the same.
TEST(Silhouette, RendererSoftensTheEdgesAlphaOnTheRealFrame) {
    auto set = readParticles(test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
    ASSERT_TRUE(set.ok());
    RenderSettings s;
    s.radiusM = estimateRadius(set->positions).radius;
    Camera base;
    base.width = 320;
    base.height = 180;
    s.camera = autoFrameCamera(set->positions, s.radiusM, base);
    s.scene.background = false;
    s.filter = FilterParams{GaussianParams{}};
    Renderer r;
    auto off = r.render(ParticleView::of(*set), s);
    ASSERT_TRUE(off.ok());
    EXPECT_TRUE(off->silhouette.empty());
    s.silhouette.enabled = true;
    auto on = r.render(ParticleView::of(*set), s);
    ASSERT_TRUE(on.ok()) << on.error().describe();
    ASSERT_FALSE(on->silhouette.empty());
    int fractionalOff = 0, fractionalOn = 0, same = 0, full = 0;
    for (std::size_t i = 0; i < on->color.size(); ++i) {
        fractionalOff += off->color.pixels[i].a > 0.0f && off->color.pixels[i].a < 1.0f;
        fractionalOn += on->color.pixels[i].a > 0.0f && on->color.pixels[i].a < 1.0f;
        if (on->silhouette.pixels[i] == 1.0f) ++full, same += on->color.pixels[i] == off->color.pixels[i];
    }
    EXPECT_EQ(fractionalOff, 0);
    EXPECT_GT(fractionalOn, 200);
    EXPECT_EQ(same, full);
    s.view = View::Silhouette;
    EXPECT_TRUE(r.render(ParticleView::of(*set), s).ok());
    s.silhouette.fadeFrom = 2.0f;
    EXPECT_FALSE(r.render(ParticleView::of(*set), s).ok());
}

}  // namespace
}  // namespace silhouette_test_local
