// GL reduced-resolution processing (docs/pipeline.md#reduced-resolution;
// src/gl/upsample.cpp and shaders/upsample*.comp) against the CPU reference
// (src/cpu/upsample.cpp): the reduced scene depth, the upsampled depth, normal,
// thickness, noise and coverage, and the blended edges bit for bit on synthetic
// low images of odd sizes (two bodies at different depths, a sheet, single
// pixels, fluid on the borders, a wall in the scene hiding part of it), for d =
// 2 and 4; then the whole pipeline at half resolution through the public
// Renderer on the real frame (depth and normals the same bits, the colour
// within the whole-pipeline tolerance). Skips only when no headless GL 4.3
// context can be created at all.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "core/fluid_scale.h"
#include "cpu/upsample.h"
#include "gl/gpu_image.h"
#include "gl/upsample.h"
#include "gl_test_util.h"
#include "meniscus/renderer.h"
#include "shared/upsample.h"
#include "test_util.h"

namespace gl_upsample_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlUpsample : public GlTest {};

constexpr float kInf = std::numeric_limits<float>::infinity();


struct LowScene {
    Image<float> depth, thickness, noise, sceneDepth;
    Image<glm::vec3> normal;
    Image<glm::vec4> sceneColor;
};

// lw x lh low images: a disc whose depth varies (0.8-1.4 m), a body behind
// it at 2.5 m, a sheet one pixel wide, ~2% scattered single pixels, a band on
// the top border; the full W x H scene depth with a wall at 1.1 m over its
// left fifth; every value scrambled.
LowScene makeScene(int lw, int lh, int W, int H) {
    LowScene s;
    s.depth = Image<float>(lw, lh, kInf);
    s.thickness = Image<float>(lw, lh, 0.0f);
    s.noise = Image<float>(lw, lh, 0.0f);
    s.normal = Image<glm::vec3>(lw, lh, glm::vec3(0.0f));
    for (int y = 0; y < lh; ++y)
        for (int x = 0; x < lw; ++x) {
            const std::uint32_t i = std::uint32_t(y * lw + x);
            const float dx = float(x) - 0.4f * float(lw), dy = float(y) - 0.5f * float(lh);
            float z = kInf;
            if (std::hypot(dx, dy) < 0.3f * float(lh)) z = 0.8f + 0.6f * float(x) / float(lw);
            else if (x > lw / 2 && y > lh / 3) z = 2.5f;
            else if (x == lw / 5) z = 1.2f;
            else if (y < 2) z = 1.7f;
            else if (hash01(i, 1) < 0.02f) z = 0.5f + 2.0f * hash01(i, 2);
            s.depth.at(x, y) = z;
            if (z < kInf) {
                s.thickness.at(x, y) = 0.2f * hash01(i, 3);
                s.noise.at(x, y) = hash01(i, 4) - 0.5f;
                s.normal.at(x, y) = glm::normalize(glm::vec3(hash01(i, 5) - 0.5f, hash01(i, 6) - 0.5f, 1.0f));
            }
        }
    s.sceneDepth = Image<float>(W, H, kInf);
    s.sceneColor = Image<glm::vec4>(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::uint32_t i = std::uint32_t(y * W + x);
            s.sceneDepth.at(x, y) = x < W / 5 ? 1.1f : 3.0f + hash01(i, 7);
            s.sceneColor.at(x, y) = {hash01(i, 8), hash01(i, 9), hash01(i, 10), hash01(i, 11)};
        }
    return s;
}

}  // namespace

