// GL spray drops (docs/pipeline.md#classification,
// docs/pipeline.md#noise-and-foam; the NVIDIA SSFR patent's spray particles;
// src/gl/spray.cpp, spray_splat.comp and spray_resolve.comp) against the CPU
// reference cpu::drawSpray: the cover and the colour bit for bit on a smoothed
// slab seen from an angle, a nearer wall in the scene depth over part of the
// image, ~2,000 drops above and inside the slab with scrambled velocities (at
// rest, slow, and fast enough for long streaks), a drop near the camera whose
// capsule takes the large-drop pass, and drops behind the near plane or crossing
// it; then the whole pipeline with the spray on through the public Renderer on
// the real frame, which has velocities and no density (so the drops are
// classified by the SPH estimate, core/spray.cpp). Skips only when no headless GL
// 4.3 context can be created at all.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/backend.h"
#include "cpu/filters.h"
#include "cpu/splat.h"
#include "cpu/spray.h"
#include "gl/backend.h"
#include "render/stages.h"
#include "gl/gpu_image.h"
#include "gl/spray.h"
#include "gl_test_util.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "shared/environment.h"
#include "shared/shading.h"
#include "shared/spray.h"
#include "test_util.h"

namespace gl_spray_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlSpray : public GlTest {};

constexpr float kInf = std::numeric_limits<float>::infinity();

struct Scene {
    Camera camera;
    float radius = 0.03f;
    std::vector<glm::vec3> drops, velocities;
    Image<float> depth, sceneDepth;
    Image<glm::vec4> color;
    glm::vec3 light{0.3f, 1.0f, 0.4f};
    std::size_t near = 0;   // index of the drop near the camera
    std::size_t sweep = 0;  // index of the streak across the image
};


// The slab of gl_velocity_map_test (6,000 jittered particles, smoothed), a
// wall 2 m from the eye over the image's right third (nearer than the far
// half of the drops there), 2,000 drops over the slab (the lowest inside it,
// hidden by the fluid), a fifth at rest, most at up to 3 m/s, every 13th at
// 20-60 m/s (streaks of 20-60 cm at 10 ms: tens to hundreds of pixels); one
// drop 0.1 m before the eye (a disc of ~60 pixels' radius), one behind the
// near plane, one behind the eye, one whose streak crosses the near plane
// (drawn round), and one 0.2 m away streaking corner to corner (a faint band
// whose rectangle is the whole image). The colour under them has alpha 0, 0.4 and 1.
Scene makeScene() {
    Scene s;
    s.camera.eye = {0.55f, 1.1f, 1.9f};
    s.camera.target = {0.0f, 0.05f, 0.0f};
    s.camera.width = 320;
    s.camera.height = 240;
    const std::vector<glm::vec3> slab = jitteredBlock({40, 5, 30}, 0.04f, 0.3f, {-0.8f, -0.1f, -0.6f}, 7);
    const Image<float> raw = cpu::splatDepth(s.camera, slab, s.radius);
    s.depth = cpu::smoothDepth(raw, s.camera, s.radius, FilterParams{GaussianParams{}});
    const int W = s.camera.width, H = s.camera.height;
    s.sceneDepth = Image<float>(W, H, kInf);
    for (int y = 0; y < H * 4 / 5; ++y)
        for (int x = W * 2 / 3; x < W; ++x) s.sceneDepth.at(x, y) = 2.0f;
    for (std::uint32_t i = 0; i < 2000; ++i) {
        s.drops.push_back({-0.8f + 1.6f * hash01(i, 1), 0.0f + 0.5f * hash01(i, 2), -0.6f + 1.2f * hash01(i, 3)});
        glm::vec3 v{hash01(i, 4) - 0.5f, hash01(i, 5) - 0.5f, hash01(i, 6) - 0.5f};
        if (i % 5 == 0) v = glm::vec3(0.0f);
        else if (i % 13 == 0) v *= 40.0f + 80.0f * hash01(i, 7);
        else v *= 6.0f;
        s.velocities.push_back(v);
    }
    const glm::vec3 view = glm::normalize(s.camera.target - s.camera.eye);
    s.near = s.drops.size();
    s.drops.push_back(s.camera.eye + 0.1f * view + 0.01f * s.camera.right());
    s.velocities.push_back({0.5f, 0.0f, 0.0f});
    s.drops.push_back(s.camera.eye + 0.5f * s.camera.nearM * view);  // behind the near plane
    s.velocities.push_back({0.0f, 0.0f, 0.0f});
    s.drops.push_back(s.camera.eye - 0.3f * view);  // behind the eye
    s.velocities.push_back({0.0f, 0.0f, 0.0f});
    s.drops.push_back(s.camera.eye + 0.05f * view);  // its streak's end reaches the near plane
    s.velocities.push_back(20.0f * view);
    s.sweep = s.drops.size();  // a faint streak corner to corner: its rectangle is the whole image
    s.drops.push_back(s.camera.eye + 0.2f * view);
    s.velocities.push_back(30.0f * (s.camera.right() + s.camera.trueUp()));
    s.color = Image<glm::vec4>(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float a = (x + y) % 3 == 0 ? 0.0f : ((x / 7) % 2 ? 1.0f : 0.4f);
            s.color.at(x, y) = {0.1f + 0.8f * float(x) / float(W), 0.3f, 0.9f - 0.7f * float(y) / float(H), a};
        }
    return s;
}

