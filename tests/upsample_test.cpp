// Reduced-resolution processing (docs/pipeline.md#reduced-resolution;
// src/shared/upsample.h, src/cpu/upsample.cpp, core/fluid_scale.h): the low
// camera sees what the full one sees at 1/d of the pixels; every full pixel
// belongs to exactly one low pixel; the reduced scene depth is the farthest
// under each low pixel; a tilted plane upsampled stays that plane (depth and
// normal); two bodies at different depths and the background are never mixed;
// the contour is the half-coverage line at full resolution (not d x d steps);
// the scene hides what is behind it; edges are blended by the coverage; and the
// whole pipeline at half resolution stays close to the full-resolution render
// of the real frame, with every AOV at the image's size.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/fluid_scale.h"
#include "cpu/upsample.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "shared/upsample.h"
#include "test_util.h"

namespace upsample_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// tests/data/splishsplash/partio/ParticleData_Fluid_21.bgeo (frame 21 of the
// small SPlisHSPlasH dam break), read once.
const ParticleSet& realSet() {
    static const ParticleSet set = [] {
        auto s = readParticles(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
        EXPECT_TRUE(s.ok()) << s.error().describe();
        return s ? std::move(*s) : ParticleSet{};
    }();
    return set;
}

// The eye depth at continuous pixel (px, py) of the view-space plane
// n . p = k (the ray p = z * pixelRay has n . ray z = k).
float planeDepth(const Camera& c, float px, float py, glm::vec3 n, float k) {
    return k / glm::dot(n, c.pixelRay(px, py));
}

}  // namespace

TEST(FluidScale, DivisorsAndTheLowCamera) {
    EXPECT_EQ(fluidDivisor(1.0f), 1);
    EXPECT_EQ(fluidDivisor(0.5f), 2);
    EXPECT_EQ(fluidDivisor(0.25f), 4);
    EXPECT_EQ(fluidDivisor(0.3f), 0);
    EXPECT_EQ(fluidDivisor(2.0f), 0);
    for (const auto& [W, H, d] : {std::tuple{1280, 720, 2}, std::tuple{1281, 721, 4}, std::tuple{67, 33, 4},
                                 std::tuple{7, 5, 2}}) {
        Camera full = faceOnCamera({0.1f, 0.2f, 0.0f}, 2.0f, W, H);
        full.eye += glm::vec3(0.3f, 0.4f, 0.0f);  // not face-on: a general view
        const Camera low = reducedCamera(full, d);
        EXPECT_EQ(low.width, (W + d - 1) / d);
        EXPECT_EQ(low.height, (H + d - 1) / d);
        EXPECT_NEAR(low.focalPx() * float(d), full.focalPx(), 1e-4f * full.focalPx());
        // A point's full pixel coordinate maps to its low coordinate as
        // lowCoordinate does (pixel centres: u = x + 1/2).
        for (glm::vec3 p : {glm::vec3(0.1f, 0.2f, 0.0f), glm::vec3(0.5f, -0.2f, 0.3f), glm::vec3(-0.4f, 0.6f, -0.2f)}) {
            const glm::vec2 uf = full.projectView(full.toView(p)), ul = low.projectView(low.toView(p));
            const float off = float(low.width * d - W), offY = float(low.height * d - H);
            EXPECT_NEAR(ul.x, (uf.x + 0.5f * off) / float(d), 2e-3f) << W << "x" << H << " d " << d;
            EXPECT_NEAR(ul.y, (uf.y + 0.5f * offY) / float(d), 2e-3f) << W << "x" << H << " d " << d;
        }
        // Every full pixel lies in exactly one low pixel's span, its nearest.
        for (const auto& [nf, nl] : {std::pair{W, low.width}, std::pair{H, low.height}}) {
            std::vector<int> owners(std::size_t(nf), 0);
            for (int i = 0; i < nl; ++i) {
                const glm::ivec2 span = shared::lowPixelSpan(i, nf, nl, d);
                ASSERT_LT(span.x, span.y);
                for (int x = span.x; x < span.y; ++x) {
                    ++owners[std::size_t(x)];
                    EXPECT_EQ(shared::nearestLowPixel(x, nf, nl, d), i) << x;
                    // Its centre's low coordinate is within half a low pixel of i.
                    EXPECT_LE(std::fabs(shared::lowCoordinate(x, nf, nl, d) - float(i)), 0.5f);
                }
            }
            for (int n : owners) EXPECT_EQ(n, 1);
        }
    }
    EXPECT_EQ(reducedCamera(faceOnCamera({}, 1.0f, 64, 48), 1), faceOnCamera({}, 1.0f, 64, 48));
}

