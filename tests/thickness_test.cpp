// Thickness stage (docs/pipeline.md#thickness): exact chords of one sphere, a
// block at rest spacing reading its true depth, clipping by the scene and the
// near plane, the blur keeping the mean, the one-pass depth+thickness matching
// the two calls, thread and scale invariance, at full resolution and on the
// coarser grids (resolutionDivisor 2 and 4). Speed is measured by build/bench,
// not here.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "cpu/scene.h"
#include "cpu/splat.h"
#include "cpu/thickness.h"
#include "shared/thickness.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "test_util.h"

namespace thickness_test_local {

using namespace meniscus;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Full resolution, no blur: the exact per-pixel chords.
ThicknessParams noBlur() {
    ThicknessParams p;
    p.blurSigmaRadii = 0.0f;
    p.resolutionDivisor = 1;
    return p;
}

ThicknessParams withDivisor(int divisor) {
    ThicknessParams p;  // default blur
    p.resolutionDivisor = divisor;
    return p;
}

// Length of the ray through the centre of pixel (i, j) inside the sphere, in
// double precision, clipped to eye depths [zNear, zFar).
double analyticChord(const Camera& cam, int i, int j, const glm::dvec3& c, double r, double zNear, double zFar) {
    const double f = 0.5 * cam.height / std::tan(0.5 * glm::radians(double(cam.fovYDegrees)));
    const glm::dvec3 d{(i + 0.5 - 0.5 * cam.width) / f, -(j + 0.5 - 0.5 * cam.height) / f, -1.0};
    const double len = glm::length(d);
    const glm::dvec3 u = d / len;
    const double b = glm::dot(u, c);
    const double h2 = r * r - glm::dot(c - b * u, c - b * u);
    if (h2 < 0) return 0.0;
    const double t0 = std::max(b - std::sqrt(h2), zNear * len), t1 = std::min(b + std::sqrt(h2), zFar * len);
    return std::max(0.0, t1 - t0);
}

// Mean of img over the pixels whose centre lies in [x0, x1) x [y0, y1).
double meanOver(const Image<float>& img, int x0, int y0, int x1, int y1) {
    double sum = 0.0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) sum += img.at(x, y);
    return sum / (double(x1 - x0) * double(y1 - y0));
}

// A block of nx x ny x nz particles at spacing s (radius s/2) seen face-on,
// its front face 3 m from the eye; projected radius ~5.5 px.
struct BlockScene {
    float s = 0.1f, r = 0.05f;
    int nz = 6;
    std::vector<glm::vec3> pts;
    Camera cam;
    // The pixels that see the central 60% x 60% of the front face.
    int x0, y0, x1, y1;
    BlockScene() {
        const int n = 20;
        pts = test::jitteredBlock({n, n, nz}, s, 0.0f, {-0.5f * s * (n - 1), -0.5f * s * (n - 1), -s * (nz - 1)});
        cam = test::faceOnCamera({0.0f, 0.0f, 0.0f}, 3.0f, 320, 240);
        const float half = 0.3f * s * n;
        const glm::vec2 a = cam.projectView(cam.toView({-half, half, 0.0f}));
        const glm::vec2 b = cam.projectView(cam.toView({half, -half, 0.0f}));
        x0 = int(std::ceil(a.x)), y0 = int(std::ceil(a.y)), x1 = int(b.x), y1 = int(b.y);
    }
};

}  // namespace

TEST(Thickness, WeightCalibratesToTheRestSpacing) {
    // w = s^3 / (4/3 pi r^3); s = 2r by default -> 6/pi. Relative 1e-6.
    EXPECT_NEAR(shared::thicknessWeight(0.05f, noBlur()), 6.0 / std::numbers::pi, 1e-6 * 6.0 / std::numbers::pi);
    ThicknessParams p = noBlur();
    p.spacingM = 0.12f;
    const double want = 0.12 * 0.12 * 0.12 / (4.0 / 3.0 * std::numbers::pi * 0.05 * 0.05 * 0.05);
    EXPECT_NEAR(shared::thicknessWeight(0.05f, p), want, 1e-6 * want);
}

