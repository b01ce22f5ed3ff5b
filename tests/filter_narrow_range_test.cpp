// Narrow-range filter (docs/pipeline.md#narrow-range-filter, Truong & Yuksel,
// I3D 2018): smooths splatted particle bumps (2-D and separable), keeps planes,
// bodies, silhouettes and +inf apart, scale- and thread-count-invariant.
#include <cmath>
#include <cstdio>
#include <cstring>

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "cpu/filters.h"
#include "shared/narrow_range.h"
#include "smoothing_test_util.h"

namespace meniscus::filter_narrow_range_test_local {
namespace {

using test::blockScene;

Image<float> narrow(const Image<float>& d, const Camera& cam, float r, bool separable = false) {
    NarrowRangeParams p;
    p.iterations = 3;  // the filter on spheres (the default of 1 goes with the anisotropic kernels)
    p.separable = separable;
    return cpu::filterNarrowRange(d, cam, r, p);
}

class NarrowRange : public ::testing::TestWithParam<bool> {};  // param: separable

TEST_P(NarrowRange, SmoothsJitteredBlockFace) {
    const auto sc = blockScene();
    const auto before = test::blockFaceAngles(sc.depth, sc);
    const auto after = test::blockFaceAngles(narrow(sc.depth, sc.camera, sc.radius, GetParam()), sc);
    std::printf("face normal angle: before mean %.2f p95 %.2f deg, after mean %.2f p95 %.2f max %.2f deg (%d px)\n",
                before.meanDeg, before.p95Deg, after.meanDeg, after.p95Deg, after.maxDeg, after.count);
    ASSERT_GT(after.count, 20000);
    // Raw sphere caps tilt normals by ~47° on average. The filter (kernel
    // radius 3 r, 3 iterations) must bring the mean under 5° and 95% of the
    // central normals within 12° of the face normal, and be much tighter than
    // before (mean below a fifth).
    EXPECT_LT(after.meanDeg, 5.0);
    EXPECT_LT(after.p95Deg, 12.0);
    EXPECT_LT(after.meanDeg, before.meanDeg / 5.0);
}

TEST_P(NarrowRange, TiltedPlaneStaysPlane) {
    const Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, 320, 240);
    const Image<float> d = test::planeDepth(cam, 2.0f, glm::vec3(0.3f, -0.4f, 1.0f));
    // r = 0.02 m: projected radius ~3.3 px, kernel radius ~10 px.
    const Image<float> out = narrow(d, cam, 0.02f, GetParam());
    const double worst = test::maxRelativeChange(d, out);
    std::printf("plane: max relative change %.3g\n", worst);
    // Eye depth is not linear across the screen (1/z is), so a symmetric mean
    // moves a tilted plane by ~z_xx·σ²/2 = z·(tσ/f)² per pass (slope t = 0.5,
    // σ = 3.3 px, f = 330 px): ~3e-5 of its depth, ~9e-5 after 3 iterations.
    // Tolerance 2e-4 relative (0.02 r), over the whole image: taps beyond the
    // border are dropped with their mirror, so the border rows stay unbiased.
    EXPECT_LT(worst, 2e-4);
}

TEST_P(NarrowRange, InfStaysInfAndBorderIsHandled) {
    const test::BorderBallScene sc = test::borderBallScene();
    const float r = sc.r;
    const Camera& cam = sc.cam;
    const Image<float>& d = sc.depth;
    int borderFluid = 0;
    for (int y = 0; y < d.height; ++y) borderFluid += std::isfinite(d.at(0, y));
    ASSERT_GT(borderFluid, 10);
    const Image<float> out = narrow(d, cam, r, GetParam());
    float zMin = INFINITY, zMax = 0.0f;
    for (float z : d.pixels)
        if (std::isfinite(z)) zMin = std::min(zMin, z), zMax = std::max(zMax, z);
    for (std::size_t i = 0; i < d.size(); ++i) {
        ASSERT_EQ(std::isinf(d.pixels[i]), std::isinf(out.pixels[i])) << i;
        if (std::isfinite(d.pixels[i])) {
            // Every output is a weighted mean of input depths and z0 + mu r
            // values, so it stays in [min input, max input + mu r] (mu = 1;
            // tolerance 1e-6 relative for rounding).
            ASSERT_TRUE(std::isfinite(out.pixels[i])) << i;
            ASSERT_GE(out.pixels[i], zMin * (1.0f - 1e-6f)) << i;
            ASSERT_LE(out.pixels[i], (zMax + r) * (1.0f + 1e-6f)) << i;
        }
    }
}

TEST_P(NarrowRange, TwoBodiesDoNotBleed) {
    const auto t = test::twoBodyScene();
    const auto st = test::bleedStats(
        t, [&](const Image<float>& d) { return narrow(d, t.far.camera, t.far.radius, GetParam()); });
    // The faces are 18 r apart (> tau = 10 r). Near-body pixels see far taps as
    // "behind", exactly like +inf, so they come out as with the near body alone
    // (tolerance 0.01 r); far-body pixels drop near taps with their mirrors and
    // are never pulled toward the near body by more than 1.25 r compared with
    // the far body alone (a bleed would be ~9 r).
    test::expectNoBleed(st, "two bodies");
}

TEST_P(NarrowRange, SilhouetteNotPulledTowardBackground) {
    // The block's outer edge borders +inf. A plain mean would drag edge pixels
    // to the background; here "behind" taps count as z0 + mu r, so every pixel
    // of the block's front face region keeps within 4 r of the nominal face
    // (raw edge pixels are up to 1.5 r behind it, and each pass may push an
    // edge pixel back by less than mu r = 1 r: measured 2.4 r for 2-D,
    // 3.6 r separable, whose 6 passes push more).
    const auto sc = blockScene();
    const Image<float> out = narrow(sc.depth, sc.camera, sc.radius, GetParam());
    const float r = sc.radius;
    double worst = 0.0;
    int edge = 0;
    for (int y = 1; y + 1 < out.height; ++y)
        for (int x = 1; x + 1 < out.width; ++x) {
            const float z = sc.depth.at(x, y);
            // Front-face pixels (raw within 1.5 r of the face) next to the background.
            if (!std::isfinite(z) || std::fabs(z - sc.faceDepth) > 1.5f * r) continue;
            const bool nextToInf = std::isinf(sc.depth.at(x - 1, y)) || std::isinf(sc.depth.at(x + 1, y)) ||
                                   std::isinf(sc.depth.at(x, y - 1)) || std::isinf(sc.depth.at(x, y + 1));
            if (!nextToInf) continue;
            // Only the block's outer silhouette: far from the image centre.
            const glm::vec3 p = sc.camera.unproject(float(x) + 0.5f, float(y) + 0.5f, z);
            if (std::max(std::fabs(p.x), std::fabs(p.y)) < 0.35f) continue;
            ++edge;
            worst = std::max(worst, std::fabs(double(out.at(x, y)) - sc.faceDepth) / r);
        }
    std::printf("silhouette: %d edge px, worst |z - face| %.2f r\n", edge, worst);
    ASSERT_GT(edge, 500);
    EXPECT_LT(worst, 4.0);
}

TEST_P(NarrowRange, ScaleInvariant) {
    const auto a = blockScene(1.0f), b = blockScene(10.0f);
    const Image<float> oa = narrow(a.depth, a.camera, a.radius, GetParam());
    const Image<float> ob = narrow(b.depth, b.camera, b.radius, GetParam());
    double worst = 0.0;
    for (std::size_t i = 0; i < oa.size(); ++i) {
        ASSERT_EQ(std::isinf(oa.pixels[i]), std::isinf(ob.pixels[i])) << i;
        if (std::isfinite(oa.pixels[i]))
            worst = std::max(worst, std::fabs(double(ob.pixels[i]) / (10.0 * oa.pixels[i]) - 1.0));
    }
    std::printf("scale x10: max relative deviation %.3g\n", worst);
    EXPECT_LT(worst, 1e-4);  // "exactly 10×" up to float rounding of the inputs
}

TEST_P(NarrowRange, ThreadCountInvariant) {
    const auto sc = blockScene();
    auto run = [&](int threads) {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
        return narrow(sc.depth, sc.camera, sc.radius, GetParam());
    };
    const Image<float> one = run(1), three = run(3), all = run(int(tbb::info::default_concurrency()) + 1);
    // Bit-identical: each pixel is computed by one task in a fixed order.
    EXPECT_EQ(0, std::memcmp(one.pixels.data(), three.pixels.data(), one.size() * sizeof(float)));
    EXPECT_EQ(0, std::memcmp(one.pixels.data(), all.pixels.data(), one.size() * sizeof(float)));
}

TEST_P(NarrowRange, BallGetsCloserToAnalyticNormals) {
    // Grid-aligned ball, spacing 2 r (terraces, holes into deeper layers).
    const float r = 0.01f, R = 0.2f;
    const auto pts = test::ballOfParticles(glm::vec3(0.0f), R, 2.0f * r);
    const Camera cam = test::faceOnCamera(glm::vec3(0.0f), 1.4f, 400, 400);
    const Image<float> d = cpu::splatDepth(cam, pts, r);
    const glm::vec3 c = cam.toView(glm::vec3(0.0f));
    auto angles = [&](const Image<float>& img) {
        return test::normalAngles(
            img, cam, 2.0f * r, [&](const glm::vec3& p) { return glm::normalize(p - c).z > 0.5f; },
            [&](const glm::vec3& p) { return glm::normalize(p - c); });
    };
    const auto before = angles(d), after = angles(narrow(d, cam, r, GetParam()));
    std::printf("ball: mean angle to analytic normal before %.2f, after %.2f deg (%d px)\n", before.meanDeg,
                after.meanDeg, after.count);
    ASSERT_GT(after.count, 10000);
    // Tolerance: the mean error drops below a third (measured 2-D: 50° -> 9°).
    EXPECT_LT(after.meanDeg, before.meanDeg / 3.0);
}

TEST(NarrowRangeFilter, SeparableDiffersFrom2D) {
    // The option really switches the algorithm (both are exercised above).
    const auto sc = blockScene();
    const Image<float> a = narrow(sc.depth, sc.camera, sc.radius, false);
    const Image<float> b = narrow(sc.depth, sc.camera, sc.radius, true);
    EXPECT_NE(0, std::memcmp(a.pixels.data(), b.pixels.data(), a.size() * sizeof(float)));
}

INSTANTIATE_TEST_SUITE_P(Filter, NarrowRange, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& i) { return i.param ? "Separable" : "TwoD"; });

}  // namespace
}  // namespace meniscus::filter_narrow_range_test_local

