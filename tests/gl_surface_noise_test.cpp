// GL surface noise (docs/pipeline.md#noise-and-foam, src/gl/surface_noise.cpp;
// the patent US 8,947,430, eqs. 14-17) against the CPU reference
// src/cpu/surface_noise.cpp: the noise image N and the bumped normals bit for
// bit on a slab seen from an angle (scrambled ids, turbulence amplitudes, a
// particle near the camera whose sprite takes the large-sprite pass), and the
// whole pipeline with the noise and foam on, through the public Renderer on the
// real frame. Skips only when no headless GL 4.3 context can be created at all.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/filters.h"
#include "cpu/normals.h"
#include "cpu/splat.h"
#include "cpu/surface_noise.h"
#include "gl/gpu_image.h"
#include "gl/surface_noise.h"
#include "gl/uniforms.h"
#include "gl_test_util.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "shared/surface_noise.h"
#include "test_util.h"

namespace gl_surface_noise_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlSurfaceNoise : public GlTest {};

struct Scene {
    Camera camera;
    float radius = 0.03f;
    std::vector<glm::vec3> positions;
    std::vector<float> idz, amplitude;
    Image<float> depth;
    Image<glm::vec3> normals;
    std::size_t near = 0;  // index of the particle near the camera
};

// A jittered slab of 6,000 particles seen obliquely from above, plus one
// particle 0.3 m in front of the eye (a sprite of ~17,000 pixels: pass 1).
// Ids are a scrambled permutation far beyond the id period; amplitudes vary
// between 0.4 and 3.2 (the turbulence factors).
Scene makeScene() {
    Scene s;
    s.camera.eye = {0.55f, 1.1f, 1.9f};
    s.camera.target = {0.0f, 0.05f, 0.0f};
    s.camera.width = 320;
    s.camera.height = 240;
    s.positions = jitteredBlock({40, 5, 30}, 0.04f, 0.3f, {-0.8f, -0.1f, -0.6f}, 7);
    const glm::vec3 view = glm::normalize(s.camera.target - s.camera.eye);
    s.near = s.positions.size();
    s.positions.push_back(s.camera.eye + 0.3f * view + 0.02f * s.camera.right());
    const std::size_t n = s.positions.size();
    for (std::size_t i = 0; i < n; ++i) {
        const std::int64_t id = std::int64_t((i * 2654435761u) % 4000037u) + 1000000;
        s.idz.push_back(shared::noiseIdCoordinate(id));
        s.amplitude.push_back(0.4f + 0.7f * float((i * 40503u) % 5u));
    }
    const Image<float> raw = cpu::splatDepth(s.camera, s.positions, s.radius);
    s.depth = cpu::smoothDepth(raw, s.camera, s.radius, FilterParams{GaussianParams{}});
    s.normals = cpu::computeNormals(s.depth, s.camera, s.radius, defaults::kDepthJumpRadii);
    return s;
}

struct GlOut {
    Image<float> noise;
    Image<glm::vec3> normals;
    double ms = 0.0;
};

GlOut runGl(const Scene& s, const NoiseParams& p, bool withAmplitude) {
    GlOut out;
    auto stage = gl::SurfaceNoise::create();
    EXPECT_TRUE(stage.ok()) << stage.error().describe();
    if (!stage) return out;
    const gl::FrameParams fp =
        gl::packFrameParams(s.camera, s.radius, FilterParams{}, ThicknessParams{}, ShadingParams{});
    gl::FrameParamsBlock block;
    block.upload(fp);
    gl::Buffer positions;
    positions.upload(s.positions.data(), GLsizeiptr(s.positions.size() * sizeof(glm::vec3)));
    gl::GpuImage depth, normals, noise;
    depth.upload(s.depth);
    normals.upload(s.normals);
    glFinish();
    const auto t0 = std::chrono::steady_clock::now();
    stage->run(fp, s.camera, p, positions, GLuint(s.positions.size()), s.idz,
               withAmplitude ? std::span<const float>(s.amplitude) : std::span<const float>(), depth, normals, noise);
    glFinish();
    out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    out.noise = noise.download<float>();
    out.normals = normals.download<glm::vec3>();
    return out;
}