TEST(FluidScale, ReducedSceneDepthIsTheFarthestUnderEachLowPixel) {
    const int W = 37, H = 23, d = 4, lw = 10, lh = 6;
    Image<float> full(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) full.at(x, y) = (x * 7 + y * 13) % 11 == 0 ? kInf : 1.0f + float((x * 31 + y * 17) % 97);
    const Image<float> low = cpu::reduceSceneDepth(full, lw, lh, d);
    ASSERT_EQ(low.width, lw);
    ASSERT_EQ(low.height, lh);
    for (int j = 0; j < lh; ++j)
        for (int i = 0; i < lw; ++i) {
            const glm::ivec2 xs = shared::lowPixelSpan(i, W, lw, d), ys = shared::lowPixelSpan(j, H, lh, d);
            float z = 0.0f;
            for (int y = ys.x; y < ys.y; ++y)
                for (int x = xs.x; x < xs.y; ++x) z = std::max(z, full.at(x, y));
            EXPECT_EQ(low.at(i, j), z);
        }
}

// A tilted plane rendered exactly at low resolution, upsampled: the depth of
// the plane itself at every full pixel (1/z is affine over a plane), and its
// normal, except the outermost low pixel's worth of border (taps clamped).
TEST(FluidScale, APlaneStaysAPlane) {
    for (const int d : {2, 4}) {
        const Camera full = faceOnCamera({0.0f, 0.0f, 0.0f}, 2.0f, 161, 97);
        const Camera low = reducedCamera(full, d);
        const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.2f, 1.0f));
        const float k = glm::dot(n, glm::vec3(0.0f, 0.0f, -2.0f));  // through the point 2 m ahead
        Image<float> lowDepth(low.width, low.height), lowT(low.width, low.height);
        Image<glm::vec3> lowN(low.width, low.height, n);
        for (int y = 0; y < low.height; ++y)
            for (int x = 0; x < low.width; ++x) {
                lowDepth.at(x, y) = planeDepth(low, float(x) + 0.5f, float(y) + 0.5f, n, k);
                lowT.at(x, y) = 0.01f * float(x) + 0.02f * float(y);  // affine: stays affine
            }
        const cpu::Upsampled up =
            cpu::upsampleSurface(lowDepth, lowN, lowT, nullptr, nullptr, full.width, full.height, d, 0.1f);
        double worstZ = 0.0, worstN = 0.0;
        for (int y = d; y < full.height - d; ++y)
            for (int x = d; x < full.width - d; ++x) {
                const float exact = planeDepth(full, float(x) + 0.5f, float(y) + 0.5f, n, k);
                worstZ = std::max(worstZ, double(std::fabs(up.depth.at(x, y) - exact) / exact));
                worstN = std::max(worstN, double(glm::length(up.normal.at(x, y) - n)));
                EXPECT_EQ(up.coverage.at(x, y), 1.0f);
            }
        std::printf("d = %d: plane depth within %.2e relative, normal within %.2e\n", d, worstZ, worstN);
        EXPECT_LT(worstZ, 2e-6);
        EXPECT_LT(worstN, 1e-6);
        EXPECT_TRUE(up.noise.empty());
    }
}

