// GL compositing of several fluids (docs/pipeline.md#several-fluids;
// src/gl/composite_fluids.cpp, shaders/composite_fluids.comp, and the E/T split
// in shaders/shade.comp) against the CPU reference
// (src/cpu/composite_fluids.cpp, src/cpu/shading.cpp): the composite of
// synthetic layers bit for bit, for one to four layers (overlapping bodies in
// every depth order, equal depths, layers hidden behind a scene wall); then the
// whole pipeline with two and three fluids through the public Renderer on the
// real frame. Skips only when no headless GL 4.3 context can be created at all.
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/composite_fluids.h"
#include "gl/composite_fluids.h"
#include "gl/gpu_image.h"
#include "gl_test_util.h"
#include "meniscus/renderer.h"
#include "test_util.h"

namespace gl_composite_fluids_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlCompositeFluids : public GlTest {};

constexpr float kInf = std::numeric_limits<float>::infinity();

// Layer l of W x H: a disc centred differently per layer with a depth slope,
// so that the layers overlap in every order; a few pixels share one depth
// across layers; every value scrambled.
struct Layer {
    Image<float> depth, thickness;
    Image<glm::vec3> normal;
    Image<glm::vec4> color, emission, transmit;
};
Layer makeLayer(int l, int W, int H) {
    Layer L;
    L.depth = Image<float>(W, H, kInf);
    L.thickness = Image<float>(W, H, 0.0f);
    L.normal = Image<glm::vec3>(W, H, glm::vec3(0.0f));
    L.color = Image<glm::vec4>(W, H);
    L.emission = Image<glm::vec4>(W, H, glm::vec4(0.0f));
    L.transmit = Image<glm::vec4>(W, H, glm::vec4(0.0f));
    const float cx = W * (0.3f + 0.13f * float(l)), cy = H * (0.4f + 0.07f * float(l));
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::uint32_t i = std::uint32_t((y * W + x) * 8 + l);
            L.color.at(x, y) = {hash01(i, 1), hash01(i, 2), hash01(i, 3), 1.0f};
            if (std::hypot(float(x) - cx, float(y) - cy) > 0.35f * float(H)) continue;
            const float z = x % 17 == 0 ? 1.5f : 1.0f + 0.2f * float(l) + (float(x) - cx) * (0.01f - 0.004f * float(l));
            L.depth.at(x, y) = z;
            L.thickness.at(x, y) = 0.3f * hash01(i, 4);
            L.normal.at(x, y) = glm::normalize(glm::vec3(hash01(i, 5) - 0.5f, hash01(i, 6) - 0.5f, 1.0f));
            L.emission.at(x, y) = {hash01(i, 7), hash01(i, 8), hash01(i, 9), 1.0f};
            L.transmit.at(x, y) = {hash01(i, 10), hash01(i, 11), hash01(i, 12), 0.0f};
        }
    return L;
}

}  // namespace

TEST_F(GlCompositeFluids, TheCompositeIsTheCpuBits) {
    static auto stage = gl::FluidCompositor::create();
    ASSERT_TRUE(stage.ok()) << stage.error().describe();
    const int W = 157, H = 93;
    Image<float> sceneDepth(W, H, kInf);
    Image<glm::vec4> sceneColor(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::uint32_t i = std::uint32_t(y * W + x);
            sceneDepth.at(x, y) = x < W / 6 ? 1.05f : 4.0f;  // a wall hiding part of the fluids
            sceneColor.at(x, y) = {hash01(i, 20), hash01(i, 21), hash01(i, 22), hash01(i, 23)};
        }
    std::vector<Layer> layers;
    for (int l = 0; l < kMaxFluids; ++l) layers.push_back(makeLayer(l, W, H));
    for (int n = 1; n <= kMaxFluids; ++n) {
        std::vector<cpu::FluidLayerImages> cl;
        std::vector<gl::GpuImage> up(std::size_t(6 * n));
        std::vector<gl::FluidLayerGpu> gl;
        for (int l = 0; l < n; ++l) {
            const Layer& L = layers[std::size_t(l)];
            const int fluid = 3 - l;  // not the layer's position
            cl.push_back({fluid, &L.depth, &L.normal, &L.thickness, &L.color, &L.emission, &L.transmit});
            gl::GpuImage* g = &up[std::size_t(6 * l)];
            g[0].upload(L.depth);
            g[1].upload(L.normal);
            g[2].upload(L.thickness);
            g[3].upload(L.color);
            g[4].upload(L.emission);
            g[5].upload(L.transmit);
            gl.push_back({fluid, &g[0], &g[1], &g[2], &g[3], &g[4], &g[5]});
        }
        const cpu::Composited ref = cpu::compositeFluids(cl, sceneColor, &sceneDepth);
        gl::GpuImage sc, sd, color, depth, normal, thickness, fluid;
        sc.upload(sceneColor);
        sd.upload(sceneDepth);
        stage->run(gl, sc, sd, color, depth, normal, thickness, fluid);
        glFinish();
        EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
        int overlap = 0;
        for (std::size_t i = 0; i < ref.depth.size(); ++i) {
            int m = 0;
            for (int l = 0; l < n; ++l) m += layers[std::size_t(l)].depth.pixels[i] < sceneDepth.pixels[i];
            overlap += m > 1;
        }
        if (n > 1) {
            EXPECT_GT(overlap, W * H / 20) << n;
        }
        EXPECT_EQ(differingBits(ref.color, color.download<glm::vec4>()), 0) << n;
        EXPECT_EQ(differingBits(ref.depth, depth.download<float>()), 0) << n;
        EXPECT_EQ(differingBits(ref.normal, normal.download<glm::vec3>()), 0) << n;
        EXPECT_EQ(differingBits(ref.thickness, thickness.download<float>()), 0) << n;
        EXPECT_EQ(differingBits(ref.fluid, fluid.download<float>()), 0) << n;
    }
}