TEST_F(GlUpsample, ReduceUpsampleAndEdgesAreTheCpuBits) {
    static auto stage = gl::Upsampling::create();
    ASSERT_TRUE(stage.ok()) << stage.error().describe();
    for (const auto& [W, H, d] : {std::tuple{203, 117, 2}, std::tuple{203, 117, 4}}) {
        const int lw = shared::lowSide(W, d), lh = shared::lowSide(H, d);
        const LowScene k = makeScene(lw, lh, W, H);
        const float jump = 0.3f;
        // CPU.
        const Image<float> cpuReduced = cpu::reduceSceneDepth(k.sceneDepth, lw, lh, d);
        const cpu::Upsampled ref =
            cpu::upsampleSurface(k.depth, k.normal, k.thickness, &k.noise, &k.sceneDepth, W, H, d, jump);
        Image<glm::vec4> cpuColor(W, H);
        for (std::size_t i = 0; i < cpuColor.size(); ++i)
            cpuColor.pixels[i] = {hash01(std::uint32_t(i), 12), 0.5f, hash01(std::uint32_t(i), 13), 1.0f};
        const Image<glm::vec4> startColor = cpuColor;
        cpu::blendFluidEdges(ref.depth, ref.coverage, k.sceneColor, cpuColor);
        // GL.
        gl::GpuImage sceneDepth, reduced, lowDepth, lowNormal, lowT, lowNoise, depth, normal, thickness, noise,
            coverage, behind, color;
        sceneDepth.upload(k.sceneDepth);
        lowDepth.upload(k.depth);
        lowNormal.upload(k.normal);
        lowT.upload(k.thickness);
        lowNoise.upload(k.noise);
        behind.upload(k.sceneColor);
        color.upload(startColor);
        stage->reduceSceneDepth(sceneDepth, lw, lh, d, reduced);
        stage->upsample(lowDepth, lowNormal, lowT, &lowNoise, &sceneDepth, W, H, d, jump, depth, normal, thickness,
                        &noise, coverage);
        stage->blendEdges(depth, coverage, behind, color);
        glFinish();
        EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
        int fluid = 0, partial = 0;
        for (std::size_t i = 0; i < ref.depth.size(); ++i) {
            fluid += ref.depth.pixels[i] < kInf;
            partial += ref.depth.pixels[i] < kInf && ref.coverage.pixels[i] < 1.0f;
        }
        std::printf("%dx%d, d = %d: %d fluid pixels, %d on an edge\n", W, H, d, fluid, partial);
        EXPECT_GT(fluid, W * H / 10);
        EXPECT_GT(partial, 100);
        EXPECT_EQ(differingBits(cpuReduced, reduced.download<float>()), 0);
        EXPECT_EQ(differingBits(ref.depth, depth.download<float>()), 0);
        EXPECT_EQ(differingBits(ref.normal, normal.download<glm::vec3>()), 0);
        EXPECT_EQ(differingBits(ref.thickness, thickness.download<float>()), 0);
        EXPECT_EQ(differingBits(ref.noise, noise.download<float>()), 0);
        EXPECT_EQ(differingBits(ref.coverage, coverage.download<float>()), 0);
        EXPECT_EQ(differingBits(cpuColor, color.download<glm::vec4>()), 0);
    }
}

// The whole pipeline at half resolution on the real frame, noise on: CPU and
// GL give the same depth and normals, and colours within the whole-pipeline
// tolerance.
TEST_F(GlUpsample, TheWholePipelineAtHalfResolution) {
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    for (const float scale : {0.5f, 0.25f}) {
        RenderSettings s = realFrameSettings(320, 180);
        s.fluidScale = scale;
        s.noise.enabled = true;
        BackendFrames f;
        ASSERT_TRUE(renderOnBoth(cpu, *gl, ParticleView::of(realSet()), s, f));
        EXPECT_EQ(differingBits(f.cpu.depth, f.gl.depth), 0) << scale;
        EXPECT_EQ(differingBits(f.cpu.rawDepth, f.gl.rawDepth), 0) << scale;
        const NormalDiff n = compareNormals(f.cpu.normal, f.gl.normal, f.cpu.depth);
        EXPECT_LT(n.maxDeg, 1e-3) << scale;
        expectPipelineColor(f.cpu.color, f.gl.color, "fluid scale " + std::to_string(scale));
        EXPECT_GT(stageMs(f.glTimes, "upsample"), -1.0);
        EXPECT_GT(stageMs(f.glTimes, "fluid-edges"), -1.0);
    }
}
}  // namespace gl_upsample_test_local
