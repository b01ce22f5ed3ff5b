// GL normals stage (docs/pipeline.md#normals, src/gl/normals.cpp) against the
// CPU reference cpu::computeNormals: one particle, a ball, the real frame (raw
// and smoothed depth), and the edge cases: no fluid, fluid touching the image
// border, separate bodies at different depths, isolated pixels, an odd image
// size. Skips only when no headless GL 4.3 context can be created at all.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/filters.h"
#include "cpu/normals.h"
#include "cpu/splat.h"
#include "gl/normals.h"
#include "gl/uniforms.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "gl_test_util.h"
#include "test_util.h"

namespace gl_normals_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlNormals : public GlTest {};

constexpr float kInf = std::numeric_limits<float>::infinity();

// Tolerances. The shader runs normalAt's operations in the CPU's order,
// `precise` (no FMA, no reassociation), and llvmpipe's float division and
// sqrt are IEEE, so the normals agree to rounding:
//  - angle between GL and CPU normals: at most 1e-3 degrees (~2e-5 rad, a few
//    ulps of the tangents' differences, which cancel on nearly flat surfaces);
//  - an ulp can flip a discontinuity decision (|dz| vs the jump threshold),
//    turning a pixel's central difference into a one-sided one: at most 0.01%
//    of the fluid pixels may exceed the angle tolerance;
//  - non-fluid pixels are exactly (0,0,0) on both.
constexpr double kMaxDeg = 1e-3;
constexpr double kFlipFraction = 1e-4;

struct Result3 {
    NormalDiff diff;
    int over = 0;         // fluid pixels beyond kMaxDeg
    int nonFluidBad = 0;  // non-fluid pixels not exactly (0,0,0) on the GL side
    double maxAbs = 0.0;  // max |gl - cpu| of any component (reported)
    Image<glm::vec3> gl;
};

Result3 compareWithCpu(const Image<float>& depth, const Camera& cam, float r) {
    Result3 out;
    auto normals = gl::Normals::create();
    EXPECT_TRUE(normals.ok()) << normals.error().describe();
    if (!normals) return out;
    const gl::FrameParams p = gl::packFrameParams(cam, r, FilterParams{}, ThicknessParams{}, ShadingParams{});
    gl::FrameParamsBlock block;
    block.upload(p);
    gl::GpuImage in, n;
    in.upload(depth);
    normals->run(p, in, n);
    out.gl = n.download<glm::vec3>();
    const Image<glm::vec3> ref = cpu::computeNormals(depth, cam, r, p.normalsJumpRadii);
    out.diff = compareNormals(ref, out.gl, depth);
    for (std::size_t k = 0; k < depth.size() && k < out.gl.size(); ++k) {
        if (!(depth.pixels[k] < kInf)) {
            out.nonFluidBad += out.gl.pixels[k] != glm::vec3(0.0f);
            continue;
        }
        const glm::vec3 a = ref.pixels[k], b = out.gl.pixels[k];
        for (int c = 0; c < 3; ++c) out.maxAbs = std::max(out.maxAbs, double(std::abs(a[c] - b[c])));
        const double c = std::clamp(double(glm::dot(a, b)) / (double(glm::length(a)) * double(glm::length(b))), -1.0, 1.0);
        out.over += !(std::acos(c) * 180.0 / 3.14159265358979 <= kMaxDeg);
    }
    return out;
}

void expectWithinTolerance(const Result3& r, const char* what) {
    std::printf("%s: %d fluid pixels, angle max %.3g deg mean %.3g p99 %.3g, %d over %.0e deg, %d bad non-fluid,"
                " max component difference %.3g\n",
                what, r.diff.compared, r.diff.maxDeg, r.diff.meanDeg, r.diff.p99Deg, r.over, kMaxDeg, r.nonFluidBad,
                r.maxAbs);
    EXPECT_LE(r.over, int(kFlipFraction * r.diff.compared)) << what;
    EXPECT_LE(r.diff.p99Deg, kMaxDeg) << what;
    EXPECT_EQ(r.nonFluidBad, 0) << what;
}


}  // namespace

TEST_F(GlNormals, OneParticleMatchesCpu) {
    Camera cam;
    cam.eye = {0.3f, 0.4f, 2.0f};
    cam.width = 320;
    cam.height = 240;
    cam.fovYDegrees = 40.0f;
    const glm::vec3 p{0.05f, -0.02f, 0.1f};
    const float r = 0.15f;
    const Image<float> depth = cpu::splatDepth(cam, std::span(&p, 1), r);
    const Result3 res = compareWithCpu(depth, cam, r);
    EXPECT_GT(res.diff.compared, 1000);
    expectWithinTolerance(res, "one particle");
    EXPECT_LE(res.diff.maxDeg, kMaxDeg);
}