struct GlOut {
    Image<float> cover;
    Image<glm::vec4> color;
    GLuint drawn = 0, chunks = 0;
    double ms = 0.0;
};

GlOut runGl(const Scene& s, const SprayParams& p, bool withScene, bool withVelocities) {
    GlOut o;
    static auto stage = gl::SprayDrops::create();
    EXPECT_TRUE(stage.ok()) << stage.error().describe();
    if (!stage) return o;
    gl::GpuImage depth, scene, color, cover;
    depth.upload(s.depth);
    scene.upload(s.sceneDepth);
    color.upload(s.color);
    glFinish();
    const auto t0 = std::chrono::steady_clock::now();
    const std::span<const glm::vec3> v =
        withVelocities ? std::span<const glm::vec3>(s.velocities) : std::span<const glm::vec3>{};
    stage->run(s.camera, s.drops, v, s.radius, p, s.light, depth, withScene ? &scene : nullptr, color, cover);
    glFinish();
    o.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    o.cover = cover.download<float>();
    o.color = color.download<glm::vec4>();
    o.drawn = stage->drawnDrops();
    o.chunks = stage->chunks();
    return o;
}

struct CpuOut {
    Image<float> cover;
    Image<glm::vec4> color;
    double ms = 0.0;
};
CpuOut runCpu(const Scene& s, const SprayParams& p, bool withScene, bool withVelocities) {
    CpuOut o;
    o.color = s.color;
    const auto t0 = std::chrono::steady_clock::now();
    o.cover = cpu::drawSpray(s.camera, s.drops,
                             withVelocities ? std::span<const glm::vec3>(s.velocities) : std::span<const glm::vec3>{},
                             s.radius, s.depth, withScene ? &s.sceneDepth : nullptr, p, s.light, o.color);
    o.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return o;
}

int coveredPixels(const Image<float>& cover) {
    int n = 0;
    for (float v : cover.pixels) n += v > 0.0f;
    return n;
}

// Returns the CPU's cover (for the callers' own checks).
Image<float> expectBitIdentical(const Scene& s, const SprayParams& p, bool withScene, bool withVelocities,
                                const char* what) {
    const CpuOut ref = runCpu(s, p, withScene, withVelocities);
    const GlOut g = runGl(s, p, withScene, withVelocities);
    const double warmMs = runGl(s, p, withScene, withVelocities).ms;  // the first run pays llvmpipe's shader JIT
    const int covered = coveredPixels(ref.cover);
    const int offCover = differingBits(ref.cover, g.cover), offColor = differingBits(ref.color, g.color);
    std::printf("%s: %u drops drawn in %u chunks, %d pixels covered; differing cover %d, colour %d"
                " (GL %.1f ms, CPU %.1f ms)\n",
                what, g.drawn, g.chunks, covered, offCover, offColor, warmMs, ref.ms);
    EXPECT_GT(covered, 1000) << what;
    EXPECT_GE(g.chunks, g.drawn + 64) << what;  // the near drop and the sweep over many invocations
    EXPECT_EQ(offCover, 0) << what;
    EXPECT_EQ(offColor, 0) << what;
    for (std::size_t k = 0; k < ref.cover.size() && k < g.cover.size() && offCover + offColor > 0; ++k)
        if (std::memcmp(&ref.cover.pixels[k], &g.cover.pixels[k], 4) != 0 ||
            std::memcmp(&ref.color.pixels[k], &g.color.pixels[k], 16) != 0) {
            ADD_FAILURE() << what << ": first difference at pixel " << k % std::size_t(ref.cover.width) << ", "
                          << k / std::size_t(ref.cover.width) << ": cpu cover " << ref.cover.pixels[k] << " gl "
                          << g.cover.pixels[k];
            break;
        }
    return ref.cover;
}


}  // namespace

