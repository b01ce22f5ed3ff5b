// The GL mesh path (src/gl/raster_mesh.cpp) against the CPU rasteriser
// cpu::rasteriseMesh: an icosphere with and without a scene depth in front of
// it, the fill rule on a quad whose edges run through pixel centres, a
// triangle crossing the near plane, and the whole pipeline through the
// Renderer with a mesh on both backends. Skips only when no headless GL 4.3
// context can be created at all.
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/raster_mesh.h"
#include "gl/raster_mesh.h"
#include "gl/uniforms.h"
#include "gl_test_util.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "mesh_test_util.h"
#include "test_util.h"

namespace gl_raster_mesh_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlRasterMesh : public GlTest {};

constexpr float kInf = std::numeric_limits<float>::infinity();

// Tolerances, GL vs CPU. GL snaps the window coordinates it computes in float
// (clip / w, then the viewport) to 1/256 px, the CPU those it computes in
// double, and llvmpipe interpolates in float, the CPU in double, so:
//  - eye depth: relative 1e-5 where both have a triangle, but for the
//    centres that the 1/256 px snapping lets into a triangle seen edge-on
//    (the silhouette ring): the CPU clamps their 1/w to the triangle's range,
//    llvmpipe extrapolates: at most 0.1% of the covered pixels, within 1e-2
//    (measured on the sphere: 1 pixel of 13,654, 1.3e-3);
//  - normals: 1e-3 (about 0.06 degrees) of angle in radians at the 99th percentile;
//    the rest (grazing triangles) under 0.25 degrees (measured: 0.03);
//  - coverage: a vertex snapped one 1/256 px step apart moves a pixel centre
//    lying within that step of an edge to the neighbour (or, on a silhouette,
//    out): at most 0.5% of the covered pixels, all on triangle edges;
//  - where the depth agrees, the winner of two nearly equal depths may differ
//    (the depth test compares near/z in GL): the same bound.
constexpr double kDepthRel = 1e-5, kDepthRelRing = 1e-2, kDepthRingFraction = 1e-3;
constexpr double kNormalP99Deg = 1e-3 * 180.0 / 3.14159265358979;
constexpr double kNormalMaxDeg = 0.25;
constexpr double kCoverageFraction = 5e-3;

struct Comparison {
    DepthDiff depth;
    int depthOver = 0;  // pixels covered on both beyond kDepthRel
    NormalDiff normals;
    cpu::MeshRaster cpu;
    Image<float> glDepth;
};

Comparison compareWithCpu(const Camera& cam, const TriangleMesh& mesh, const Image<float>* scene) {
    Comparison c;
    auto r = gl::MeshRasteriser::create();
    EXPECT_TRUE(r.ok()) << r.error().describe();
    if (!r) return c;
    const gl::FrameParams p = gl::packFrameParams(cam, 0.01f, FilterParams{}, ThicknessParams{}, ShadingParams{});
    gl::FrameParamsBlock block;
    block.upload(p);
    gl::GpuImage sceneImg, depth, normal;
    if (scene) sceneImg.upload(*scene);
    r->run(p, mesh, scene ? &sceneImg : nullptr, depth, normal);
    c.glDepth = depth.download<float>();
    const Image<glm::vec3> glNormal = normal.download<glm::vec3>();
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    c.cpu = cpu::rasteriseMesh(cam, mesh, scene);
    c.depth = compareDepth(c.cpu.depth, c.glDepth);
    for (std::size_t k = 0; k < c.glDepth.size(); ++k) {
        const float a = c.cpu.depth.pixels[k], b = c.glDepth.pixels[k];
        c.depthOver += a < kInf && b < kInf && !(std::abs(double(b) - double(a)) <= kDepthRel * double(a));
    }
    // Normals where both have a triangle.
    Image<float> both = c.cpu.depth;
    for (std::size_t k = 0; k < both.size(); ++k)
        if (!(c.glDepth.pixels[k] < kInf)) both.pixels[k] = kInf;
    c.normals = compareNormals(c.cpu.normal, glNormal, both);
    // Where there is no triangle the normal is (0,0,0) on both.
    for (std::size_t k = 0; k < both.size(); ++k)
        if (!(c.glDepth.pixels[k] < kInf)) {
            EXPECT_EQ(glNormal.pixels[k], glm::vec3(0.0f)) << k;
        }
    return c;
}

void expectWithinTolerance(const Comparison& c, const char* what) {
    std::printf("%s: %d covered on the CPU, %d differ in coverage; depth rel max %.3g mean %.3g (%d over %.0e);"
                " normals p99 %.3g max %.3g deg\n",
                what, c.depth.coveredCpu, c.depth.coverageDiffer, c.depth.maxRel, c.depth.meanRel, c.depthOver,
                kDepthRel, c.normals.p99Deg, c.normals.maxDeg);
    EXPECT_LE(c.depth.coverageDiffer, int(kCoverageFraction * c.depth.coveredCpu) + 1) << what;
    EXPECT_LE(c.depthOver, int(kDepthRingFraction * c.depth.coveredCpu)) << what;
    EXPECT_LE(c.depth.maxRel, kDepthRelRing) << what;
    EXPECT_LE(c.normals.p99Deg, kNormalP99Deg) << what;
    EXPECT_LE(c.normals.maxDeg, kNormalMaxDeg) << what;
}

}  // namespace

