// GL narrow-range filter (docs/pipeline.md#narrow-range-filter,
// src/gl/filter_narrow_range.cpp) against the CPU reference
// cpu::filterNarrowRange, 2-D and separable: a jittered block face-on, a ball
// of particles, two bodies, a ball cut by the border, an empty image, small
// kernel caps and the real SPlisHSPlasH frame. Skips only when no headless GL
// 4.3 context exists.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/filters.h"
#include "cpu/splat.h"
#include "gl/filter_narrow_range.h"
#include "gl/uniforms.h"
#include "gl_test_util.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "smoothing_test_util.h"
#include "test_util.h"

namespace gl_filter_narrow_range_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

// Param: separable.
class GlNarrowRange : public GlTest, public ::testing::WithParamInterface<bool> {};

// Tolerances. Same tap order, same (double-computed) weights, the CPU's
// operations in the CPU's order, all `precise` (no FMA), IEEE division on
// llvmpipe: the two agree bit for bit in practice (measured max relative
// difference 0 on every case below). Allowed: relative 1e-6 of the depth (a
// few ulps through 3 iterations, should a driver round division differently)
// and no coverage difference at all (+inf stays +inf, fluid stays fluid).
constexpr double kDepthRel = 1e-6;

NarrowRangeParams params(bool separable) {
    NarrowRangeParams p;
    p.separable = separable;
    return p;
}

gl::FrameParams frameParams(const Camera& cam, float r, const NarrowRangeParams& p) {
    return gl::packFrameParams(cam, r, FilterParams{p}, ThicknessParams{}, ShadingParams{});
}

Image<float> glNarrow(const Image<float>& depth, const Camera& cam, float r, const NarrowRangeParams& p) {
    auto f = gl::NarrowRange::create();
    EXPECT_TRUE(f.ok()) << f.error().describe();
    if (!f) return {};
    const gl::FrameParams fp = frameParams(cam, r, p);
    gl::FrameParamsBlock block;
    block.upload(fp);
    gl::GpuImage in, out;
    in.upload(depth);
    f->run(fp, in, out);
    return out.download<float>();
}

DepthDiff expectParity(const Image<float>& depth, const Camera& cam, float r, const NarrowRangeParams& p,
                       const char* what) {
    const Image<float> cpu = cpu::filterNarrowRange(depth, cam, r, p);
    const Image<float> gl = glNarrow(depth, cam, r, p);
    const DepthDiff d = compareDepth(cpu, gl);
    std::printf("%s (%s): %d fluid px, %d coverage differences, max rel %.3g, mean rel %.3g\n", what,
                p.separable ? "separable" : "2-D", d.coveredCpu, d.coverageDiffer, d.maxRel, d.meanRel);
    EXPECT_EQ(d.coverageDiffer, 0);
    EXPECT_LE(d.maxRel, kDepthRel);
    return d;
}


}  // namespace

TEST_P(GlNarrowRange, JitteredBlockFaceOnMatchesCpu) {
    const auto sc = blockScene();
    const DepthDiff d = expectParity(sc.depth, sc.camera, sc.radius, params(GetParam()), "block");
    EXPECT_GT(d.coveredCpu, 50000);
    // The filter did something: some pixel moved by more than 0.1 r.
    const Image<float> gl = glNarrow(sc.depth, sc.camera, sc.radius, params(GetParam()));
    double moved = 0.0;
    for (std::size_t i = 0; i < gl.size(); ++i)
        if (std::isfinite(gl.pixels[i])) moved = std::max(moved, std::fabs(double(gl.pixels[i]) - sc.depth.pixels[i]));
    EXPECT_GT(moved / sc.radius, 0.1);
}

TEST_P(GlNarrowRange, BallOfParticlesMatchesCpu) {
    const float r = 0.02f;
    const auto pos = ballOfParticles(glm::vec3(0.0f), 0.3f, 2.0f * r);
    const Camera cam = faceOnCamera(glm::vec3(0.0f), 1.2f, 240, 200);
    const Image<float> depth = cpu::splatDepth(cam, pos, r);
    const DepthDiff d = expectParity(depth, cam, r, params(GetParam()), "ball");
    EXPECT_GT(d.coveredCpu, 10000);
}

TEST_P(GlNarrowRange, RealFrameMatchesCpu) {
    const RealFrame& frame = realFrame();
    ASSERT_FALSE(frame.positions.empty());
    const float r = frame.radius;
    const Camera cam = realFrameCamera(320, 180);
    const Image<float> depth = cpu::splatDepth(cam, frame.positions, r);
    const DepthDiff d = expectParity(depth, cam, r, params(GetParam()), "real frame");
    EXPECT_GT(d.coveredCpu, 320 * 180 / 10);
}

TEST_P(GlNarrowRange, SmallCapAndOtherParametersMatchCpu) {
    // maxKernelPx below the projected kernel (every pixel at the cap), other
    // lambda/mu/size/iterations: the block's fields are the ones used.
    const auto sc = blockScene();
    NarrowRangeParams p = params(GetParam());
    p.maxKernelPx = 5;
    p.iterations = 2;
    p.filterSizeRadii = 2.0f;
    p.lambda = 4.0f;
    p.mu = 0.5f;
    expectParity(sc.depth, sc.camera, sc.radius, p, "block, cap 5 px, 2 iterations, lambda 4, mu 0.5");
}