TEST(Thickness, OneSphereFaceOnIsTheAnalyticChord) {
    const Camera cam = test::faceOnCamera({0.0f, 0.0f, 0.0f}, 2.0f, 101, 101);  // odd: a pixel ray through the centre
    const float r = 0.2f;
    const glm::vec3 p{0.0f, 0.0f, 0.0f};
    const Image<float> depth = cpu::splatDepth(cam, std::span(&p, 1), r);
    const Image<float> T = cpu::computeThickness(cam, std::span(&p, 1), r, noBlur(), nullptr, depth);
    const double w = shared::thicknessWeight(r, noBlur());
    // Centre pixel: the full diameter (relative 1e-4).
    EXPECT_NEAR(T.at(50, 50), w * 2.0 * r, 1e-4 * w * 2.0 * r);
    // Every pixel against the double-precision chord (relative 1e-4, plus 1e-3 r
    // absolute for grazing rays where the chord is a square root of a rounding error).
    const glm::dvec3 c = glm::dvec3(cam.toView(p));
    int covered = 0;
    for (int j = 0; j < cam.height; ++j)
        for (int i = 0; i < cam.width; ++i) {
            const double want = w * analyticChord(cam, i, j, c, r, cam.nearM, kInf);
            covered += want > 0.0;
            EXPECT_NEAR(T.at(i, j), want, 1e-4 * want + 1e-3 * r) << i << "," << j;
        }
    EXPECT_GT(covered, 500);  // projected radius ~14 px: ~600 pixels
    // An off-centre pixel, strictly (relative 1e-4).
    const double off = w * analyticChord(cam, 60, 55, c, r, cam.nearM, kInf);
    ASSERT_GT(off, 0.5 * w * r);
    EXPECT_NEAR(T.at(60, 55), off, 1e-4 * off);
}

TEST(Thickness, BlockAtRestSpacingReadsItsTrueDepth) {
    const BlockScene b;
    const Image<float> depth = cpu::splatDepth(b.cam, b.pts, b.r);
    const Image<float> T = cpu::computeThickness(b.cam, b.pts, b.r, noBlur(), nullptr, depth);
    // Per pixel T swings between 0 (between columns) and ~1.9 nz s; the mean over
    // the interior is the true depth nz s within 5%.
    const double mean = meanOver(T, b.x0, b.y0, b.x1, b.y1);
    EXPECT_NEAR(mean, b.nz * b.s, 0.05 * b.nz * b.s);
    EXPECT_GT(b.x1 - b.x0, 50);
}

TEST(Thickness, BlurKeepsTheMeanAndStaysOnTheFluid) {
    const BlockScene b;
    const Image<float> depth = cpu::splatDepth(b.cam, b.pts, b.r);
    const Image<float> raw = cpu::computeThickness(b.cam, b.pts, b.r, noBlur(), nullptr, depth);
    ThicknessParams p;
    p.blurSigmaRadii = 1.0f;
    p.resolutionDivisor = 1;
    const Image<float> T = cpu::computeThickness(b.cam, b.pts, b.r, p, nullptr, depth);
    const double meanRaw = meanOver(raw, b.x0, b.y0, b.x1, b.y1), mean = meanOver(T, b.x0, b.y0, b.x1, b.y1);
    EXPECT_NEAR(mean, meanRaw, 0.02 * meanRaw);  // within 2%
    // It does smooth: the interior's spread shrinks by at least half.
    auto spread = [&](const Image<float>& img, double m) {
        double v = 0.0;
        for (int y = b.y0; y < b.y1; ++y)
            for (int x = b.x0; x < b.x1; ++x) v += (img.at(x, y) - m) * (img.at(x, y) - m);
        return std::sqrt(v / (double(b.x1 - b.x0) * double(b.y1 - b.y0)));
    };
    EXPECT_LT(spread(T, mean), 0.5 * spread(raw, meanRaw));
    // Nothing spreads into pixels without fluid (exactly 0 there).
    for (std::size_t k = 0; k < T.size(); ++k)
        if (std::isinf(depth.pixels[k])) {
            ASSERT_EQ(T.pixels[k], 0.0f) << "pixel " << k;
        }
}