TEST_F(GlRasterMesh, SphereMatchesCpu) {
    const glm::vec3 centre{0.1f, -0.05f, 0.0f};
    const TriangleMesh mesh = icosphere(centre, 0.5f, 5);
    Camera cam;
    cam.eye = {0.4f, 0.3f, 2.5f};
    cam.width = 321;
    cam.height = 239;
    cam.fovYDegrees = 40.0f;
    const Comparison a = compareWithCpu(cam, mesh, nullptr);
    EXPECT_GT(a.depth.coveredCpu, 5000);
    expectWithinTolerance(a, "sphere");
    // A scene depth cutting through the sphere (a slanted wall): the same fragments discarded.
    Image<float> scene(cam.width, cam.height, kInf);
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) scene.at(x, y) = 2.3f + 0.004f * float(x - cam.width / 2);
    const Comparison b = compareWithCpu(cam, mesh, &scene);
    EXPECT_LT(b.depth.coveredCpu, a.depth.coveredCpu - 1000);
    expectWithinTolerance(b, "sphere behind a scene wall");
}

// Vertices on pixel centres (no rounding difference in the snapping): the two
// fill rules must agree exactly, the shared diagonal and the borders included.
TEST_F(GlRasterMesh, FillRuleMatchesCpuOnPixelCentres) {
    const Camera cam = axisCamera(64, 48, 60.0f, 0.1f);
    auto at = [&](double px, double py) { return atPixel(cam, px, py, 2.0); };
    TriangleMesh m;
    m.positions = {at(10.5, 5.5), at(40.5, 5.5), at(40.5, 35.5), at(10.5, 35.5), at(50.5, 40.5), at(60.5, 45.5)};
    m.normals.assign(m.positions.size(), glm::vec3(0.0f, 0.0f, 1.0f));
    // The quad split along its diagonal, and a thin sliver whose edges pass between centres.
    m.indices = {0, 2, 1, 0, 3, 2, 4, 5, 2};
    const Comparison c = compareWithCpu(cam, m, nullptr);
    std::printf("quad: %d covered, %d differ\n", c.depth.coveredCpu, c.depth.coverageDiffer);
    EXPECT_EQ(c.depth.coverageDiffer, 0);
    EXPECT_GT(c.depth.coveredCpu, 29 * 29);
    EXPECT_EQ(c.depthOver, 0);
}

TEST_F(GlRasterMesh, TriangleCrossingTheNearPlaneMatchesCpu) {
    for (float nearM : {0.1f, 1.5f}) {
        const Camera cam = axisCamera(160, 120, 70.0f, nearM);
        const Comparison c = compareWithCpu(cam, floorTriangle(), nullptr);
        EXPECT_GT(c.depth.coveredCpu, 2000);
        expectWithinTolerance(c, nearM < 1.0f ? "near plane 0.1" : "near plane 1.5");
    }
}

// The whole pipeline with a mesh on both backends: the real frame's particles
// (thickness, raw depth, framing) and two overlapping spheres of mesh in the
// middle of the fluid, partly under the studio's floor.
TEST_F(GlRasterMesh, RendererWithMeshMatchesCpu) {
    const RealFrame& f = realFrame();
    ASSERT_FALSE(f.positions.empty());
    const Bounds box = computeBounds(f.positions);
    const glm::vec3 c = box.center(), e = box.extent();
    TriangleMesh mesh = icosphere(c, 0.35f * e.y, 5);
    const TriangleMesh second = icosphere(c + glm::vec3(0.3f * e.x, -0.3f * e.y, 0.0f), 0.3f * e.y, 4);
    const auto base = std::uint32_t(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), second.positions.begin(), second.positions.end());
    mesh.normals.insert(mesh.normals.end(), second.normals.begin(), second.normals.end());
    for (std::uint32_t i : second.indices) mesh.indices.push_back(base + i);
    RenderSettings s;
    s.radiusM = f.radius;
    s.camera = realFrameCamera(320, 180);
    s.mesh = &mesh;
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    std::vector<StageTime> times;
    auto a = cpu.render(f.positions, s);
    auto b = gl->render(f.positions, s, &times);
    ASSERT_TRUE(a.ok()) << a.error().describe();
    ASSERT_TRUE(b.ok()) << b.error().describe();
    bool rasterised = false;
    for (const auto& t : times) rasterised |= t.stage == "rasterise";
    EXPECT_TRUE(rasterised);
    const DepthDiff z = compareDepth(a->depth, b->depth), raw = compareDepth(a->rawDepth, b->rawDepth);
    EXPECT_GT(z.coveredCpu, 2000);
    EXPECT_LE(z.maxRel, kDepthRelRing);
    EXPECT_LE(z.coverageDiffer, int(kCoverageFraction * z.coveredCpu) + 1);
    EXPECT_LE(raw.maxRel, 1e-5);  // the particles' splat, as in gl_backend_test
    const NormalDiff n = compareNormals(a->normal, b->normal, a->depth);
    EXPECT_LE(n.p99Deg, kNormalP99Deg);
    // Colour: the whole-pipeline tolerance of gl_backend_test (2 steps, 0.1% over 1),
    // plus the pixels whose coverage differs (a silhouette pixel shows fluid on one side only).
    const ColorDiff col = compareColor(a->color, b->color);
    const double allowed = 1e-3 + double(z.coverageDiffer) / double(a->color.size());
    std::printf("renderer: depth rel %.3g, %d of %d covered pixels differ, colour max %d steps, %.3g%% over 1\n",
                z.maxRel, z.coverageDiffer, z.coveredCpu, col.maxSteps, 100.0 * col.fractionOver1);
    EXPECT_LE(col.fractionOver1, allowed);
    if (z.coverageDiffer == 0) {
        EXPECT_LE(col.maxSteps, 2);
    }
}
}  // namespace gl_raster_mesh_test_local