TEST_F(GlSpray, DropsAreTheCpuBits) {
    const Scene s = makeScene();
    const SprayParams p;
    const int W = s.camera.width, H = s.camera.height;
    // The scene really has what the test is about: the near drop's capsule
    // over 4096 pixels, long streaks, drops hidden by the fluid and by the wall.
    const float f = s.camera.focalPx(), sizeM = p.sizeRadii * s.radius;
    int longStreaks = 0, hiddenByFluid = 0, hiddenByWall = 0, behindNear = 0;
    for (std::size_t i = 0; i < s.drops.size(); ++i) {
        const glm::vec3 c = s.camera.toView(s.drops[i]);
        if (!(-c.z > s.camera.nearM)) {
            ++behindNear;
            continue;
        }
        const glm::vec3 v = s.camera.toView(s.camera.eye + s.velocities[i]);
        const shared::SprayDrop d = shared::sprayDrop(c, v, f, W, H, s.camera.nearM, sizeM, p.streakSeconds, p.opacity);
        const int area = (d.rect.z - d.rect.x) * (d.rect.w - d.rect.y);
        if (i == s.near) {
            EXPECT_GT(area, 4096);  // a disc far larger than the others
        }
        if (i == s.sweep) {
            EXPECT_GT(area, 65535);  // more pixels than llvmpipe lets one invocation's loops run
        }
        longStreaks += glm::length(d.b - d.a) > 20.0f;
        const int x = int(std::floor(0.5f * (d.a.x + d.b.x))), y = int(std::floor(0.5f * (d.a.y + d.b.y)));
        if (x < 0 || x >= W || y < 0 || y >= H) continue;
        hiddenByFluid += !(d.z < s.depth.at(x, y));
        hiddenByWall += d.z < s.depth.at(x, y) && !(d.z < s.sceneDepth.at(x, y));
    }
    std::printf("%d long streaks, %d drops hidden by the fluid, %d by the wall, %d behind the near plane\n",
                longStreaks, hiddenByFluid, hiddenByWall, behindNear);
    EXPECT_GT(longStreaks, 50);
    EXPECT_GT(hiddenByFluid, 50);
    EXPECT_GT(hiddenByWall, 50);
    EXPECT_EQ(behindNear, 2);

    const Image<float> withWall = expectBitIdentical(s, p, true, true, "defaults");
    const Image<float> noWall = expectBitIdentical(s, p, false, true, "no scene depth");
    EXPECT_GT(coveredPixels(noWall), coveredPixels(withWall) + 500);  // the wall really hides drops
    expectBitIdentical(s, p, true, false, "round drops");
}

TEST_F(GlSpray, OtherParametersAreTheCpuBits) {
    const Scene s = makeScene();
    SprayParams p;
    p.sizeRadii = 1.5f;
    p.streakSeconds = 0.03f;
    p.opacity = 2.5f;
    p.color = {0.9f, 0.5f, 0.2f};
    expectBitIdentical(s, p, true, true, "drops of 1.5 r, 30 ms streaks, opacity 2.5");
    p.sizeRadii = 0.3f;
    p.streakSeconds = 0.0f;
    p.opacity = 0.2f;
    expectBitIdentical(s, p, true, true, "drops of 0.3 r, no streak, opacity 0.2");
}