// Two bodies 1 m and 3 m away side by side with background around them:
// every upsampled depth is one of the two (to rounding), never between, and
// every thickness one of the bodies' own; the fluid/background edge is the
// half-coverage line.
TEST(FluidScale, BodiesAndBackgroundAreNeverMixed) {
    const int lw = 40, lh = 30, d = 2, W = lw * d, H = lh * d;
    Image<float> lowDepth(lw, lh, kInf), lowT(lw, lh, 0.0f);
    Image<glm::vec3> lowN(lw, lh, glm::vec3(0.0f));
    for (int y = 5; y < 25; ++y)
        for (int x = 4; x < 36; ++x) {
            const bool near = x < 20;
            lowDepth.at(x, y) = near ? 1.0f : 3.0f;
            lowT.at(x, y) = near ? 0.1f : 0.2f;
            lowN.at(x, y) = near ? glm::vec3(0, 0, 1) : glm::normalize(glm::vec3(1, 0, 1));
        }
    const cpu::Upsampled up = cpu::upsampleSurface(lowDepth, lowN, lowT, &lowT, nullptr, W, H, d, 0.5f);
    int fluid = 0, nearPx = 0, farPx = 0, partial = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float z = up.depth.at(x, y), t = up.thickness.at(x, y), c = up.coverage.at(x, y);
            partial += c > 0.0f && c < 1.0f;
            if (!(z < kInf)) {
                EXPECT_EQ(t, 0.0f);
                EXPECT_EQ(up.normal.at(x, y), glm::vec3(0.0f));
                EXPECT_LT(c, 0.5f);
                continue;
            }
            EXPECT_GE(c, 0.5f);
            ++fluid;
            const bool isNear = std::fabs(z - 1.0f) < 1e-6f, isFar = std::fabs(z - 3.0f) < 3e-6f;
            ASSERT_TRUE(isNear || isFar) << "depth " << z << " at " << x << ", " << y;
            nearPx += isNear;
            farPx += isFar;
            EXPECT_NEAR(t, isNear ? 0.1f : 0.2f, 1e-7f);
            EXPECT_NEAR(up.noise.at(x, y), isNear ? 0.1f : 0.2f, 1e-7f);
            EXPECT_NEAR(glm::length(up.normal.at(x, y) - (isNear ? glm::vec3(0, 0, 1) : glm::normalize(glm::vec3(1, 0, 1)))),
                        0.0f, 1e-6f);
        }
    // The two bodies are 16 x 20 low pixels each: the seam between them (each
    // full pixel takes the body of its nearest tap) and their outer contours
    // (the half-coverage line) split the full pixels evenly.
    EXPECT_GT(fluid, 4 * 30 * 18);
    EXPECT_EQ(nearPx, farPx);
    EXPECT_GT(partial, 0);
}

// A disc rendered exactly at low resolution: at full resolution its edge is
// the half-coverage line, closer to the true circle than the low pixels'
// d x d blocks, and a row through it is one run of fluid.
TEST(FluidScale, TheContourIsAtFullResolution) {
    const int lw = 48, lh = 48, d = 4, W = lw * d, H = lh * d;
    const float rLow = 15.3f;
    Image<float> lowDepth(lw, lh, kInf);
    for (int y = 0; y < lh; ++y)
        for (int x = 0; x < lw; ++x)
            if (std::hypot(float(x) + 0.5f - 24.0f, float(y) + 0.5f - 24.0f) < rLow) lowDepth.at(x, y) = 1.0f;
    const cpu::Upsampled up = cpu::upsampleSurface(lowDepth, {}, {}, nullptr, nullptr, W, H, d, 0.5f);
    const Image<float> blocks = nearestUpsample(lowDepth, W, H, d);
    int differ = 0, offUp = 0, offBlocks = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const bool exact = std::hypot(float(x) + 0.5f - 96.0f, float(y) + 0.5f - 96.0f) < rLow * float(d);
            const bool a = up.depth.at(x, y) < kInf, b = blocks.at(x, y) < kInf;
            differ += a != b;
            offUp += a != exact;
            offBlocks += b != exact;
        }
    std::printf("disc: %d pixels differ from the block upsampling; off the true circle: %d upsampled, %d blocks\n",
                differ, offUp, offBlocks);
    EXPECT_GT(differ, 0);
    EXPECT_LT(offUp, offBlocks);
    int transitions = 0;
    for (int x = 1; x < W; ++x)
        transitions += (up.depth.at(x, H / 2) < kInf) != (up.depth.at(x - 1, H / 2) < kInf);
    EXPECT_EQ(transitions, 2);
}