// The tap order both backends walk (src/shared/narrow_range.h): every offset
// of the disc but the centre exactly once, with or as its mirror; sorted by
// (d2, dy, dx), so a smaller radius's list is a prefix. Weights: the Gaussian
// of sigma = R / 3 (1e-6 relative).
TEST(NarrowRangeTaps, HalfDiscIsCompleteAndCentreOutward) {
    for (int R : {1, 2, 5, 12}) {
        const std::vector<meniscus::shared::DiscTap> taps = meniscus::shared::narrowRangeHalfDisc(R);
        int disc = 0;
        for (int dy = -R; dy <= R; ++dy)
            for (int dx = -R; dx <= R; ++dx) disc += dx * dx + dy * dy <= R * R;
        ASSERT_EQ(int(taps.size()), (disc - 1) / 2) << R;
        for (std::size_t i = 0; i < taps.size(); ++i) {
            const meniscus::shared::DiscTap& t = taps[i];
            EXPECT_TRUE(t.dy > 0 || (t.dy == 0 && t.dx > 0)) << R;  // one of each mirror pair
            EXPECT_EQ(t.d2, t.dx * t.dx + t.dy * t.dy);
            if (i > 0) {
                const meniscus::shared::DiscTap& p = taps[i - 1];
                EXPECT_TRUE(p.d2 < t.d2 || (p.d2 == t.d2 && (p.dy < t.dy || (p.dy == t.dy && p.dx < t.dx)))) << R;
            }
        }
        const std::vector<meniscus::shared::DiscTap> smaller = meniscus::shared::narrowRangeHalfDisc(R - 1);
        for (std::size_t i = 0; i < smaller.size(); ++i) EXPECT_EQ(smaller[i].d2, taps[i].d2) << R;
        for (int d2 : {0, 1, R * R}) {
            const double sigma = R / 3.0, want = std::exp(-d2 / (2.0 * sigma * sigma));
            EXPECT_NEAR(meniscus::shared::narrowRangeWeight(d2, R), want, 1e-6 * want);
        }
    }
}