void expectBitIdentical(const Scene& s, const NoiseParams& p, bool withAmplitude, const char* what) {
    const std::span<const float> amp = withAmplitude ? std::span<const float>(s.amplitude) : std::span<const float>();
    const Image<float> N = cpu::splatNoise(s.camera, s.positions, s.radius, s.depth, s.idz, amp, p);
    Image<glm::vec3> bumped = s.normals;
    cpu::bumpNormals(s.camera, s.radius, s.depth, N, p, bumped);
    const GlOut g = runGl(s, p, withAmplitude);
    int nonZero = 0, fluid = 0, moved = 0;
    for (std::size_t k = 0; k < N.size(); ++k) {
        fluid += s.depth.pixels[k] < std::numeric_limits<float>::infinity();
        nonZero += N.pixels[k] != 0.0f;
        moved += glm::length(bumped.pixels[k] - s.normals.pixels[k]) > 1e-3f;
    }
    const int offN = differingBits(N, g.noise), offNormals = differingBits(bumped, g.normals);
    std::printf("%s: %d fluid pixels, N != 0 on %d, normals moved on %d; differing: N %d, normals %d (GL %.1f ms)\n",
                what, fluid, nonZero, moved, offN, offNormals, g.ms);
    EXPECT_GT(nonZero, fluid / 2) << what;
    EXPECT_GT(moved, fluid / 4) << what;
    EXPECT_EQ(offN, 0) << what;
    EXPECT_EQ(offNormals, 0) << what;
    for (std::size_t k = 0; k < N.size() && k < g.noise.size() && offN > 0; ++k)
        if (std::memcmp(&N.pixels[k], &g.noise.pixels[k], 4) != 0) {
            ADD_FAILURE() << what << ": first N difference at pixel " << k % std::size_t(N.width) << ", "
                          << k / std::size_t(N.width) << ": cpu " << N.pixels[k] << " gl " << g.noise.pixels[k];
            break;
        }
}

}  // namespace

TEST_F(GlSurfaceNoise, NoiseAndBumpedNormalsAreTheCpuBits) {
    const Scene s = makeScene();
    // The near particle really takes the large-sprite pass and counts.
    const glm::vec3 c = s.camera.toView(s.positions[s.near]);
    const NoiseParams p;
    const shared::NoiseSprite sp =
        shared::noiseSprite(c, s.camera.focalPx(), s.camera.width, s.camera.height, p.spriteRadii * s.radius);
    const int rectPixels = (sp.rect.z - sp.rect.x) * (sp.rect.w - sp.rect.y);
    EXPECT_GT(rectPixels, 4096);
    const float w = shared::noiseParticleWeight(-c.z, s.depth.at(int(sp.centre.x), int(sp.centre.y)), s.radius,
                                                p.depthFalloffRadii * s.radius, s.amplitude[s.near]);
    EXPECT_GE(w, shared::kNoiseMinWeight);
    std::printf("near sprite: %d pixels, weight %.3g\n", rectPixels, w);
    expectBitIdentical(s, p, true, "defaults, amplitudes");
}

TEST_F(GlSurfaceNoise, OtherParametersAndNoAmplitudesAreTheCpuBits) {
    const Scene s = makeScene();
    NoiseParams p;
    p.spriteRadii = 3.0f;
    p.sigma = 0.6f;
    p.frequency = 3.5f;
    p.octaves = 6;
    p.lacunarity = 2.3f;
    p.gain = 0.7f;
    p.depthFalloffRadii = 2.5f;
    p.bump = 1.5f;
    expectBitIdentical(s, p, false, "six octaves, no amplitudes");
}

TEST_F(GlSurfaceNoise, NoFluidOrNoParticlesGiveZero) {
    Scene s = makeScene();
    const NoiseParams p;
    // No fluid anywhere: N = 0, normals untouched (there are none to bump).
    Scene none = s;
    none.depth = Image<float>(s.camera.width, s.camera.height, std::numeric_limits<float>::infinity());
    const GlOut a = runGl(none, p, true);
    ASSERT_EQ(a.noise.size(), none.depth.size());
    for (float v : a.noise.pixels) ASSERT_EQ(v, 0.0f);
    EXPECT_EQ(differingBits(none.normals, a.normals), 0);
    // No particles over fluid (the mesh path's case): N = 0, and the normals
    // renormalised exactly as the CPU's bumpNormals does.
    Scene empty = s;
    empty.positions.clear();
    empty.idz.clear();
    empty.amplitude.clear();
    const Image<float> N = cpu::splatNoise(empty.camera, empty.positions, empty.radius, empty.depth, {}, {}, p);
    Image<glm::vec3> bumped = empty.normals;
    cpu::bumpNormals(empty.camera, empty.radius, empty.depth, N, p, bumped);
    const GlOut b = runGl(empty, p, false);
    EXPECT_EQ(differingBits(N, b.noise), 0);
    EXPECT_EQ(differingBits(bumped, b.normals), 0);
}