TEST(FluidScale, TheSceneHidesWhatIsBehindIt) {
    const int lw = 8, lh = 8, d = 2, W = 16, H = 16;
    Image<float> lowDepth(lw, lh, 2.0f);
    Image<float> scene(W, H, kInf);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W / 2; ++x) scene.at(x, y) = 1.5f;  // a wall in front of the left half
    const cpu::Upsampled up = cpu::upsampleSurface(lowDepth, {}, {}, nullptr, &scene, W, H, d, 0.5f);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) EXPECT_EQ(up.depth.at(x, y) < kInf, x >= W / 2) << x << ", " << y;
}

TEST(FluidScale, EdgesAreBlendedByCoverage) {
    Image<float> depth(3, 1, 1.0f), coverage(3, 1);
    depth.at(2, 0) = kInf;
    coverage.pixels = {1.0f, 0.5f, 0.25f};
    const Image<glm::vec4> behind(3, 1, glm::vec4(0.0f, 0.0f, 1.0f, 1.0f));
    Image<glm::vec4> color(3, 1, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    cpu::blendFluidEdges(depth, coverage, behind, color);
    EXPECT_EQ(color.at(0, 0), glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));  // all fluid: unchanged
    EXPECT_EQ(color.at(1, 0), glm::vec4(0.5f, 0.0f, 0.5f, 1.0f));  // on the contour: half and half
    EXPECT_EQ(color.at(2, 0), glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));  // not fluid: left alone
}

// The real frame at half and quarter resolution against full resolution:
// the same liquid (mask IoU, normals), every AOV at the image's size, the
// reduced stages in the timings; bad scales and the mesh path refused.
TEST(FluidScale, TheRealFrameAtReducedResolution) {
    const ParticleSet& set = realSet();
    RenderSettings s;
    s.radiusM = estimateRadius(set.positions).radius;
    Camera base;
    base.width = 320;
    base.height = 180;
    s.camera = autoFrameCamera(set.positions, s.radiusM, base);
    auto full = renderFrame(ParticleView::of(set), s);
    ASSERT_TRUE(full.ok()) << full.error().describe();
    for (const float scale : {0.5f, 0.25f}) {
        s.fluidScale = scale;
        std::vector<StageTime> times;
        auto low = renderFrame(ParticleView::of(set), s, &times);
        ASSERT_TRUE(low.ok()) << low.error().describe();
        for (const Image<float>* img : {&low->depth, &low->rawDepth, &low->thickness}) {
            EXPECT_EQ(img->width, 320);
            EXPECT_EQ(img->height, 180);
        }
        std::vector<std::string> names;
        for (const auto& t : times) names.push_back(t.stage);
        for (const char* want : {"reduce-scene-depth", "upsample", "fluid-edges"})
            EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
        int both = 0, either = 0;
        std::vector<double> angles;
        for (std::size_t i = 0; i < full->depth.size(); ++i) {
            const bool a = full->depth.pixels[i] < kInf, b = low->depth.pixels[i] < kInf;
            both += a && b;
            either += a || b;
            if (a && b)
                angles.push_back(glm::degrees(std::acos(std::clamp(
                    double(glm::dot(full->normal.pixels[i], low->normal.pixels[i])), -1.0, 1.0))));
        }
        std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
        const double iou = double(both) / double(either), median = angles[angles.size() / 2];
        std::printf("fluid scale %.2f: mask IoU %.3f against full resolution, median normal difference %.1f deg\n",
                    double(scale), iou, median);
        // Bounds above what the renders give (spheres, 3 narrow-range
        // iterations: 0.5: IoU 0.92, 3.8 deg; 0.25: 0.87, 14 deg on this
        // 320 x 180 view of the small dam break, where a quarter of the pixels
        // leaves about one per particle; the default anisotropic kernels with
        // one iteration: 0.93, 6.2 deg and 0.89, 19.2 deg).
        EXPECT_GT(iou, scale == 0.5f ? 0.88 : 0.8);
        EXPECT_LT(median, scale == 0.5f ? 7.5 : 22.0);
    }
    s.fluidScale = 0.3f;
    auto bad = renderFrame(ParticleView::of(set), s);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("fluidScale"), std::string::npos);
}
}  // namespace upsample_test_local
