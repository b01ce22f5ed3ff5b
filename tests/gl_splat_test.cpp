// GL depth splat (docs/pipeline.md#depth-splat, src/gl/splat.cpp) against the
// CPU reference cpu::splatDepth: synthetic and real frames, with and without a
// scene depth. Skips only when no headless GL 4.3 context can be created at
// all.
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "core/anisotropy.h"
#include "cpu/splat.h"
#include "cpu/thickness.h"
#include "shared/thickness.h"
#include "gl/splat.h"
#include "gl/thickness_lowres.h"
#include "gl/buffer_fill.h"
#include "gl/filter_separable.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "gl_test_util.h"
#include "test_util.h"

namespace gl_splat_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

// Every test needs the context; without one it skips with the reason.
class GlSplat : public GlTest {};

Result<Image<float>> glSplat(const Camera& cam, std::span<const glm::vec3> pos, float r, const Image<float>* scene = nullptr,
                             std::span<const EllipsoidShape> shapes = {}) {
    return gl::splatDepth(cam, pos, r, scene, shapes);
}

// Tolerances, shared by every case below:
//  - depth: relative 1e-5 where both have fluid. Same operations in the same order
//    on both sides (`precise` in the shader); llvmpipe's sqrt/division may differ
//    from IEEE by an ulp or so, which moves depth by ~1e-7 relative.
//  - coverage: a pixel may differ only where its ray grazes a sphere (squared miss
//    distance within rounding of r^2): at most 0.05% of the covered pixels.
constexpr double kDepthRel = 1e-5;
constexpr double kCoverageFraction = 5e-4;

}  // namespace

TEST_F(GlSplat, OneParticleMatchesCpu) {
    Camera cam;
    cam.eye = {0.3f, 0.4f, 2.0f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.width = 320;
    cam.height = 240;
    cam.fovYDegrees = 40.0f;
    const glm::vec3 p{0.05f, -0.02f, 0.1f};
    const float r = 0.15f;
    const auto gl = glSplat(cam, std::span(&p, 1), r);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    const DepthDiff d = compareDepth(cpu::splatDepth(cam, std::span(&p, 1), r), *gl);
    EXPECT_GT(d.coveredCpu, 1000);
    EXPECT_LE(d.coverageDiffer, int(kCoverageFraction * d.coveredCpu) + 2);  // +2: the grazing edge of one disc
    EXPECT_LE(d.maxRel, kDepthRel);
}

TEST_F(GlSplat, RealFrameMatchesCpu) {
    const RealFrame& frame = realFrame();
    ASSERT_FALSE(frame.positions.empty());
    const float r = frame.radius;
    const Camera cam = realFrameCamera(320, 180);
    const auto gl = glSplat(cam, frame.positions, r);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    const DepthDiff d = compareDepth(cpu::splatDepth(cam, frame.positions, r), *gl);
    std::printf("real frame: %zu particles, %d covered, %d coverage differences, max rel %.3g\n",
                frame.positions.size(), d.coveredCpu, d.coverageDiffer, d.maxRel);
    EXPECT_GT(d.coveredCpu, 320 * 180 / 10);
    EXPECT_LE(d.coverageDiffer, int(kCoverageFraction * d.coveredCpu));
    EXPECT_LE(d.maxRel, kDepthRel);
}

namespace {
// A ball (r = 0.02 m) cut by a scene wall, seen from close enough that the near
// plane clips the front spheres too.
struct ClippedBall {
    std::vector<glm::vec3> positions;
    float r = 0.02f;
    Camera cam;
    Image<float> scene;
};
ClippedBall clippedBall() {
    ClippedBall c;
    c.positions = ballOfParticles({0.0f, 0.0f, 0.0f}, 0.3f, 0.04f);
    c.cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.0f, 200, 150);
    c.cam.nearM = 0.75f;
    c.scene = Image<float>(c.cam.width, c.cam.height, std::numeric_limits<float>::infinity());
    for (int y = 0; y < c.cam.height; ++y)
        for (int x = 0; x < c.cam.width; ++x)
            if (x > c.cam.width / 3) c.scene.at(x, y) = 0.9f + 0.001f * float(y);  // a tilted wall through the ball
    return c;
}
}  // namespace