TEST_P(GlNarrowRange, TwoBodiesDoNotBleed) {
    const auto t = twoBodyScene();
    expectParity(t.depth, t.far.camera, t.far.radius, params(GetParam()), "two bodies");
    const auto st = bleedStats(
        t, [&](const Image<float>& d) { return glNarrow(d, t.far.camera, t.far.radius, params(GetParam())); });
    // The CPU test's bounds (tests/filter_narrow_range_test.cpp): a bleed would be ~9 r.
    expectNoBleed(st, "two bodies (GL)");
}

TEST_P(GlNarrowRange, BorderAndInfinityMatchCpu) {
    // A ball cut by the left border: taps beyond it are dropped with their mirror.
    const BorderBallScene sc = borderBallScene();
    expectParity(sc.depth, sc.cam, sc.r, params(GetParam()), "border ball");
    const Image<float> gl = glNarrow(sc.depth, sc.cam, sc.r, params(GetParam()));
    expectCoverageKept(sc.depth, gl);
}

TEST_P(GlNarrowRange, NoFluidStaysInfinity) {
    const Camera cam = faceOnCamera(glm::vec3(0.0f), 1.0f, 67, 45);  // sizes not multiples of the groups
    const Image<float> depth(cam.width, cam.height, std::numeric_limits<float>::infinity());
    const Image<float> gl = glNarrow(depth, cam, 0.01f, params(GetParam()));
    ASSERT_EQ(gl.size(), depth.size());
    for (float z : gl.pixels) ASSERT_TRUE(std::isinf(z) && z > 0);
}

TEST_P(GlNarrowRange, ScatteredPixelsOddWidthMatchCpu) {
    // The GL passes walk only the 8-pixel row segments that hold fluid
    // (gl/fluid_segments.h): isolated fluid pixels (segments with one fluid
    // lane), a full last column of a width that 8 does not divide (a partial
    // last segment) and runs of background between them.
    const Camera cam = faceOnCamera(glm::vec3(0.0f), 1.0f, 67, 45);
    const float r = 0.01f;
    Image<float> depth(cam.width, cam.height, std::numeric_limits<float>::infinity());
    std::uint32_t seed = 12345u;
    auto next = [&] { return (seed = seed * 1664525u + 1013904223u) >> 8; };
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            const bool fluid = x == cam.width - 1 || next() % 10 < 3;
            if (fluid) depth.at(x, y) = 1.0f + 0.002f * float(next() % 1000) / 1000.0f;
        }
    const DepthDiff d = expectParity(depth, cam, r, params(GetParam()), "scattered");
    EXPECT_GT(d.coveredCpu, 0);
    const Image<float> cpu = cpu::filterNarrowRange(depth, cam, r, params(GetParam()));
    int changed = 0;
    for (std::size_t i = 0; i < cpu.size(); ++i) changed += cpu.pixels[i] != depth.pixels[i];
    EXPECT_GT(changed, d.coveredCpu / 2);  // the filter did act on most fluid pixels
}

TEST_P(GlNarrowRange, WideKernelsStayWithinTheLoopLimit) {
    // Kernels of 64 px on every pixel of a 64 x 64 close-up: 6,433 tap pairs
    // per pixel in 2-D. gallivm (llvmpipe) silently stops an invocation's
    // loops after 65,535 iterations in all, so the passes must walk fewer
    // segments per invocation here (FluidSegments::kLoopBudget) than for the
    // usual kernels of a few pixels, or most pixels would come out half
    // filtered.
    const Camera cam = faceOnCamera(glm::vec3(0.0f), 1.0f, 64, 64);
    NarrowRangeParams p = params(GetParam());
    p.maxKernelPx = 64;
    p.iterations = 1;
    const float r = 1.2f * float(p.maxKernelPx) / (p.filterSizeRadii * cam.focalPx());  // kernel > the cap at z = 1
    Image<float> depth(cam.width, cam.height, 1.0f);
    std::uint32_t seed = 777u;
    auto next = [&] { return (seed = seed * 1664525u + 1013904223u) >> 8; };
    for (float& z : depth.pixels) z = 1.0f + 0.2f * r * float(next() % 1000) / 1000.0f;
    const DepthDiff d = expectParity(depth, cam, r, p, "64 px kernels");
    EXPECT_EQ(d.coveredCpu, 64 * 64);
}

TEST_P(GlNarrowRange, ReusedAcrossSizesAndZeroIterations) {
    // One object, two image sizes (tables rebuilt for the new padded width),
    // then zero iterations (a copy).
    auto f = gl::NarrowRange::create();
    ASSERT_TRUE(f.ok()) << f.error().describe();
    const auto a = blockScene();
    const BorderBallScene b = borderBallScene();
    gl::FrameParamsBlock block;
    gl::GpuImage in, out;
    for (int pass = 0; pass < 3; ++pass) {
        const Image<float>& depth = pass == 1 ? b.depth : a.depth;
        const Camera& cam = pass == 1 ? b.cam : a.camera;
        const float r = pass == 1 ? b.r : a.radius;
        NarrowRangeParams p = params(GetParam());
        if (pass == 2) p.iterations = 0;
        const gl::FrameParams fp = frameParams(cam, r, p);
        block.upload(fp);
        in.upload(depth);
        f->run(fp, in, out);
        const DepthDiff d = compareDepth(cpu::filterNarrowRange(depth, cam, r, p), out.download<float>());
        EXPECT_EQ(d.coverageDiffer, 0) << pass;
        EXPECT_LE(d.maxRel, pass == 2 ? 0.0 : kDepthRel) << pass;
    }
}

INSTANTIATE_TEST_SUITE_P(Variants, GlNarrowRange, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& i) { return i.param ? "Separable" : "TwoD"; });
}  // namespace gl_filter_narrow_range_test_local