TEST(Thickness, SceneAndNearPlaneClipTheChord) {
    Camera cam = test::faceOnCamera({0.0f, 0.0f, 0.0f}, 2.0f, 101, 101);
    const float r = 0.2f;
    const glm::vec3 p{0.0f, 0.0f, 0.0f};
    const double w = shared::thicknessWeight(r, noBlur());
    const glm::dvec3 c = glm::dvec3(cam.toView(p));
    // A scene plane at the sphere centre's eye depth: half the centre chord
    // remains (relative 1e-4), and every pixel matches the clipped chord.
    const float zc = 2.0f;
    Image<float> scene(cam.width, cam.height, zc);
    const Image<float> depth = cpu::splatDepth(cam, std::span(&p, 1), r, &scene);
    const Image<float> T = cpu::computeThickness(cam, std::span(&p, 1), r, noBlur(), &scene, depth);
    EXPECT_NEAR(T.at(50, 50), w * r, 1e-4 * w * r);
    const double off = w * analyticChord(cam, 58, 45, c, r, cam.nearM, zc);
    ASSERT_GT(off, 0.3 * w * r);
    EXPECT_NEAR(T.at(58, 45), off, 1e-4 * off);
    // A scene in front of the sphere hides it all.
    Image<float> wall(cam.width, cam.height, 1.5f);
    const Image<float> none = cpu::computeThickness(cam, std::span(&p, 1), r, noBlur(), &wall, depth);
    for (float t : none.pixels) ASSERT_EQ(t, 0.0f);
    // The near plane at the centre keeps the back half.
    cam.nearM = zc;
    const Image<float> back = cpu::computeThickness(cam, std::span(&p, 1), r, noBlur(), nullptr, depth);
    EXPECT_NEAR(back.at(50, 50), w * r, 1e-4 * w * r);
    const double offBack = w * analyticChord(cam, 58, 45, c, r, zc, kInf);
    EXPECT_NEAR(back.at(58, 45), offBack, 1e-4 * offBack);
}

TEST(Thickness, OnePassEqualsTheTwoCalls) {
    const BlockScene b;
    Image<float> scene(b.cam.width, b.cam.height, kInf);
    for (int y = 0; y < b.cam.height; ++y)
        for (int x = 0; x < b.cam.width / 3; ++x) scene.at(x, y) = 3.2f;  // cuts through the block, left third
    for (int divisor : {1, 2}) {
        const ThicknessParams p = withDivisor(divisor);
        const Image<float> depth = cpu::splatDepth(b.cam, b.pts, b.r, &scene);
        const Image<float> T = cpu::computeThickness(b.cam, b.pts, b.r, p, &scene, depth);
        const cpu::DepthAndThickness both = cpu::splatDepthAndThickness(b.cam, b.pts, b.r, p, &scene);
        EXPECT_EQ(0, std::memcmp(depth.pixels.data(), both.depth.pixels.data(), depth.size() * sizeof(float)));
        EXPECT_EQ(0, std::memcmp(T.pixels.data(), both.thickness.pixels.data(), T.size() * sizeof(float)))
            << "divisor " << divisor;
    }
}

TEST(Thickness, BitIdenticalForAnyThreadCount) {
    const Camera cam = test::faceOnCamera({0.0f, 0.0f, 0.0f}, 2.0f, 400, 300);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    std::vector<glm::vec3> pts(20000);
    for (auto& p : pts) p = {u(rng), u(rng), u(rng)};
    for (int divisor : {1, 2, 4}) {
        const ThicknessParams params = withDivisor(divisor);  // with the blur
        cpu::DepthAndThickness one;
        {
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
            one = cpu::splatDepthAndThickness(cam, pts, 0.01f, params);
        }
        const cpu::DepthAndThickness all = cpu::splatDepthAndThickness(cam, pts, 0.01f, params);
        EXPECT_EQ(0, std::memcmp(one.depth.pixels.data(), all.depth.pixels.data(), one.depth.size() * sizeof(float)));
        EXPECT_EQ(0, std::memcmp(one.thickness.pixels.data(), all.thickness.pixels.data(),
                                 one.thickness.size() * sizeof(float)))
            << "divisor " << divisor;
        double total = 0.0;
        for (float t : all.thickness.pixels) total += t;
        EXPECT_GT(total, 0.0);
    }
}