TEST_F(GlSplat, SceneDepthAndNearPlaneMatchCpu) {
    ClippedBall c = clippedBall();
    const auto& pos = c.positions;
    const float r = c.r;
    const Camera& cam = c.cam;
    Image<float>& scene = c.scene;
    scene.at(0, 0) = -1.0f;  // a bad scene value: nothing in front of it, as on the CPU
    const auto gl = glSplat(cam, pos, r, &scene);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    const Image<float> cpu = cpu::splatDepth(cam, pos, r, &scene);
    const DepthDiff d = compareDepth(cpu, *gl);
    EXPECT_GT(d.coveredCpu, 1000);
    EXPECT_LE(d.coverageDiffer, int(kCoverageFraction * d.coveredCpu) + 2);
    EXPECT_LE(d.maxRel, kDepthRel);
    EXPECT_TRUE(std::isinf(gl->at(0, 0)));
}

TEST_F(GlSplat, NoParticlesIsAllInfinity) {
    const Camera cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.0f, 64, 48);
    const auto gl = glSplat(cam, {}, 0.1f);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    ASSERT_EQ(gl->size(), std::size_t(64 * 48));
    for (float z : gl->pixels) EXPECT_TRUE(std::isinf(z) && z > 0);
}

// ---- Thickness chords (docs/pipeline.md#thickness): GL's fixed-point sums vs the CPU's.

namespace {
struct GlDepthAndThickness {
    Image<float> depth, thickness;
};
GlDepthAndThickness glSplatWithThickness(const Camera& cam, std::span<const glm::vec3> pos, float r,
                                         const ThicknessParams& tp, const Image<float>* scene,
                                         std::span<const EllipsoidShape> shapes = {}) {
    auto s = gl::Splat::create();
    EXPECT_TRUE(s.ok()) << s.error().describe();
    if (!s) return {};
    gl::FrameParamsBlock block;
    const gl::FrameParams frame = gl::packFrameParams(cam, r, NoFilter{}, tp, ShadingParams{});
    block.upload(frame);
    s->uploadParticles(pos, shapes);
    gl::GpuImage sceneImg, depth, thickness;
    if (scene) sceneImg.upload(*scene);
    s->run(frame, scene ? &sceneImg : nullptr, depth, &thickness);
    return {depth.download<float>(), thickness.download<float>()};
}

// Tolerance: both backends round each chord to 1/32768 of a radius and add
// the same integers (shared/splat_chords.h), then resolve them with the same
// formula (and blur and upsample with the same operations), so on llvmpipe
// (IEEE sqrt and division; what CI runs) they agree bit for bit: measured 0
// on every case here, and required. A hardware driver may round sqrt or
// division otherwise, moving a chord by a unit or a grazing pixel's coverage:
// there relative 1e-4 of max(T, 2 r w) -- one whole diameter -- as before the
// CPU summed in fixed point too.
double thicknessRel() {
    std::string why;
    const gl::Context* ctx = sharedGlContext(&why);
    return ctx && gl::isSoftwareRenderer(ctx->renderer()) ? 0.0 : 1e-4;
}

// Compares depth and thickness with the CPU; returns the CPU's largest thickness.
double expectThicknessMatches(const Camera& cam, std::span<const glm::vec3> pos, float r, const Image<float>* scene,
                              std::span<const EllipsoidShape> shapes = {}) {
    ThicknessParams tp;
    tp.blurSigmaRadii = 0.0f;  // the blur is its own stage (gl_filter_separable_test)
    const auto cpu = cpu::splatDepthAndThickness(cam, pos, r, tp, scene, shapes);
    const auto gl = glSplatWithThickness(cam, pos, r, tp, scene, shapes);
    const DepthDiff d = compareDepth(cpu.depth, gl.depth);
    EXPECT_LE(d.coverageDiffer, int(kCoverageFraction * d.coveredCpu) + 2);
    EXPECT_LE(d.maxRel, kDepthRel);
    const double diameter = 2.0 * r * shared::thicknessWeight(r, tp);
    const ScalarDiff t = compareScalar(cpu.thickness, gl.thickness, diameter);
    double maxT = 0.0;
    for (float v : cpu.thickness.pixels) maxT = std::max(maxT, double(v));
    std::printf("thickness: max %.4g m, max abs diff %.3g m, max rel %.3g\n", maxT, t.maxAbs, t.maxRel);
    EXPECT_EQ(t.nonFinite, 0);
    EXPECT_LE(t.maxRel, thicknessRel());
    return maxT / diameter;
}
}  // namespace

