// GL hole filling (docs/pipeline.md#hole-filling, src/gl/hole_fill.cpp) against the CPU
// reference cpu::fillHoles on the same inputs: the real frame's splat (radius
// a little small: thousands of holes, slits, bays) with and without a scene
// in front, and a plate with a hole. The rule's arithmetic is shared and
// `precise`, its only division IEEE on llvmpipe: the same pixels filled with
// the same bits (what CI sees). A hardware GPU may round that division
// differently: within 1e-6 relative, and at most 0.1 % of the pixels may
// flip (a span or depth test decided by an ulp).
// Skips only when no headless GL 4.3 context can be created at all.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "cpu/hole_fill.h"
#include "gl/hole_fill.h"
#include "gl/uniforms.h"
#include "gl_test_util.h"
#include "meniscus/renderer.h"
#include "test_util.h"

namespace gl_hole_fill_test_local {

using namespace meniscus;

namespace {

class GlHoleFill : public test::GlTest {};

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr double kMaxRel = 1e-6, kFlipFraction = 1e-3;

void expectSameFill(const Camera& cam, float r, const Image<float>& depth, const Image<float>& thickness,
                    const Image<float>* scene) {
    Image<float> d = depth, t = thickness;
    const std::size_t n = cpu::fillHoles(cam, r, HoleFillParams{}, scene, d, t);
    EXPECT_GT(n, 0u);
    auto hf = gl::HoleFill::create();
    ASSERT_TRUE(hf.ok()) << hf.error().describe();
    const gl::FrameParams fp = gl::packFrameParams(cam, r, NoFilter{}, ThicknessParams{}, ShadingParams{});
    gl::FrameParamsBlock block;
    block.upload(fp);
    gl::GpuImage gd, gt, gs;
    gd.upload(depth);
    gt.upload(thickness);
    if (scene) gs.upload(*scene);
    hf->run(fp, HoleFillParams{}, scene ? &gs : nullptr, gd, gt);
    const Image<float> glD = gd.download<float>(), glT = gt.download<float>();
    ASSERT_EQ(glD.size(), d.size());
    ASSERT_EQ(glT.size(), t.size());
    int flips = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < d.size(); ++i) {
        if ((d.pixels[i] < kInf) != (glD.pixels[i] < kInf)) {
            ++flips;
            continue;
        }
        if (d.pixels[i] < kInf)
            worst = std::max(worst, double(std::abs(d.pixels[i] - glD.pixels[i])) / double(d.pixels[i]));
        worst = std::max(worst, double(std::abs(t.pixels[i] - glT.pixels[i])) / std::max(1e-6, double(t.pixels[i])));
    }
    EXPECT_LE(flips, int(kFlipFraction * double(d.size())));
    EXPECT_LE(worst, kMaxRel);
    const GLubyte* renderer = glGetString(GL_RENDERER);
    if (renderer && std::string(reinterpret_cast<const char*>(renderer)).find("llvmpipe") != std::string::npos) {
        EXPECT_EQ(test::differingBits(d, glD), 0);
        EXPECT_EQ(test::differingBits(t, glT), 0);
    }
}

}  // namespace

TEST_F(GlHoleFill, TheRealFramesSplatFillsTheSameAsTheCpu) {
    auto set = readParticles(test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo").string());
    ASSERT_TRUE(set) << set.error().describe();
    RenderSettings s;
    s.radiusM = 0.02f;
    s.camera = test::lookAt({2.5f, 2.1f, 2.9f}, {0.43f, 0.45f, 0.0f}, 320, 180);
    s.holeFill.enabled = false;
    auto raw = Renderer().render(set->positions, s);
    ASSERT_TRUE(raw) << raw.error().describe();
    expectSameFill(s.camera, s.radiusM, raw->rawDepth, raw->thickness, nullptr);
    // A scene in front of the water's right half (a wall at 3 m there).
    Image<float> scene(320, 180, kInf);
    for (int y = 0; y < 180; ++y)
        for (int x = 160; x < 320; ++x) scene.at(x, y) = 3.0f;
    expectSameFill(s.camera, s.radiusM, raw->rawDepth, raw->thickness, &scene);
}

TEST_F(GlHoleFill, APlateWithAHole) {
    const Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, 64, 48);
    Image<float> d(64, 48, 2.0f), t(64, 48, 0.1f);
    for (int y = 20; y < 23; ++y)
        for (int x = 30; x < 33; ++x) d.at(x, y) = kInf;
    expectSameFill(cam, 0.05f, d, t, nullptr);
}
}  // namespace gl_hole_fill_test_local