// The whole pipeline with the noise on: the Noise AOV the same bits, the
// colour within gl_backend_test's whole-pipeline tolerance (2 sRGB steps, at
// most 0.1% of the pixels off by more than 1), the bumped normals close.
TEST_F(GlSurfaceNoise, PipelineWithNoiseMatchesCpuOnTheRealFrame) {
    ASSERT_FALSE(realFrame().positions.empty());
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    RenderSettings s = realFrameSettings(320, 180);
    s.noise.enabled = true;
    s.noise.foamThreshold = 0.05f;  // foam on a good share of the surface
    for (bool background : {true, false}) {
        s.scene.background = background;
        BackendFrames f;
        ASSERT_TRUE(renderOnBoth(cpu, *gl, ParticleView(realFrame().positions), s, f));
        const Aovs *a = &f.cpu, *b = &f.gl;
        const std::vector<StageTime>& times = f.glTimes;
        ASSERT_FALSE(a->noise.empty());
        int nonZero = 0, foamy = 0;
        for (std::size_t k = 0; k < a->noise.size(); ++k) {
            nonZero += a->noise.pixels[k] != 0.0f;
            foamy += a->foam.pixels[k] > 0.0f;
        }
        EXPECT_GT(nonZero, 320 * 180 / 10);
        EXPECT_GT(foamy, 320 * 180 / 100);
        EXPECT_EQ(differingBits(a->depth, b->depth), 0);
        EXPECT_EQ(differingBits(a->noise, b->noise), 0);
        EXPECT_EQ(differingBits(a->foam, b->foam), 0);
        const NormalDiff n = compareNormals(a->normal, b->normal, a->depth);
        EXPECT_LE(n.p99Deg, 0.01);
        const ColorDiff c = expectPipelineColor(a->color, b->color, "background " + std::string(background ? "on" : "off"));
        const double noiseMs = stageMs(times, "noise");
        EXPECT_GE(noiseMs, 0.0) << "no noise stage timed";
        std::printf("background %s: N != 0 on %d, foam on %d pixels; normals p99 %.3g deg, colour max %d steps,"
                    " %.2g%% over 1; GL noise stage %.1f ms\n",
                    background ? "on" : "off", nonZero, foamy, n.p99Deg, c.maxSteps, 100.0 * c.fractionOver1, noiseMs);
    }
    // Foam really changes the picture: the same frame without the noise differs.
    s.noise.enabled = false;
    auto plain = gl->render(realFrame().positions, s);
    s.noise.enabled = true;
    auto foamed = gl->render(realFrame().positions, s);
    ASSERT_TRUE(plain.ok() && foamed.ok());
    EXPECT_GT(compareColor(plain->color, foamed->color).maxSteps, 10);
}

// The turbulence factors through the pipeline: scrambled ids and a velocity
// jump on every third particle between two consecutive frames, so the second
// frame's amplitudes (FrameSettings::noiseAmplitude) are not all 1; the Noise
// AOV is the CPU's bit for bit on both frames.
TEST_F(GlSurfaceNoise, TurbulenceAmplitudesMatchCpuThroughThePipeline) {
    const std::vector<glm::vec3>& positions = realFrame().positions;
    ASSERT_FALSE(positions.empty());
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    const std::size_t n = positions.size();
    std::vector<std::int64_t> ids(n);
    for (std::size_t i = 0; i < n; ++i) ids[i] = std::int64_t((i * 2654435761u) % 1000003u) * 7 + 3;
    std::vector<glm::vec3> still(n, glm::vec3(0.0f)), jumped = still;
    for (std::size_t i = 0; i < n; i += 3) jumped[i] = glm::vec3(1.0f, 0.0f, 0.0f);  // above tauMps = 0.5
    RenderSettings s = realFrameSettings(320, 180);
    s.noise.enabled = true;
    std::vector<Image<float>> noiseGl;
    for (int frame = 0; frame < 2; ++frame) {
        ParticleView view(positions);
        view.id = StridedView<std::int64_t>(std::span<const std::int64_t>(ids));
        view.velocity = StridedView<glm::vec3>(std::span<const glm::vec3>(frame == 0 ? still : jumped));
        s.frameIndex = frame;
        auto a = cpu.render(view, s);
        auto b = gl->render(view, s);
        ASSERT_TRUE(a.ok()) << a.error().describe();
        ASSERT_TRUE(b.ok()) << b.error().describe();
        EXPECT_EQ(differingBits(a->noise, b->noise), 0) << "frame " << frame;
        expectPipelineColor(a->color, b->color, "frame " + std::to_string(frame));
        noiseGl.push_back(b->noise);
    }
    // The jump really changed the amplitudes (else this tests nothing new).
    EXPECT_GT(differingBits(noiseGl[0], noiseGl[1]), 320 * 180 / 20);
}
}  // namespace gl_surface_noise_test_local
