// GL curvature flow (docs/pipeline.md#curvature-flow,
// src/gl/filter_curvature_flow.cpp) against the CPU reference
// cpu::filterCurvatureFlow: a jittered block face-on, a ball of particles, two
// bodies, a ball cut by the border, an empty image and the real SPlisHSPlasH
// frame. Skips only when no headless GL 4.3 context exists.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/filters.h"
#include "cpu/splat.h"
#include "gl/filter_curvature_flow.h"
#include "gl/uniforms.h"
#include "gl_test_util.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "smoothing_test_util.h"
#include "test_util.h"

namespace gl_filter_curvature_flow_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlCurvatureFlow : public GlTest {};

// Tolerances. The shader runs the CPU's operations in the same order, all
// `precise` (no FMA), and llvmpipe's division and sqrt are IEEE, so the two
// agree bit for bit in practice (measured max relative difference 0 on every
// case below). Allowed: relative 1e-6 of the depth (a few ulps amplified by
// 40 iterations, should a driver round sqrt/division differently) and no
// coverage difference at all (the fluid set never changes).
constexpr double kDepthRel = 1e-6;

gl::FrameParams frameParams(const Camera& cam, float r, const CurvatureFlowParams& p) {
    return gl::packFrameParams(cam, r, FilterParams{p}, ThicknessParams{}, ShadingParams{});
}

// Runs the GL filter on `depth` (block uploaded here) and reads the result back.
Image<float> glFlow(const Image<float>& depth, const Camera& cam, float r, const CurvatureFlowParams& p = {}) {
    auto flow = gl::CurvatureFlow::create();
    EXPECT_TRUE(flow.ok()) << flow.error().describe();
    if (!flow) return {};
    const gl::FrameParams fp = frameParams(cam, r, p);
    gl::FrameParamsBlock block;
    block.upload(fp);
    gl::GpuImage in, out;
    in.upload(depth);
    flow->run(fp, in, out);
    return out.download<float>();
}

DepthDiff expectParity(const Image<float>& depth, const Camera& cam, float r, const char* what,
                       const CurvatureFlowParams& p = {}) {
    const Image<float> cpu = cpu::filterCurvatureFlow(depth, cam, r, p);
    const Image<float> gl = glFlow(depth, cam, r, p);
    const DepthDiff d = compareDepth(cpu, gl);
    std::printf("%s: %d fluid px, %d coverage differences, max rel %.3g, mean rel %.3g\n", what, d.coveredCpu,
                d.coverageDiffer, d.maxRel, d.meanRel);
    EXPECT_EQ(d.coverageDiffer, 0);
    EXPECT_LE(d.maxRel, kDepthRel);
    return d;
}


}  // namespace

TEST_F(GlCurvatureFlow, JitteredBlockFaceOnMatchesCpu) {
    const auto sc = blockScene();
    const DepthDiff d = expectParity(sc.depth, sc.camera, sc.radius, "block");
    EXPECT_GT(d.coveredCpu, 50000);
}

TEST_F(GlCurvatureFlow, BallOfParticlesMatchesCpu) {
    const float r = 0.02f;
    const auto pos = ballOfParticles(glm::vec3(0.0f), 0.3f, 2.0f * r);
    const Camera cam = faceOnCamera(glm::vec3(0.0f), 1.2f, 240, 200);
    const Image<float> depth = cpu::splatDepth(cam, pos, r);
    const DepthDiff d = expectParity(depth, cam, r, "ball");
    EXPECT_GT(d.coveredCpu, 10000);
}

TEST_F(GlCurvatureFlow, RealFrameMatchesCpu) {
    const RealFrame& frame = realFrame();
    ASSERT_FALSE(frame.positions.empty());
    const float r = frame.radius;
    const Camera cam = realFrameCamera(320, 180);
    const Image<float> depth = cpu::splatDepth(cam, frame.positions, r);
    const DepthDiff d = expectParity(depth, cam, r, "real frame");
    EXPECT_GT(d.coveredCpu, 320 * 180 / 10);
}

TEST_F(GlCurvatureFlow, OtherParametersMatchCpu) {
    // A different step, threshold and count: the block's fields are used.
    const auto sc = blockScene();
    CurvatureFlowParams p;
    p.iterations = 7;
    p.alpha = 0.25f;
    p.jumpRadii = 2.0f;
    expectParity(sc.depth, sc.camera, sc.radius, "block, 7 iterations alpha 0.25 jump 2r", p);
}

TEST_F(GlCurvatureFlow, TwoBodiesDoNotBleed) {
    const auto t = twoBodyScene();
    expectParity(t.depth, t.far.camera, t.far.radius, "two bodies");
    const auto st = bleedStats(t, [&](const Image<float>& d) { return glFlow(d, t.far.camera, t.far.radius); });
    // The CPU test's bounds (tests/filter_curvature_flow_test.cpp): a bleed would be ~9 r.
    expectNoBleed(st, "two bodies (GL)");
}

TEST_F(GlCurvatureFlow, BorderAndInfinityMatchCpu) {
    // A ball cut by the left border: the border counts as "no fluid"; +inf stays +inf.
    const BorderBallScene sc = borderBallScene();
    expectParity(sc.depth, sc.cam, sc.r, "border ball");
    const Image<float> gl = glFlow(sc.depth, sc.cam, sc.r);
    expectCoverageKept(sc.depth, gl);
}

TEST_F(GlCurvatureFlow, NoFluidStaysInfinity) {
    const Camera cam = faceOnCamera(glm::vec3(0.0f), 1.0f, 67, 45);  // sizes not multiples of the tiles
    const Image<float> depth(cam.width, cam.height, std::numeric_limits<float>::infinity());
    const Image<float> gl = glFlow(depth, cam, 0.01f);
    ASSERT_EQ(gl.size(), depth.size());
    for (float z : gl.pixels) ASSERT_TRUE(std::isinf(z) && z > 0);
}

TEST_F(GlCurvatureFlow, ZeroIterationsCopies) {
    const auto sc = borderBallScene();
    CurvatureFlowParams p;
    p.iterations = 0;
    const Image<float> gl = glFlow(sc.depth, sc.cam, sc.r, p);
    ASSERT_EQ(gl.size(), sc.depth.size());
    for (std::size_t i = 0; i < gl.size(); ++i) ASSERT_EQ(std::memcmp(&gl.pixels[i], &sc.depth.pixels[i], 4), 0) << i;
}
}  // namespace gl_filter_curvature_flow_test_local