TEST_F(GlNormals, BallMatchesCpu) {
    // A grid ball: terraced surface with creases and small depth steps.
    const auto pos = ballOfParticles({0.0f, 0.0f, 0.0f}, 0.3f, 0.04f);
    const float r = 0.02f;
    const Camera cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.2f, 257, 191);  // odd size
    const Image<float> depth = cpu::splatDepth(cam, pos, r);
    const Result3 res = compareWithCpu(depth, cam, r);
    EXPECT_GT(res.diff.compared, 5000);
    expectWithinTolerance(res, "ball");
}

TEST_F(GlNormals, RealFrameRawAndSmoothedMatchCpu) {
    const RealFrame& f = realFrame();
    ASSERT_FALSE(f.positions.empty());
    const Camera cam = realFrameCamera(320, 180);
    const Image<float> raw = cpu::splatDepth(cam, f.positions, f.radius);
    const Result3 a = compareWithCpu(raw, cam, f.radius);
    EXPECT_GT(a.diff.compared, 320 * 180 / 10);
    expectWithinTolerance(a, "real frame, raw depth");
    const Image<float> smooth = cpu::smoothDepth(raw, cam, f.radius, NarrowRangeParams{});
    const Result3 b = compareWithCpu(smooth, cam, f.radius);
    expectWithinTolerance(b, "real frame, smoothed depth");
}

TEST_F(GlNormals, NoFluidIsAllZero) {
    const Camera cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.0f, 67, 45);
    const Image<float> depth(cam.width, cam.height, kInf);
    const Result3 res = compareWithCpu(depth, cam, 0.05f);
    ASSERT_EQ(res.gl.size(), depth.size());
    EXPECT_EQ(res.diff.compared, 0);
    EXPECT_EQ(res.nonFluidBad, 0);
}

TEST_F(GlNormals, BordersSeparateBodiesAndIsolatedPixelsMatchCpu) {
    // A tilted plane covering the whole image (fluid on every border pixel: the
    // outside counts as +inf), cut by a nearer body (a depth step far above the
    // jump threshold), with holes and isolated fluid pixels.
    const Camera cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 2.0f, 96, 64);
    const float r = 0.01f;
    Image<float> depth(cam.width, cam.height, kInf);
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) depth.at(x, y) = 2.0f + 0.004f * float(x) - 0.003f * float(y);
    for (int y = 20; y < 44; ++y)
        for (int x = 30; x < 60; ++x) depth.at(x, y) = 1.2f + 0.0005f * float(x * x) / 60.0f;  // separate, nearer
    for (int y = 5; y < 9; ++y)
        for (int x = 70; x < 75; ++x) depth.at(x, y) = kInf;  // a hole
    depth.at(10, 50) = kInf;
    depth.at(12, 50) = kInf;  // a one-pixel sliver between two holes at (11, 50)
    Image<float> sparse(cam.width, cam.height, kInf);  // isolated pixels only
    for (int k = 0; k < 40; ++k) sparse.at((k * 37) % cam.width, (k * 23) % cam.height) = 1.5f + 0.01f * float(k);
    const Result3 a = compareWithCpu(depth, cam, r);
    EXPECT_EQ(a.diff.compared, cam.width * cam.height - 20 - 2);
    expectWithinTolerance(a, "borders and separate bodies");
    EXPECT_LE(a.diff.maxDeg, kMaxDeg);
    // Normals of the two bodies never mix: next to the 0.8 m step the far
    // surface keeps the tilt of its interior (a mixed difference would turn
    // the normal by tens of degrees).
    const glm::vec3 farN = a.gl.at(27, 30), stepN = a.gl.at(29, 30);
    EXPECT_GT(glm::dot(farN, stepN), 0.99999f);
    const Result3 b = compareWithCpu(sparse, cam, r);
    EXPECT_EQ(b.diff.compared, 40);
    expectWithinTolerance(b, "isolated pixels");
    EXPECT_LE(b.diff.maxDeg, kMaxDeg);
}

TEST_F(GlNormals, WrongSizedDepthGivesZeros) {
    const Camera cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.0f, 32, 24);
    auto normals = gl::Normals::create();
    ASSERT_TRUE(normals.ok()) << normals.error().describe();
    const gl::FrameParams p = gl::packFrameParams(cam, 0.05f, FilterParams{}, ThicknessParams{}, ShadingParams{});
    gl::FrameParamsBlock block;
    block.upload(p);
    gl::GpuImage in, n;
    in.upload(Image<float>(16, 24, 1.0f));
    normals->run(p, in, n);
    const Image<glm::vec3> out = n.download<glm::vec3>();
    ASSERT_EQ(out.size(), std::size_t(32 * 24));
    for (const glm::vec3& v : out.pixels) ASSERT_EQ(v, glm::vec3(0.0f));
}
}  // namespace gl_normals_test_local
