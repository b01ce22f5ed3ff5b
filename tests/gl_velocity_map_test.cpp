// GL velocity whitening map (docs/pipeline.md#noise-and-foam; Cords & Staadt
// 2008, "Instant Liquids" §4; src/gl/surface_noise.cpp's runWhitening,
// noise_splat.comp and noise_resolve.comp in their whitening mode) against the
// CPU reference cpu::splatWhitening: the map bit for bit on a slab seen from an
// angle with a floating block over it (a jump in depth the culling must see),
// scrambled whiteness from a spread of speeds, and a particle near the camera
// whose sprite takes the large-sprite pass; then the whole pipeline with the
// whitening on (and with the noise as well) through the public Renderer on
// the real frame, which has velocities.
// Skips only when no headless GL 4.3 context can be created at all.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/filters.h"
#include "cpu/splat.h"
#include "cpu/velocity_map.h"
#include "gl/gpu_image.h"
#include "gl/surface_noise.h"
#include "gl/uniforms.h"
#include "gl_test_util.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "shared/velocity_map.h"
#include "test_util.h"

namespace gl_velocity_map_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlVelocityMap : public GlTest {};

constexpr float kInf = std::numeric_limits<float>::infinity();

struct Scene {
    Camera camera;
    float radius = 0.03f;
    std::vector<glm::vec3> positions;
    std::vector<float> whiteness;
    Image<float> depth;
    std::size_t near = 0;  // index of the particle near the camera
};

// A jittered slab of 6,000 particles seen obliquely from above, a block of
// 320 floating 0.3 m over it (its silhouette a jump in depth: the slab's
// particles behind it sample the block's depth and are culled), and one
// particle 0.3 m in front of the eye (a sprite of ~17,000 pixels: pass 2).
// Speeds are scrambled over 0..6 m/s, so with the default threshold and ramp
// (2.5, 2) about 40% of the particles have whiteness 0, 25% have 1 and the
// rest lie between.
Scene makeScene() {
    Scene s;
    s.camera.eye = {0.55f, 1.1f, 1.9f};
    s.camera.target = {0.0f, 0.05f, 0.0f};
    s.camera.width = 320;
    s.camera.height = 240;
    s.positions = jitteredBlock({40, 5, 30}, 0.04f, 0.3f, {-0.8f, -0.1f, -0.6f}, 7);
    const std::vector<glm::vec3> block = jitteredBlock({10, 4, 8}, 0.04f, 0.3f, {-0.3f, 0.35f, -0.1f}, 11);
    s.positions.insert(s.positions.end(), block.begin(), block.end());
    const glm::vec3 view = glm::normalize(s.camera.target - s.camera.eye);
    s.near = s.positions.size();
    s.positions.push_back(s.camera.eye + 0.3f * view + 0.02f * s.camera.right());
    const WhiteningParams p;
    for (std::size_t i = 0; i < s.positions.size(); ++i) {
        const float speed = 6.0f * float((i * 2654435761u) % 1000u) / 1000.0f;
        s.whiteness.push_back(shared::whitenessOfSpeed(speed, p.thresholdMps, p.rampMps));
    }
    s.whiteness[s.near] = 0.8f;
    const Image<float> raw = cpu::splatDepth(s.camera, s.positions, s.radius);
    s.depth = cpu::smoothDepth(raw, s.camera, s.radius, FilterParams{GaussianParams{}});
    return s;
}

Image<float> runGl(const Scene& s, const WhiteningParams& p, std::span<const float> whiteness, double* ms = nullptr) {
    auto stage = gl::SurfaceNoise::create();
    EXPECT_TRUE(stage.ok()) << stage.error().describe();
    if (!stage) return {};
    const gl::FrameParams fp =
        gl::packFrameParams(s.camera, s.radius, FilterParams{}, ThicknessParams{}, ShadingParams{});
    gl::FrameParamsBlock block;
    block.upload(fp);
    gl::Buffer positions;
    positions.upload(s.positions.data(), GLsizeiptr(s.positions.size() * sizeof(glm::vec3)));
    gl::GpuImage depth, map;
    depth.upload(s.depth);
    glFinish();
    const auto t0 = std::chrono::steady_clock::now();
    stage->runWhitening(fp, s.camera, p, positions, GLuint(s.positions.size()), whiteness, depth, map);
    glFinish();
    if (ms) *ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return map.download<float>();
}