TEST_F(GlSplat, ThicknessOfRealFrameMatchesCpu) {
    const RealFrame& frame = realFrame();
    ASSERT_FALSE(frame.positions.empty());
    const float r = frame.radius;
    const Camera cam = realFrameCamera(320, 180);
    EXPECT_GT(expectThicknessMatches(cam, frame.positions, r, nullptr), 4.0);  // diameters: the sums are exercised
}

TEST_F(GlSplat, ThicknessClippedByNearPlaneAndSceneMatchesCpu) {
    const ClippedBall c = clippedBall();
    EXPECT_GT(expectThicknessMatches(c.cam, c.positions, c.r, &c.scene), 4.0);
}

// The rectangle's special cases: spheres reaching the eye plane (the whole
// image: one holds the eye, so only its clipped exit chord counts; one beside
// it), behind the eye (nothing), wholly and partly off screen, one close
// enough to cover a quarter of the image; with a scene and its bad values.
// At 640x480 the spheres at the eye cover more than 65,535 pixels: one
// invocation looping over them all would hit llvmpipe's silent cap on loop
// iterations per invocation (the splat splits such rectangles).
TEST_F(GlSplat, SpheresAtTheEyeOffScreenAndLargeMatchCpu) {
    const float r = 0.1f;
    for (const glm::ivec2 size : {glm::ivec2(160, 120), glm::ivec2(640, 480)}) {
        SCOPED_TRACE(testing::Message() << size.x << "x" << size.y);
        Camera cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.0f, size.x, size.y);
        cam.nearM = 0.05f;
        const glm::vec3 eye = cam.eye;
        const std::vector<glm::vec3> pos = {
            eye + glm::vec3(0.05f, 0.0f, 0.0f),     // holds the eye
            eye + glm::vec3(0.15f, 0.02f, -0.05f),  // crosses the eye plane beside it
            eye + glm::vec3(0.0f, 0.0f, 0.5f),      // behind the eye
            {5.0f, 0.0f, 0.0f},                     // off screen
            {-0.5f, 0.1f, 0.0f},                    // across the left border
            {0.2f, 0.37f, 0.1f},                    // across the top border
            {0.1f, -0.1f, 0.6f},                    // close: ~60 px across at 160x120
            {0.0f, 0.0f, 0.0f},
            {0.05f, 0.02f, -0.05f},
        };
        Image<float> scene(cam.width, cam.height, std::numeric_limits<float>::infinity());
        for (int y = 0; y < cam.height; ++y)
            for (int x = cam.width / 2; x < cam.width; ++x) scene.at(x, y) = 0.95f + 0.002f * float(y) * 120.0f / float(cam.height);
        scene.at(cam.width / 2, cam.height / 2) = -1.0f;
        scene.at(cam.width / 2 + 1, cam.height / 2) = std::numeric_limits<float>::quiet_NaN();
        const auto gl = glSplat(cam, pos, r, &scene);
        ASSERT_TRUE(gl.ok()) << gl.error().describe();
        const DepthDiff d = compareDepth(cpu::splatDepth(cam, pos, r, &scene), *gl);
        EXPECT_GT(d.coveredCpu, cam.width * cam.height / 4);
        EXPECT_LE(d.coverageDiffer, int(kCoverageFraction * d.coveredCpu) + 2);
        EXPECT_LE(d.maxRel, kDepthRel);
        EXPECT_GT(expectThicknessMatches(cam, pos, r, &scene), 1.0);
    }
}