// The whole pipeline with several fluids on the real frame (split into two,
// then three fluids across the tank; noise and whitening on for the three;
// then two at half resolution):
// CPU and GL give the same depth, normals, fluid index, raw splat, noise and
// whitening, and
// colours within the whole-pipeline tolerance.
TEST_F(GlCompositeFluids, TheWholePipelineWithSeveralFluids) {
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    const ParticleSet& set = realSet();
    Bounds box;
    for (const glm::vec3& p : set.positions) box.extend(p);
    const std::vector<glm::vec3> velocity(set.size(), glm::vec3(0.0f, 0.0f, 1.5f));
    for (int fluids : {2, 3, 4}) {  // 4: two fluids at half resolution
        std::vector<std::int64_t> index(set.size());
        for (std::size_t i = 0; i < set.size(); ++i) {
            const float u = (set.positions[i].x - box.min.x) / (box.max.x - box.min.x);
            index[i] = std::min<std::int64_t>(fluids - 1, std::int64_t(u * float(fluids)));
        }
        ParticleView view = ParticleView::of(set);
        view.fluid = StridedView<std::int64_t>(std::span<const std::int64_t>(index));
        if (fluids == 3) view.velocity = StridedView<glm::vec3>(std::span<const glm::vec3>(velocity));
        RenderSettings s = realFrameSettings(320, 180);
        Material a, b, c;
        ASSERT_TRUE(materialPreset("water", &a) && materialPreset("lava", &b) && materialPreset("milk", &c));
        s.fluidMaterials = {a, b, c};
        s.noise.enabled = fluids == 3;
        s.whitening.enabled = fluids == 3;
        if (fluids == 4) {
            for (std::int64_t& k : index) k = std::min<std::int64_t>(k, 1);
            s.fluidScale = 0.5f;
        }
        BackendFrames f;
        ASSERT_TRUE(renderOnBoth(cpu, *gl, view, s, f));
        EXPECT_EQ(differingBits(f.cpu.depth, f.gl.depth), 0) << fluids;
        EXPECT_EQ(differingBits(f.cpu.rawDepth, f.gl.rawDepth), 0) << fluids;
        EXPECT_EQ(differingBits(f.cpu.fluid, f.gl.fluid), 0) << fluids;
        if (fluids == 3) {  // each pixel's nearest fluid's own maps
            EXPECT_EQ(differingBits(f.cpu.noise, f.gl.noise), 0);
            EXPECT_EQ(differingBits(f.cpu.whitening, f.gl.whitening), 0);
            EXPECT_FALSE(f.cpu.noise.empty());
        }
        const NormalDiff n = compareNormals(f.cpu.normal, f.gl.normal, f.cpu.depth);
        EXPECT_LT(n.maxDeg, 1e-3) << fluids;
        expectPipelineColor(f.cpu.color, f.gl.color, std::to_string(fluids) + " fluids");
        int seen[4] = {0, 0, 0, 0};
        for (float k : f.cpu.fluid.pixels)
            if (k >= 0.0f) ++seen[int(k)];
        for (int k = 0; k < (fluids == 4 ? 2 : fluids); ++k) EXPECT_GT(seen[k], 1000) << fluids << ", fluid " << k;
        EXPECT_GT(stageMs(f.glTimes, "composite-fluids"), -1.0);
        EXPECT_GT(stageMs(f.glTimes, "fluid 1: shade"), -1.0);
        if (fluids == 4) {
            EXPECT_GT(stageMs(f.glTimes, "fluid 1: fluid-edges"), -1.0);
        }
    }
}
}  // namespace gl_composite_fluids_test_local