// With an HDR map the drops take its ambient (shared::sprayLight, on the
// host for both backends): the same bits as the CPU's, and a constant map of
// radiance L tinted toward red moves the drops' colour by (L - the studio's
// ambient) times their cover (its E(n) / pi is L; the key light's share is
// the same with or without the map).
TEST_F(GlSpray, EnvironmentMapLightsTheDropsAsTheCpu) {
    const Scene s = makeScene();
    SprayParams p;
    p.color = glm::vec3(1.0f);
    const glm::vec3 L{0.9f, 0.5f, 0.2f};
    const ConstantEnvironment constant(L);
    const shared::EnvironmentMap& env = constant.map;
    Image<glm::vec4> cpuColor = s.color;
    const Image<float> cpuCover = cpu::drawSpray(s.camera, s.drops, s.velocities, s.radius, s.depth, &s.sceneDepth, p,
                                                 s.light, cpuColor, env);
    Image<glm::vec4> studioColor = s.color;
    cpu::drawSpray(s.camera, s.drops, s.velocities, s.radius, s.depth, &s.sceneDepth, p, s.light, studioColor);
    auto stage = gl::SprayDrops::create();
    ASSERT_TRUE(stage.ok()) << stage.error().describe();
    gl::GpuImage depth, scene, color, cover;
    depth.upload(s.depth);
    scene.upload(s.sceneDepth);
    color.upload(s.color);
    stage->run(s.camera, s.drops, s.velocities, s.radius, p, s.light, depth, &scene, color, cover, env);
    const Image<glm::vec4> glColor = color.download<glm::vec4>();
    EXPECT_EQ(differingBits(cpuCover, cover.download<float>()), 0);
    EXPECT_EQ(differingBits(cpuColor, glColor), 0);
    // The tint, at the most covered pixel.
    std::size_t best = 0;
    for (std::size_t k = 0; k < cpuCover.pixels.size(); ++k)
        if (cpuCover.pixels[k] > cpuCover.pixels[best]) best = k;
    const float c = cpuCover.pixels[best];
    ASSERT_GT(c, 0.3f);
    const glm::vec4 d = (glColor.pixels[best] - studioColor.pixels[best]) / c;
    std::printf("most covered pixel: cover %.3f, colour moved by the map %.4f %.4f %.4f per cover\n", c, d.x, d.y, d.z);
    const float ambient = shared::kOpaqueAmbient;
    EXPECT_NEAR(d.x, L.x - ambient, 0.01f);
    EXPECT_NEAR(d.y, L.y - ambient, 0.01f);
    EXPECT_NEAR(d.z, L.z - ambient, 0.01f);
}

TEST_F(GlSpray, NoDropsOrMismatchedImagesLeaveTheColour) {
    const Scene s = makeScene();
    const SprayParams p;
    auto unchanged = [&](const Scene& k, const char* what) {
        const GlOut g = runGl(k, p, true, true);
        ASSERT_EQ(g.cover.width, s.camera.width) << what;
        ASSERT_EQ(g.cover.height, s.camera.height) << what;
        for (float v : g.cover.pixels) ASSERT_EQ(v, 0.0f) << what;
        EXPECT_EQ(differingBits(k.color, g.color), 0) << what;
        const CpuOut ref = runCpu(k, p, true, true);
        EXPECT_EQ(differingBits(ref.cover, g.cover), 0) << what;
    };
    Scene none = s;
    none.drops.clear();
    none.velocities.clear();
    unchanged(none, "no drops");
    Scene small = s;
    small.depth = Image<float>(8, 8, kInf);
    unchanged(small, "a depth of another size");
    // Fluid in front of every drop: nothing drawn.
    Scene hidden = s;
    hidden.depth = Image<float>(s.camera.width, s.camera.height, 0.02f);
    unchanged(hidden, "fluid nearer than every drop");
}