void expectBitIdentical(const Scene& s, const WhiteningParams& p, const char* what) {
    const Image<float> ref = cpu::splatWhitening(s.camera, s.positions, s.radius, s.depth, s.whiteness, p);
    double ms = 0.0;
    const Image<float> g = runGl(s, p, s.whiteness, &ms);
    int fluid = 0, between = 0, full = 0, zero = 0;
    for (std::size_t k = 0; k < ref.size(); ++k) {
        if (!(s.depth.pixels[k] < kInf)) continue;
        ++fluid;
        const float v = ref.pixels[k];
        between += v > 0.02f && v < 0.98f;
        full += v >= 0.98f;
        zero += v == 0.0f;
    }
    const int off = differingBits(ref, g);
    std::printf("%s: %d fluid pixels, map 0 on %d, in (0.02, 0.98) on %d, >= 0.98 on %d; differing %d (GL %.1f ms)\n",
                what, fluid, zero, between, full, off, ms);
    EXPECT_GT(between, fluid / 2) << what;  // a real mean of mixed whiteness, not a copy of one particle's
    EXPECT_EQ(off, 0) << what;
    for (std::size_t k = 0; k < ref.size() && k < g.size() && off > 0; ++k)
        if (std::memcmp(&ref.pixels[k], &g.pixels[k], 4) != 0) {
            ADD_FAILURE() << what << ": first difference at pixel " << k % std::size_t(ref.width) << ", "
                          << k / std::size_t(ref.width) << ": cpu " << ref.pixels[k] << " gl " << g.pixels[k];
            break;
        }
}


}  // namespace

TEST_F(GlVelocityMap, MapIsTheCpuBits) {
    const Scene s = makeScene();
    // The near particle really takes the large-sprite pass and counts.
    const WhiteningParams p;
    const glm::vec3 c = s.camera.toView(s.positions[s.near]);
    const shared::NoiseSprite sp =
        shared::noiseSprite(c, s.camera.focalPx(), s.camera.width, s.camera.height, p.spriteRadii * s.radius);
    const int rectPixels = (sp.rect.z - sp.rect.x) * (sp.rect.w - sp.rect.y);
    EXPECT_GT(rectPixels, 4096);
    const float w = shared::noiseParticleWeight(-c.z, s.depth.at(int(sp.centre.x), int(sp.centre.y)), s.radius,
                                                p.depthFalloffRadii * s.radius, 1.0f);
    EXPECT_GE(w, shared::kNoiseMinWeight);
    // The floating block really makes a jump in depth of many radii.
    int jumps = 0;
    for (int y = 0; y < s.depth.height; ++y)
        for (int x = 1; x < s.depth.width; ++x) {
            const float a = s.depth.at(x - 1, y), b = s.depth.at(x, y);
            jumps += a < kInf && b < kInf && std::abs(a - b) > 4.0f * s.radius;
        }
    EXPECT_GT(jumps, 20);
    std::printf("near sprite: %d pixels, weight %.3g; %d depth jumps over 4 r\n", rectPixels, w, jumps);
    expectBitIdentical(s, p, "defaults");
}

TEST_F(GlVelocityMap, OtherParametersAreTheCpuBits) {
    const Scene s = makeScene();
    WhiteningParams p;
    p.spriteRadii = 3.0f;
    p.sigma = 0.6f;
    p.depthFalloffRadii = 2.5f;
    expectBitIdentical(s, p, "sprites of 3 r, sigma 0.6, falloff 2.5 r");
    p.spriteRadii = 1.2f;
    p.sigma = 0.25f;
    p.depthFalloffRadii = 0.5f;
    expectBitIdentical(s, p, "sprites of 1.2 r, sigma 0.25, falloff 0.5 r");
}