// A camera facing away from every particle, and no particles at all: no
// fluid (+inf) and zero thickness everywhere, as on the CPU.
TEST_F(GlSplat, NothingInViewGivesEmptyDepthAndThickness) {
    Camera away = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.0f, 64, 48);
    away.target = away.eye + glm::vec3(0.0f, 0.0f, 1.0f);
    const auto ball = ballOfParticles({0.0f, 0.0f, 0.0f}, 0.3f, 0.04f);
    for (const std::span<const glm::vec3> pos : {std::span<const glm::vec3>(ball), std::span<const glm::vec3>()}) {
        const auto gl = glSplatWithThickness(away, pos, 0.02f, ThicknessParams{}, nullptr);
        ASSERT_EQ(gl.depth.size(), std::size_t(64 * 48));
        ASSERT_EQ(gl.thickness.size(), std::size_t(64 * 48));
        for (float z : gl.depth.pixels) EXPECT_TRUE(std::isinf(z) && z > 0);
        for (float t : gl.thickness.pixels) EXPECT_EQ(t, 0.0f);
    }
}

// Thickness on a 1/2 and 1/4 resolution grid (chords through block centres,
// blurred there, upsampled), as cpu::splatDepthAndThickness computes it with
// resolutionDivisor 2 and 4: on the real frame at a size no divisor divides,
// with and without a scene (nearest of each block) and with and without the
// blur. Tolerance as at full resolution (the same fixed-point chords): exact
// on llvmpipe.
TEST_F(GlSplat, LowResolutionThicknessMatchesCpu) {
    const RealFrame& frame = realFrame();
    ASSERT_FALSE(frame.positions.empty());
    const float r = frame.radius;
    const Camera cam = realFrameCamera(322, 181);
    Image<float> scene(cam.width, cam.height, std::numeric_limits<float>::infinity());
    {
        const Image<float> fluid = cpu::splatDepth(cam, frame.positions, r);
        for (int y = 0; y < cam.height; ++y)  // a wall through the fluid on the right half
            for (int x = cam.width / 2; x < cam.width; ++x)
                if (std::isfinite(fluid.at(x, y))) scene.at(x, y) = fluid.at(x, y) + 4.0f * r;
    }
    auto splat = gl::Splat::create();
    auto blur = gl::SeparableFilters::create();
    auto lowRes = gl::LowResThickness::create();
    ASSERT_TRUE(splat.ok() && blur.ok() && lowRes.ok());
    Ellipsoids ell;
    computeAnisotropy(frame.positions, r, AnisotropyParams{}, ell);
    for (const bool ellipsoids : {false, true})
    for (const int divisor : {2, 4})
        for (const bool withScene : {false, true})
            for (const float sigma : {0.0f, 1.0f}) {
                SCOPED_TRACE(testing::Message() << "ellipsoids " << ellipsoids << ", divisor " << divisor << ", scene "
                                                << withScene << ", sigma " << sigma);
                const std::span<const glm::vec3> pos = ellipsoids ? std::span<const glm::vec3>(ell.centres)
                                                                  : std::span<const glm::vec3>(frame.positions);
                const std::span<const EllipsoidShape> shapes =
                    ellipsoids ? std::span<const EllipsoidShape>(ell.shapes) : std::span<const EllipsoidShape>();
                splat->uploadParticles(pos, shapes);
                ThicknessParams tp;
                tp.resolutionDivisor = divisor;
                tp.blurSigmaRadii = sigma;
                const Image<float>* sc = withScene ? &scene : nullptr;
                const auto cpu = cpu::splatDepthAndThickness(cam, pos, r, tp, sc, shapes);
                gl::FrameParamsBlock block;
                const gl::FrameParams fp = gl::packFrameParams(cam, r, NoFilter{}, tp, ShadingParams{});
                block.upload(fp);
                gl::GpuImage sceneImg, depth, thickness;
                if (sc) sceneImg.upload(*sc);
                splat->run(fp, sc ? &sceneImg : nullptr, depth, nullptr);
                lowRes->run(fp, *splat, *blur, sc ? &sceneImg : nullptr, depth, divisor, thickness);
                const Image<float> gl = thickness.download<float>();
                const double diameter = 2.0 * r * shared::thicknessWeight(r, tp);
                const ScalarDiff t = compareScalar(cpu.thickness, gl, diameter);
                double maxT = 0.0;
                for (float v : cpu.thickness.pixels) maxT = std::max(maxT, double(v));
                std::printf("thickness 1/%d: max %.4g m, max abs diff %.3g m, max rel %.3g\n", divisor, maxT, t.maxAbs,
                            t.maxRel);
                EXPECT_GT(maxT, 2.0 * diameter);
                EXPECT_EQ(t.nonFinite, 0);
                EXPECT_LE(t.maxRel, thicknessRel());
            }
}