// The whole pipeline with the spray on: the Spray AOV (and the depth) the
// same bits, the colour within gl_backend_test's whole-pipeline tolerance (2
// sRGB steps, at most 0.1% of the pixels off by more than 1).
TEST_F(GlSpray, PipelineWithSprayMatchesCpuOnTheRealFrame) {
    const ParticleSet& set = realSet();
    ASSERT_FALSE(set.positions.empty());
    const ParticleView view = ParticleView::of(set);
    ASSERT_TRUE(view.velocity.present()) << "the real frame has no velocities";
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    RenderSettings s = realFrameSettings(320, 180);
    s.spray.enabled = true;
    struct Case {
        const char* what;
        bool background, noise;
        float density, streak;
    };
    for (const Case& k : {Case{"defaults", true, false, SprayParams{}.sprayDensity, SprayParams{}.streakSeconds},
                          Case{"density 0.7, 30 ms streaks, no background", false, false, 0.7f, 0.03f},
                          Case{"density 0.7, with the noise", true, true, 0.7f, 0.01f}}) {
        s.scene.background = k.background;
        s.noise.enabled = k.noise;
        s.spray.sprayDensity = k.density;
        s.spray.streakSeconds = k.streak;
        BackendFrames f;
        ASSERT_TRUE(renderOnBoth(cpu, *gl, view, s, f));
        const Aovs *a = &f.cpu, *b = &f.gl;
        const std::vector<StageTime>& cpuTimes = f.cpuTimes;
        const std::vector<StageTime>& times = f.glTimes;
        ASSERT_FALSE(a->spray.empty()) << k.what;
        const int covered = coveredPixels(a->spray);
        EXPECT_GT(covered, 50) << k.what;
        EXPECT_EQ(differingBits(a->depth, b->depth), 0) << k.what;
        EXPECT_EQ(differingBits(a->spray, b->spray), 0) << k.what;
        const ColorDiff c = expectPipelineColor(a->color, b->color, k.what);
        const double sprayMs = stageMs(times, "spray"), cpuMs = stageMs(cpuTimes, "spray");
        EXPECT_GE(sprayMs, 0.0) << "no spray stage timed";
        std::printf("%s: %d pixels covered; colour max %d steps, %.2g%% over 1; spray stage GL %.2f ms, CPU %.2f ms\n",
                    k.what, covered, c.maxSteps, 100.0 * c.fractionOver1, sprayMs, cpuMs);
    }
}

// Drawn over the scene colour's own slot (not the pipeline's order, which
// draws over the shaded colour, but the backend interface allows it), the
// drops never paint the cached scene: the next cast gives the clean scene
// again, on both backends (GL: the stage drops the cache; CPU: it copies).
TEST_F(GlSpray, PaintingOverTheSceneSlotKeepsTheCachedScene) {
    std::vector<glm::vec3> drops;
    for (int i = 0; i < 60; ++i) drops.push_back({0.1f + 0.04f * float(i % 10), 0.15f + 0.05f * float(i / 10), 0.6f});
    FrameSettings fs;
    fs.camera = faceOnCamera({0.3f, 0.3f, 0.3f}, 1.0f, 96, 64);
    fs.radius = 0.03f;
    fs.spray.enabled = true;
    fs.sprayPositions = drops;
    std::string why;
    ASSERT_TRUE(sharedGlContext(&why)->makeCurrent().ok());  // the Renderers above made their own current
    auto gl = gl::makeGlBackendOnCurrentContext();
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    const std::unique_ptr<Backend> cpu = makeCpuBackend();
    for (Backend* b : {gl->get(), cpu.get()}) {
        ASSERT_TRUE(b->beginFrame({}, fs).ok()) << b->name();
        ASSERT_TRUE(runStage(*b, "scene", {}).ok()) << b->name();
        const Image<glm::vec4> clean = b->readColor(Slot::SceneColor);
        ASSERT_TRUE(runStage(*b, "depth-splat+thickness", {}).ok()) << b->name();  // no particles: no fluid anywhere
        StageIo io;  // drawn over the scene colour itself
        io.at.depth = Slot::RawDepth, io.at.color = Slot::SceneColor;
        EXPECT_TRUE(runStage(*b, "spray", io).ok()) << b->name();
        EXPECT_GT(coveredPixels(b->readScalar(Slot::Spray)), 200) << b->name();
        EXPECT_GT(differingBits(clean, b->readColor(Slot::SceneColor)), 200) << b->name();
        ASSERT_TRUE(runStage(*b, "scene", {}).ok()) << b->name();
        EXPECT_EQ(differingBits(clean, b->readColor(Slot::SceneColor)), 0) << b->name();
    }
}
}  // namespace gl_spray_test_local