TEST(Thickness, ScaleInvariant) {
    const BlockScene b;
    const float s = 10.0f;
    std::vector<glm::vec3> pts10 = b.pts;
    for (auto& p : pts10) p *= s;
    Camera cam10 = b.cam;
    cam10.eye *= s;
    cam10.target *= s;
    cam10.nearM *= s;
    cam10.farM *= s;
    for (int divisor : {1, 2}) {
        const ThicknessParams params = withDivisor(divisor);  // with the blur
        const cpu::DepthAndThickness a = cpu::splatDepthAndThickness(b.cam, b.pts, b.r, params);
        const cpu::DepthAndThickness c = cpu::splatDepthAndThickness(cam10, pts10, s * b.r, params);
        // T scales by s: per pixel within 2e-3 of the block depth (grazing chords are
        // square roots of rounding errors), and the interior mean within 1e-4 relative.
        const float tol = 2e-3f * s * float(b.nz) * b.s;
        for (std::size_t k = 0; k < a.thickness.size(); ++k)
            ASSERT_NEAR(c.thickness.pixels[k], s * a.thickness.pixels[k], tol) << "divisor " << divisor << " pixel " << k;
        const double ma = meanOver(a.thickness, b.x0, b.y0, b.x1, b.y1);
        const double mc = meanOver(c.thickness, b.x0, b.y0, b.x1, b.y1);
        EXPECT_NEAR(mc, s * ma, 1e-4 * s * ma) << "divisor " << divisor;
    }
}

TEST(Thickness, LowResolutionBlockReadsItsTrueDepth) {
    // At half and quarter resolution, blurred or not, the interior still reads
    // the true depth nz s within 5%, and the blurred half-resolution result is
    // within 3% of the full-resolution one on average there; 0 off the fluid.
    const BlockScene b;
    const Image<float> depth = cpu::splatDepth(b.cam, b.pts, b.r);
    const Image<float> full = cpu::computeThickness(b.cam, b.pts, b.r, withDivisor(1), nullptr, depth);
    for (int divisor : {2, 4})
        for (float sigma : {0.0f, 1.0f}) {
            ThicknessParams p = withDivisor(divisor);
            p.blurSigmaRadii = sigma;
            const Image<float> T = cpu::computeThickness(b.cam, b.pts, b.r, p, nullptr, depth);
            const double mean = meanOver(T, b.x0, b.y0, b.x1, b.y1);
            EXPECT_NEAR(mean, b.nz * b.s, 0.05 * b.nz * b.s) << "divisor " << divisor << " sigma " << sigma;
            if (divisor == 2 && sigma > 0.0f) {
                const double meanFull = meanOver(full, b.x0, b.y0, b.x1, b.y1);
                EXPECT_NEAR(mean, meanFull, 0.03 * meanFull);
            }
            for (std::size_t k = 0; k < T.size(); ++k)
                if (std::isinf(depth.pixels[k])) {
                    ASSERT_EQ(T.pixels[k], 0.0f) << "pixel " << k;
                }
        }
}

TEST(Thickness, LowResolutionSceneClipsTheChord) {
    // A scene plane at the centre of one big sphere: the half-resolution
    // thickness near the centre is half the full chord (within 2%: the blocks'
    // rays differ from the pixel rays by half a pixel), and a wall in front
    // hides it all.
    const Camera cam = test::faceOnCamera({0.0f, 0.0f, 0.0f}, 2.0f, 100, 100);
    const float r = 0.2f;
    const glm::vec3 p{0.0f, 0.0f, 0.0f};
    ThicknessParams params = withDivisor(2);
    params.blurSigmaRadii = 0.0f;
    const double w = shared::thicknessWeight(r, params);
    Image<float> scene(cam.width, cam.height, 2.0f);
    const Image<float> depth = cpu::splatDepth(cam, std::span(&p, 1), r, &scene);
    const Image<float> T = cpu::computeThickness(cam, std::span(&p, 1), r, params, &scene, depth);
    EXPECT_NEAR(T.at(50, 50), w * r, 0.02 * w * r);
    Image<float> wall(cam.width, cam.height, 1.5f);
    const Image<float> none = cpu::computeThickness(cam, std::span(&p, 1), r, params, &wall, depth);
    for (float t : none.pixels) ASSERT_EQ(t, 0.0f);
}

// The grid divisor and blur cap both backends derive (src/shared/thickness.h).
TEST(Thickness, DivisorAndBlurCap) {
    const std::pair<int, int> divisors[] = {{-3, 1}, {0, 1}, {1, 1}, {2, 2}, {3, 2}, {4, 4}, {9, 4}};
    for (const auto& [asked, got] : divisors) EXPECT_EQ(shared::thicknessDivisor(asked), got) << asked;
    EXPECT_EQ(shared::thicknessBlurCapPx(-5), 0);
    EXPECT_EQ(shared::thicknessBlurCapPx(32), 32);
    EXPECT_EQ(shared::thicknessBlurCapPx(1000), shared::kThicknessBlurMaxPx);
}
}  // namespace thickness_test_local