// ---- Ellipsoids (anisotropic kernels, core/anisotropy.h; shared/ellipsoid.h)

// The real frame's anisotropic kernels: depth and chords as on the CPU,
// within the spheres' tolerances (the same shared functions on both sides).
TEST_F(GlSplat, EllipsoidsOfRealFrameMatchCpu) {
    const RealFrame& frame = realFrame();
    ASSERT_FALSE(frame.positions.empty());
    const float r = frame.radius;
    Ellipsoids ell;
    computeAnisotropy(frame.positions, r, AnisotropyParams{}, ell);
    ASSERT_GT(ell.isolated, 0u);
    const Camera cam = realFrameCamera(320, 180);
    const auto gl = glSplat(cam, ell.centres, r, nullptr, ell.shapes);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    const Image<float> cpuDepth = cpu::splatDepth(cam, ell.centres, r, nullptr, ell.shapes);
    const DepthDiff d = compareDepth(cpuDepth, *gl);
    std::printf("ellipsoids: %d covered, %d coverage differences, max rel %.3g\n", d.coveredCpu, d.coverageDiffer,
                d.maxRel);
    EXPECT_GT(d.coveredCpu, 320 * 180 / 10);
    EXPECT_LE(d.coverageDiffer, int(kCoverageFraction * d.coveredCpu));
    EXPECT_LE(d.maxRel, kDepthRel);
    // Not the spheres' depth: the shapes reached the shader.
    const DepthDiff spheres = compareDepth(cpu::splatDepth(cam, ell.centres, r), *gl);
    EXPECT_GT(spheres.coverageDiffer, 100);
    EXPECT_GT(expectThicknessMatches(cam, ell.centres, r, nullptr, ell.shapes), 4.0);
}

// Ellipsoids in the rectangle's special cases (as the spheres above):
// holding the eye, crossing the eye plane, behind it, off screen, across the
// borders, and large enough (over 4096 pixels) for the splat's second pass;
// turned and stretched up to 4:1.
TEST_F(GlSplat, EllipsoidsAtTheEyeOffScreenAndLargeMatchCpu) {
    const float r = 0.1f;
    Camera cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.0f, 320, 240);
    cam.nearM = 0.05f;
    const glm::vec3 eye = cam.eye;
    const std::vector<glm::vec3> pos = {
        eye + glm::vec3(0.05f, 0.0f, 0.0f),  eye + glm::vec3(0.15f, 0.02f, -0.05f), eye + glm::vec3(0.0f, 0.0f, 0.5f),
        {5.0f, 0.0f, 0.0f},                  {-0.5f, 0.1f, 0.0f},                  {0.2f, 0.37f, 0.1f},
        {0.1f, -0.1f, 0.6f},                 {0.0f, 0.0f, 0.0f},                   {0.05f, 0.02f, -0.05f},
    };
    std::vector<EllipsoidShape> shapes;
    for (std::size_t i = 0; i < pos.size(); ++i) {
        const float t = 0.7f * float(i);
        const glm::mat3 rot = glm::mat3(glm::rotate(glm::mat4(1.0f), t, glm::normalize(glm::vec3(1.0f, t, 2.0f))));
        shapes.push_back(ellipsoidShape(rot, r * glm::vec3(1.6f, 1.0f, 0.4f)));
    }
    Image<float> scene(cam.width, cam.height, std::numeric_limits<float>::infinity());
    for (int y = 0; y < cam.height; ++y)
        for (int x = cam.width / 2; x < cam.width; ++x) scene.at(x, y) = 0.95f + 0.001f * float(y);
    const auto gl = glSplat(cam, pos, r, &scene, shapes);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    const DepthDiff d = compareDepth(cpu::splatDepth(cam, pos, r, &scene, shapes), *gl);
    EXPECT_GT(d.coveredCpu, cam.width * cam.height / 8);
    EXPECT_LE(d.coverageDiffer, int(kCoverageFraction * d.coveredCpu) + 2);
    EXPECT_LE(d.maxRel, kDepthRel);
    EXPECT_GT(expectThicknessMatches(cam, pos, r, &scene, shapes), 1.0);
}
}  // namespace gl_splat_test_local
