// GL raycast stage (docs/pipeline.md#ray-cast-surface, src/gl/raycast.cpp)
// against the CPU reference cpu::raycastSurface: a lattice slab face on, the
// real frame from its auto camera (the splat's start depth the same for both),
// a scene depth cutting the rays, no field, and the whole pipeline on both
// backends. Skips only when no headless GL 4.3 context can be created at all.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "core/sph_field.h"
#include "cpu/raycast.h"
#include "cpu/splat.h"
#include "gl/raycast.h"
#include "gl/uniforms.h"
#include "gl_test_util.h"
#include "test_util.h"

namespace gl_raycast_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlRaycast : public GlTest {};

constexpr float kInf = std::numeric_limits<float>::infinity();

// Tolerances. The shader sums the field in the CPU's order (the same four
// partial sums) with every operation `precise`, and llvmpipe's division and
// sqrt are IEEE, so on llvmpipe the two are bit-identical (what this test
// sees in CI). A hardware GPU may round sqrt and division differently: a
// depth within 1e-5 relative, normals within 0.01 degrees, and at most 0.1 %
// of the pixels may change coverage (a march decision flipped by an ulp).
constexpr double kMaxRel = 1e-5, kMaxDeg = 0.01, kFlipFraction = 1e-3;

struct Both {
    cpu::RaycastImages cpu;
    Image<float> glDepth;
    Image<glm::vec3> glNormal;
};

Both castBoth(const std::vector<glm::vec3>& pts, const Camera& cam, float r, const Image<float>* scene = nullptr,
              bool withField = true) {
    Both out;
    RaycastParams p;
    SphField field;
    EXPECT_TRUE(buildSphField(pts, r, p, field));
    const Image<float> start = cpu::splatDepth(cam, pts, p.coverRadii * r);
    out.cpu = cpu::raycastSurface(cam, withField ? field : SphField{}, p, r, start, scene);
    auto rc = gl::Raycast::create();
    EXPECT_TRUE(rc.ok()) << rc.error().describe();
    if (!rc) return out;
    const gl::FrameParams fp = gl::packFrameParams(cam, r, NoFilter{}, ThicknessParams{}, ShadingParams{});
    gl::FrameParamsBlock block;
    block.upload(fp);
    gl::GpuImage s, sc, d, n;
    s.upload(start);
    if (scene) sc.upload(*scene);
    rc->run(fp, withField ? &field : nullptr, p, s, scene ? &sc : nullptr, d, n);
    out.glDepth = d.download<float>();
    out.glNormal = n.download<glm::vec3>();
    return out;
}

void expectClose(const Both& b) {
    const DepthDiff d = compareDepth(b.cpu.depth, b.glDepth);
    EXPECT_LE(d.coverageDiffer, kFlipFraction * std::max(d.coveredCpu, 1));
    EXPECT_LE(d.maxRel, kMaxRel);
    int over = 0;
    for (std::size_t k = 0; k < b.cpu.depth.size(); ++k) {
        const glm::dvec3 a(b.cpu.normal.pixels[k]), g(b.glNormal.pixels[k]);
        if (!std::isfinite(b.cpu.depth.pixels[k]) || !std::isfinite(b.glDepth.pixels[k])) continue;
        const double deg = std::atan2(glm::length(glm::cross(a, g)), glm::dot(a, g)) * 180.0 / 3.14159265358979;
        over += !(deg <= kMaxDeg);
    }
    EXPECT_LE(over, kFlipFraction * std::max(d.coveredCpu, 1));
    // No fluid: +inf and (0,0,0) on the GL side too.
    for (std::size_t k = 0; k < b.glDepth.size(); ++k) {
        if (!std::isfinite(b.glDepth.pixels[k])) {
            EXPECT_EQ(b.glNormal.pixels[k], glm::vec3(0.0f));
        }
    }
}

TEST_F(GlRaycast, ALatticeSlabMatchesTheCpu) {
    const float r = 0.01f, s = 2.0f * r;
    std::vector<glm::vec3> pts;
    for (int z = 0; z < 5; ++z)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) pts.push_back(s * glm::vec3(x, y, z));
    const Camera cam = faceOnCamera(glm::vec3(7.5f * s, 7.5f * s, 4.0f * s), 0.5f, 80, 60);
    const Both b = castBoth(pts, cam, r);
    expectClose(b);
    EXPECT_GT(compareDepth(b.cpu.depth, b.glDepth).coveredCpu, 1000);
}

TEST_F(GlRaycast, TheRealFrameMatchesTheCpu) {
    const RealFrame& f = realFrame();
    const Both b = castBoth(f.positions, realFrameCamera(200, 112), f.radius);
    expectClose(b);
    EXPECT_GT(compareDepth(b.cpu.depth, b.glDepth).coveredCpu, 2000);
}

TEST_F(GlRaycast, ASceneDepthAndNoFieldMatchTheCpu) {
    const RealFrame& f = realFrame();
    const Camera cam = realFrameCamera(120, 68);
    Image<float> scene(120, 68, kInf);
    for (int y = 0; y < 68; ++y)
        for (int x = 0; x < 60; ++x) scene.at(x, y) = 0.8f * glm::length(cam.eye - cam.target);
    expectClose(castBoth(f.positions, cam, f.radius, &scene));
    const Both none = castBoth(f.positions, cam, f.radius, nullptr, false);
    for (float t : none.glDepth.pixels) EXPECT_FALSE(std::isfinite(t));
    for (float t : none.cpu.depth.pixels) EXPECT_FALSE(std::isfinite(t));
}

TEST_F(GlRaycast, ThePipelineMatchesTheCpuBackend) {
    // --surface raycast end to end: the same depth and normals AOVs.
    const RealFrame& f = realFrame();
    RenderSettings s;
    s.radiusM = f.radius;
    s.camera = realFrameCamera(160, 90);
    s.raycast.enabled = true;
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl) << gl.error().describe();
    auto a = Renderer().render(f.positions, s);
    auto b = gl->render(f.positions, s);
    ASSERT_TRUE(a) << a.error().describe();
    ASSERT_TRUE(b) << b.error().describe();
    Both both{{a->depth, a->normal}, b->depth, b->normal};
    expectClose(both);
}

}  // namespace
}  // namespace gl_raycast_test_local