TEST_F(GlVelocityMap, NoWhitenessNoFluidOrNoParticlesGiveZero) {
    const Scene s = makeScene();
    const WhiteningParams p;
    // No whiteness given: all 0, though the sprites reach the fluid.
    const Image<float> a = runGl(s, p, {});
    ASSERT_EQ(a.size(), s.depth.size());
    for (float v : a.pixels) ASSERT_EQ(v, 0.0f);
    EXPECT_EQ(differingBits(cpu::splatWhitening(s.camera, s.positions, s.radius, s.depth, {}, p), a), 0);
    // No fluid anywhere.
    Scene none = s;
    none.depth = Image<float>(s.camera.width, s.camera.height, kInf);
    const Image<float> b = runGl(none, p, none.whiteness);
    ASSERT_EQ(b.size(), none.depth.size());
    for (float v : b.pixels) ASSERT_EQ(v, 0.0f);
    // No particles over fluid (the mesh path's case).
    Scene empty = s;
    empty.positions.clear();
    empty.whiteness.clear();
    const Image<float> c = runGl(empty, p, {});
    ASSERT_EQ(c.size(), empty.depth.size());
    for (float v : c.pixels) ASSERT_EQ(v, 0.0f);
    // A depth of another size: 0 everywhere, as on the CPU.
    Scene small = s;
    small.depth = Image<float>(8, 8, 1.0f);
    const Image<float> d = runGl(small, p, small.whiteness);
    ASSERT_EQ(d.size(), s.depth.size());
    for (float v : d.pixels) ASSERT_EQ(v, 0.0f);
}

// The whole pipeline with the whitening on (alone, then with the noise): the
// Whitening (and Noise) AOVs the same bits, the colour within gl_backend_test's
// whole-pipeline tolerance (2 sRGB steps, at most 0.1% of the pixels off by
// more than 1).
TEST_F(GlVelocityMap, PipelineWithWhiteningMatchesCpuOnTheRealFrame) {
    const ParticleSet& set = realSet();
    ASSERT_FALSE(set.positions.empty());
    const ParticleView view = ParticleView::of(set);
    ASSERT_TRUE(view.velocity.present()) << "the real frame has no velocities";
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    RenderSettings s = realFrameSettings(320, 180);
    s.whitening.enabled = true;
    struct Case {
        const char* what;
        bool background, noise;
        float threshold;
    };
    for (const Case& k : {Case{"defaults", true, false, WhiteningParams{}.thresholdMps},
                          Case{"threshold 1 m/s, no background", false, false, 1.0f},
                          Case{"threshold 1 m/s, with the noise", true, true, 1.0f}}) {
        s.scene.background = k.background;
        s.noise.enabled = k.noise;
        s.whitening.thresholdMps = k.threshold;
        BackendFrames f;
        ASSERT_TRUE(renderOnBoth(cpu, *gl, view, s, f));
        const Aovs *a = &f.cpu, *b = &f.gl;
        const std::vector<StageTime>& times = f.glTimes;
        ASSERT_FALSE(a->whitening.empty()) << k.what;
        int white = 0, fluid = 0;
        for (std::size_t i = 0; i < a->whitening.size(); ++i) {
            fluid += a->depth.pixels[i] < kInf;
            white += a->whitening.pixels[i] > 0.05f;
        }
        EXPECT_GT(white, fluid / 50) << k.what;
        EXPECT_EQ(differingBits(a->depth, b->depth), 0) << k.what;
        EXPECT_EQ(differingBits(a->whitening, b->whitening), 0) << k.what;
        if (k.noise) {
            EXPECT_EQ(differingBits(a->noise, b->noise), 0) << k.what;
            EXPECT_EQ(differingBits(a->foam, b->foam), 0) << k.what;
        }
        const ColorDiff c = expectPipelineColor(a->color, b->color, k.what);
        const double whiteMs = stageMs(times, "whitening");
        EXPECT_GE(whiteMs, 0.0) << "no whitening stage timed";
        std::printf("%s: %d fluid pixels, map > 0.05 on %d; colour max %d steps, %.2g%% over 1;"
                    " GL whitening stage %.1f ms\n",
                    k.what, fluid, white, c.maxSteps, 100.0 * c.fractionOver1, whiteMs);
    }
    // White water really changes the picture: the same frame without it differs.
    s.noise.enabled = false;
    s.whitening.enabled = false;
    auto plain = gl->render(view, s);
    s.whitening.enabled = true;
    auto whitened = gl->render(view, s);
    ASSERT_TRUE(plain.ok() && whitened.ok());
    EXPECT_TRUE(plain->whitening.empty());
    EXPECT_GT(compareColor(plain->color, whitened->color).maxSteps, 10);
}
}  // namespace gl_velocity_map_test_local
