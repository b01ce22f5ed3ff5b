// The whole pipeline on the GL backend against the CPU reference, through the
// public Renderer: every filter, the real frame, background on and off, every
// AOV. Skips only when no GL 4.3 context can be created at all.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <cstdlib>

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

#include "shared/thickness.h"
#include "gl_test_util.h"
#include "meniscus/environment.h"
#include "meniscus/geometry.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "gl/raster_mesh.h"
#include "render/stages.h"
#include "test_util.h"

namespace gl_backend_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlBackend : public GlTest {};

// Tolerances of the whole pipeline, GL vs CPU:
//  - depth (raw and smoothed): relative 1e-5; every depth stage is bit-identical
//    on llvmpipe, the margin is for drivers that round sqrt/division otherwise;
//  - coverage: no pixel may have fluid on one side only beyond 0.05% (grazing rays);
//  - thickness: 1e-4 of max(T, one calibrated diameter) (fixed-point chord sums);
//  - normals: 0.01 degrees at the 99th percentile (they follow the depth);
//  - colour: at most 2 8-bit sRGB steps anywhere, and at most 0.1% of pixels off
//    by more than 1 (exp/log of the driver vs the CPU's polynomials, thickness).
// With `ownEllipsoids` (the GL backend made the ellipsoids on the GPU,
// gl/anisotropy.h: float against the CPU's double, tests/gl_anisotropy_test.cpp)
// the inputs differ by rounding: the depth as there (1e-5 on all but 0.5% of
// the pixels, none beyond 5e-3), the thickness 1e-3, the normals 0.05
// degrees (measured on the real frame: 1.7e-4 and 0.02 degrees).
void expectSame(const Aovs& cpu, const Aovs& gl, float r, bool ownEllipsoids = false) {
    const DepthDiff raw = compareDepth(cpu.rawDepth, gl.rawDepth), z = compareDepth(cpu.depth, gl.depth);
    if (ownEllipsoids) {
        expectDepthNearlySame(cpu.rawDepth, gl.rawDepth, 1e-5, 5e-3, 5e-3);
        expectDepthNearlySame(cpu.depth, gl.depth, 1e-5, 5e-3, 5e-3);
    } else {
        EXPECT_LE(raw.maxRel, 1e-5);
        EXPECT_LE(z.maxRel, 1e-5);
    }
    EXPECT_LE(raw.coverageDiffer, int(5e-4 * raw.coveredCpu) + 2);
    EXPECT_LE(z.coverageDiffer, int(5e-4 * z.coveredCpu) + 2);
    const double diameter = 2.0 * r * shared::thicknessWeight(r, ThicknessParams{});
    const ScalarDiff t = compareScalar(cpu.thickness, gl.thickness, diameter);
    EXPECT_LE(t.maxRel, ownEllipsoids ? 1e-3 : 1e-4);
    const NormalDiff n = compareNormals(cpu.normal, gl.normal, cpu.depth);
    EXPECT_LE(n.p99Deg, ownEllipsoids ? 0.05 : 0.01);
    const ColorDiff c = compareColor(cpu.color, gl.color);
    EXPECT_LE(c.maxSteps, 2);
    EXPECT_LE(c.fractionOver1, 1e-3);
    std::printf("  depth rel %.2g (raw %.2g), thickness rel %.2g, normals p99 %.3g deg, colour max %d steps\n",
                z.maxRel, raw.maxRel, t.maxRel, n.p99Deg, c.maxSteps);
}

struct Frame {
    std::vector<glm::vec3> positions;
    RenderSettings settings;
};

// The real frame with the default settings at 320x180.
Frame realFrameSettings() {
    Frame f;
    f.positions = realFrame().positions;
    f.settings.radiusM = realFrame().radius;
    f.settings.camera = realFrameCamera(320, 180);
    return f;
}

}  // namespace

TEST_F(GlBackend, EveryFilterMatchesCpuOnTheRealFrame) {
    Frame f = realFrameSettings();
    ASSERT_FALSE(f.positions.empty());
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    EXPECT_EQ(gl->backendName().rfind("gl (", 0), 0u) << gl->backendName();
    Renderer cpu;
    for (const std::string name : {"none", "gaussian", "bilateral", "binomial", "curvature-flow", "narrow-range"}) {
        for (bool separable : {false, true}) {
            if (separable && name != "narrow-range") continue;
            ASSERT_TRUE(filterFromName(name, &f.settings.filter));
            if (separable) std::get<NarrowRangeParams>(f.settings.filter).separable = true;
            SCOPED_TRACE(name + (separable ? " (separable)" : ""));
            std::printf("%s%s\n", name.c_str(), separable ? " (separable)" : "");
            auto a = cpu.render(f.positions, f.settings);
            auto b = gl->render(f.positions, f.settings);
            ASSERT_TRUE(a.ok() && b.ok());
            expectSame(*a, *b, f.settings.radiusM);
        }
    }
}

TEST_F(GlBackend, MaterialsBackgroundAndViewsMatchCpu) {
    Frame f = realFrameSettings();
    ASSERT_FALSE(f.positions.empty());
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    ASSERT_TRUE(materialPreset("lava", &f.settings.shading.material));
    f.settings.scene.background = false;
    for (View v : {View::Final, View::Normals, View::Thickness}) {
        f.settings.view = v;
        auto a = cpu.render(f.positions, f.settings);
        auto b = gl->render(f.positions, f.settings);
        ASSERT_TRUE(a.ok() && b.ok());
        expectSame(*a, *b, f.settings.radiusM);
    }
}

// A backdrop (docs/compositing.md) composited on GL as on the CPU: a set of
// stripes at two depths, one in front of part of the liquid and one behind
// it, with "nothing" (a renderer's background) between them.
TEST_F(GlBackend, BackdropMatchesCpu) {
    Frame f = realFrameSettings();
    ASSERT_FALSE(f.positions.empty());
    const int W = f.settings.camera.width, H = f.settings.camera.height;
    Renderer cpu;
    auto plain = cpu.render(f.positions, f.settings);
    ASSERT_TRUE(plain.ok());
    float nearest = INFINITY, farthest = 0.0f;
    for (float z : plain->rawDepth.pixels)
        if (std::isfinite(z)) nearest = std::min(nearest, z), farthest = std::max(farthest, z);
    ASSERT_LT(nearest, farthest);
    std::vector<float> rgb, depth;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int stripe = (x / 16) % 3;
            rgb.insert(rgb.end(), {0.2f + 0.3f * float(stripe), 0.5f, 0.9f - 0.2f * float(y) / float(H)});
            // Ray distances, so the conversion runs too.
            const float z = stripe == 0 ? 0.5f * (nearest + farthest) : stripe == 1 ? 2.0f * farthest : INFINITY;
            depth.push_back(z * glm::length(f.settings.camera.pixelRay(x + 0.5f, y + 0.5f)));
        }
    auto backdrop = makeBackdrop(W, H, rgb, 3, depth, *parseBackdropDepth("ray"));
    ASSERT_TRUE(backdrop.ok());
    f.settings.scene.backdrop = std::make_shared<const BackdropImage>(std::move(*backdrop));
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    auto a = cpu.render(f.positions, f.settings);
    auto b = gl->render(f.positions, f.settings);
    ASSERT_TRUE(a.ok() && b.ok());
    expectSame(*a, *b, f.settings.radiusM);
    EXPECT_GT(differingBits(a->color, plain->color), W * H / 2);  // the backdrop is in the picture
}

// colorOnly reads back only what the view pictures; the colour is the same.
TEST_F(GlBackend, ColorOnlyMatchesCpuForEveryView) {
    Frame f = realFrameSettings();
    ASSERT_FALSE(f.positions.empty());
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    f.settings.colorOnly = true;
    for (View v : {View::Final, View::Depth, View::RawDepth, View::Normals, View::Thickness}) {
        f.settings.view = v;
        auto a = cpu.render(f.positions, f.settings);
        auto b = gl->render(f.positions, f.settings);
        ASSERT_TRUE(a.ok() && b.ok());
        EXPECT_TRUE(b->depth.empty() && b->rawDepth.empty() && b->normal.empty() && b->thickness.empty());
        ASSERT_FALSE(b->color.empty());
        const ColorDiff c = compareColor(a->color, b->color);  // the whole-pipeline colour tolerance above
        EXPECT_LE(c.maxSteps, 2) << int(v);
        EXPECT_LE(c.fractionOver1, 1e-3) << int(v);
    }
}

// Thickness at 1/2 and 1/4 resolution through the whole pipeline.
TEST_F(GlBackend, LowResolutionThicknessMatchesCpu) {
    Frame f = realFrameSettings();
    ASSERT_FALSE(f.positions.empty());
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    for (int divisor : {2, 4}) {
        f.settings.thickness.resolutionDivisor = divisor;
        auto a = cpu.render(f.positions, f.settings);
        auto b = gl->render(f.positions, f.settings);
        ASSERT_TRUE(a.ok() && b.ok());
        expectSame(*a, *b, f.settings.radiusM);
    }
}

// Anisotropic kernels through the whole pipeline: full resolution, the
// fluid at half resolution, and two fluids (each its own ellipsoids); the
// particles' own radii, as spheres and as ellipsoids.
TEST_F(GlBackend, AnisotropicKernelsMatchCpu) {
    Frame f = realFrameSettings();
    ASSERT_FALSE(f.positions.empty());
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    f.settings.anisotropy.enabled = true;
    setenv("MENISCUS_GL_HOST_ANISOTROPY", "0", 1);  // the GL backend's own ellipsoids (GlTest's SetUp restores)
    std::vector<std::int64_t> fluid(f.positions.size());
    std::vector<float> radii(f.positions.size());
    for (std::size_t i = 0; i < fluid.size(); ++i) {
        fluid[i] = f.positions[i].x < 0.5f ? 0 : 1;
        radii[i] = f.settings.radiusM * (0.8f + 0.4f * float(i % 7) / 6.0f);
    }
    // 0: ellipsoids; 1: at half resolution; 2: two fluids; 3: own radii, spheres; 4: own radii, ellipsoids.
    for (int variant = 0; variant < 5; ++variant) {
        SCOPED_TRACE(variant);
        ParticleView view(f.positions);
        f.settings.fluidScale = variant == 1 ? 0.5f : 1.0f;
        f.settings.anisotropy.enabled = variant != 3;
        if (variant == 2) view.fluid = StridedView<std::int64_t>(std::span<const std::int64_t>(fluid));
        if (variant >= 3) view.radius = StridedView<float>(std::span<const float>(radii));
        auto a = cpu.render(view, f.settings);
        auto b = gl->render(view, f.settings);
        ASSERT_TRUE(a.ok()) << a.error().describe();
        ASSERT_TRUE(b.ok()) << b.error().describe();
        // One fluid with anisotropy: the GL backend's own ellipsoids.
        expectSame(*a, *b, f.settings.radiusM, f.settings.anisotropy.enabled && variant != 2);
    }
}

TEST_F(GlBackend, SequenceReusesTheSceneAndCameraChangesRecastIt) {
    Frame f = realFrameSettings();
    ASSERT_FALSE(f.positions.empty());
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    f.settings.filter = CurvatureFlowParams{};
    f.settings.anisotropy.enabled = false;  // (its host line is not a backend stage)
    for (int k = 0; k < 3; ++k) {
        if (k == 2) f.settings.camera.eye += glm::vec3(0.2f, 0.1f, 0.0f);  // a new camera: the scene is cast again
        std::vector<StageTime> times;
        auto a = cpu.render(f.positions, f.settings);
        auto b = gl->render(f.positions, f.settings, &times);
        ASSERT_TRUE(a.ok() && b.ok());
        expectSame(*a, *b, f.settings.radiusM);
        ASSERT_EQ(times.size(), 7u);  // six stages + readback
        EXPECT_EQ(times[0].stage, "scene");
        EXPECT_EQ(times[2].stage, "fill-holes");
        EXPECT_EQ(times[5].stage, "shade");
        EXPECT_EQ(times[6].stage, "readback");
    }
}

// A GL stage that fails (here a real GL error, made by the backend's fault
// injection) gives an error naming the stage, in release builds too, and no
// image; the next frame renders again.
TEST_F(GlBackend, AFailingStageIsAnErrorNamingIt) {
    const Frame f = realFrameSettings();
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    for (const char* stage : {"scene", "smooth", "shade"}) {
        setenv("MENISCUS_GL_FAIL_STAGE", stage, 1);
        auto failed = gl->render(f.positions, f.settings);
        unsetenv("MENISCUS_GL_FAIL_STAGE");
        ASSERT_FALSE(failed.ok()) << stage;
        const std::string why = failed.error().describe();
        EXPECT_NE(why.find(std::string("GL stage '") + stage + "'"), std::string::npos) << why;
        EXPECT_NE(why.find("GL_INVALID_ENUM"), std::string::npos) << why;
        auto again = gl->render(f.positions, f.settings);
        EXPECT_TRUE(again.ok()) << stage << ": " << (again ? "" : again.error().describe());
    }
}

TEST_F(GlBackend, ReusedRendererRecastsTheSceneWhenTheLightChanges) {
    // The GL backend caches the scene per camera and studio; a new light must
    // recast it: each frame of one GL renderer matches a CPU render of the
    // same settings (a stale scene would keep the first light's planes).
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    RenderSettings s;
    s.camera = realFrameCamera(160, 90);
    s.radiusM = realFrame().radius;
    s.colorOnly = true;
    std::vector<Image<glm::vec4>> images;
    for (const glm::vec3& light : {ShadingParams{}.lightDirWorld, glm::normalize(glm::vec3(0.9f, 0.3f, -0.4f))}) {
        s.shading.lightDirWorld = light;
        auto a = Renderer().render(realFrame().positions, s);
        auto b = gl->render(realFrame().positions, s);
        ASSERT_TRUE(a.ok() && b.ok());
        EXPECT_LE(compareColor(a->color, b->color).maxSteps, 2);
        images.push_back(b->color);
    }
    double maxDiff = 0.0;
    for (std::size_t k = 0; k < images[0].size(); ++k)
        maxDiff = std::max(maxDiff, double(glm::length(images[0].pixels[k] - images[1].pixels[k])));
    EXPECT_GT(maxDiff, 0.1);  // the light really changed the picture
}

TEST_F(GlBackend, NoParticlesGivesTheSceneAsOnTheCpu) {
    RenderSettings s;
    s.radiusM = 0.05f;
    s.camera = faceOnCamera({0.0f, 0.0f, 0.0f}, 2.0f, 96, 64);
    s.scene.studioBounds.extend({-0.5f, -0.5f, -0.5f});
    s.scene.studioBounds.extend({0.5f, 0.5f, 0.5f});
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    auto a = Renderer().render({}, s);
    auto b = gl->render({}, s);
    ASSERT_TRUE(a.ok() && b.ok());
    expectSame(*a, *b, s.radiusM);
}

// The geometry the scene-geometry tests share, around the liquid's bounds: a
// cut-away tank, a rough ball in front of the liquid and a glass box through
// it (its back faces in the scene layer, its front faces over the liquid).
static std::shared_ptr<SceneGeometry> tankBallAndGlass(const Bounds& box) {
    const glm::vec3 c = box.center(), e = box.extent();
    auto g = std::make_shared<SceneGeometry>();
    GeometryObject tank;
    tank.name = "tank";
    tank.mesh = makeBoxMesh(box.min - 0.05f * e, box.max + glm::vec3(0.05f, 0.3f, 0.05f) * e);
    tank.cutaway = true;
    g->objects.push_back(tank);
    GeometryObject ball;
    ball.name = "ball";
    ball.mesh = makeSphereMesh(c + glm::vec3(0.0f, 0.0f, 0.45f * e.z), 0.12f * e.y);
    ball.material.baseColor = {0.7f, 0.2f, 0.1f};
    ball.material.roughness = 0.8f;
    g->objects.push_back(ball);
    GeometryObject glass;
    glass.name = "glass";
    glass.mesh = makeBoxMesh(c - glm::vec3(0.2f, 0.3f, 0.3f) * e, c + glm::vec3(0.3f, 0.2f, 0.3f) * e);
    glass.material.glass = true;
    g->objects.push_back(glass);
    return g;
}

// Scene geometry (docs/geometry.md): the real frame inside a cut-away tank,
// a rough sphere in front of it, a polished metal box behind it, a glass
// box around part of it and a textured wall behind it all; every
// AOV within the pipeline's tolerances, the geometry's own pixels among the
// colours (the mesh path's rasteriser on both sides, the shared shading
// formula). The same renderer again (the studio's cache under the geometry)
// and after the geometry is taken away.
TEST_F(GlBackend, SceneGeometryMatchesCpu) {
    Frame f = realFrameSettings();
    ASSERT_FALSE(f.positions.empty());
    Bounds box;
    for (const glm::vec3& p : f.positions) box.extend(p);
    const glm::vec3 c = box.center(), e = box.extent();
    auto g = tankBallAndGlass(box);
    g->objects[2].material.tint = {0.5f, 0.9f, 0.8f};
    GeometryObject metal;
    metal.name = "metal";
    metal.mesh = makeBoxMesh(c - glm::vec3(0.3f, 0.2f, 0.2f) * e, c - glm::vec3(0.1f, 0.0f, 0.0f) * e);
    metal.material.metalness = 1.0f;
    metal.material.roughness = 0.15f;
    metal.material.baseColor = {0.9f, 0.8f, 0.5f};
    g->objects.push_back(metal);
    // A textured quad (tests/data/geometry: the checker's four colours) as a
    // wall behind the liquid, its map repeated twice across it.
    auto quad = readGeometryMesh(testData("geometry/textured_quad.obj"));
    ASSERT_TRUE(quad.ok()) << quad.error().describe();
    transformMesh(quad->mesh, glm::translate(glm::mat4(1.0f), glm::vec3(box.min.x, box.min.y, box.min.z - 0.02f * e.z)) *
                                  glm::rotate(glm::mat4(1.0f), glm::radians(-90.0f), glm::vec3(1.0f, 0.0f, 0.0f)) *
                                  glm::scale(glm::mat4(1.0f), glm::vec3(e.x, 1.0f, e.y)));
    for (glm::vec2& uv : quad->uvs) uv *= 2.0f;
    g->objects.push_back(*quad);
    f.settings.geometry = g;
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    for (int k = 0; k < 3; ++k) {
        if (k == 2) f.settings.geometry = nullptr;
        auto a = cpu.render(f.positions, f.settings);
        auto b = gl->render(f.positions, f.settings);
        ASSERT_TRUE(a.ok() && b.ok());
        expectSame(*a, *b, f.settings.radiusM);
    }
}

// The scene geometry's meshes stay on the GPU while the geometry is the same
// object (gl/geometry.cpp, gl/shadow.cpp; docs/performance.md#scene-geometry):
// a second frame with the same geometry and camera uploads nothing and draws
// the same picture; a camera move uploads only the indices of the faces the
// cut-away tank shows from the new eye (the ball's faces are all drawn, the
// shadow casters are seen from the light), a turned light only the casters'
// indices from its new eye; another geometry object is
// uploaded and drawn where the CPU draws it. Every frame within the
// pipeline's tolerances of the CPU's.
TEST_F(GlBackend, SceneGeometryStaysOnTheGpu) {
    Frame f = realFrameSettings();
    ASSERT_FALSE(f.positions.empty());
    Bounds box;
    for (const glm::vec3& p : f.positions) box.extend(p);
    const glm::vec3 c = box.center(), e = box.extent();
    auto g = tankBallAndGlass(box);
    const GeometryObject &tank = g->objects[0], &ball = g->objects[1], &glass = g->objects[2];
    std::size_t vertexBytes = 0;
    for (const GeometryObject& o : g->objects) vertexBytes += 2 * o.mesh.positions.size() * sizeof(glm::vec3);
    f.settings.geometry = g;
    f.settings.shadows = ShadowMode::On;
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    auto frame = [&](const char* what, std::uint64_t* uploaded) {
        SCOPED_TRACE(what);
        const std::uint64_t before = gl::meshUploadBytes();
        auto b = gl->render(f.positions, f.settings);
        *uploaded = gl::meshUploadBytes() - before;
        auto a = cpu.render(f.positions, f.settings);
        EXPECT_TRUE(a.ok() && b.ok());
        if (a.ok() && b.ok()) expectSame(*a, *b, f.settings.radiusM);
        std::printf("%s: %llu bytes of meshes uploaded\n", what, static_cast<unsigned long long>(*uploaded));
        return b.ok() ? b->color : Image<glm::vec4>{};
    };
    std::uint64_t first = 0, second = 0, moved = 0, other = 0;
    const Image<glm::vec4> a = frame("first frame", &first);
    EXPECT_GE(first, vertexBytes);  // every object's vertices and normals (and the casters')
    const Image<glm::vec4> b = frame("the same geometry again", &second);
    EXPECT_EQ(second, 0u);
    EXPECT_EQ(differingBits(a, b), 0);
    f.settings.camera.eye += 0.02f * glm::length(e) * f.settings.camera.right();
    const Image<glm::vec4> m = frame("the camera moved", &moved);
    EXPECT_GT(moved, 0u);  // the tank's and the glass's faces seen from the new eye
    EXPECT_LE(moved, (tank.mesh.indices.size() + 2 * glass.mesh.indices.size()) * sizeof(std::uint32_t));
    // The light turned: the shadow casters seen from the light's new eye,
    // only their indices sent (the tank's and the ball's, the glass casts none).
    f.settings.shading.lightDirWorld = glm::normalize(glm::vec3(0.3f, 1.0f, 0.4f));
    std::uint64_t lit = 0;
    frame("the light turned", &lit);
    EXPECT_GT(lit, 0u);
    EXPECT_LE(lit, (tank.mesh.indices.size() + ball.mesh.indices.size()) * sizeof(std::uint32_t));
    // Another geometry object (the ball moved): uploaded, and drawn where it
    // now is (as the CPU draws it, expectSame), then kept again.
    auto shifted = std::make_shared<SceneGeometry>(*g);
    shifted->objects[1].mesh = makeSphereMesh(c + glm::vec3(0.25f * e.x, 0.0f, 0.45f * e.z), 0.12f * e.y);
    f.settings.geometry = shifted;
    const Image<glm::vec4> n = frame("another geometry object, the ball moved", &other);
    EXPECT_GE(other, vertexBytes);
    EXPECT_GT(differingBits(m, n), 200);
    std::uint64_t again = 0;
    frame("the new geometry again", &again);
    EXPECT_EQ(again, 0u);
}

// The HDR environment map (docs/pipeline.md#environment-map) in place of the
// sky on both backends: the background of the studio with walls, of the
// floor alone, the transparent background's fill, and the reflections of a
// metal box and a glass box; the map turned and brightened. Its ambient light
// (the irradiance's spherical harmonics) on the studio, the geometry, a
// half-opaque liquid with foam, the spray's drops and under the shadows
// (variant 4).
TEST_F(GlBackend, EnvironmentMapMatchesCpu) {
    Frame f = realFrameSettings();
    ASSERT_FALSE(f.positions.empty());
    auto map = readEnvironmentMap(testData("environment/sky_128x64.exr"));
    ASSERT_TRUE(map.ok()) << map.error().describe();
    f.settings.scene.environment = std::make_shared<const EnvironmentImage>(std::move(*map));
    f.settings.scene.environmentRotationDeg = 30.0f;
    f.settings.scene.environmentIntensity = 1.5f;
    Bounds box;
    for (const glm::vec3& p : f.positions) box.extend(p);
    const glm::vec3 c = box.center(), e = box.extent();
    auto g = std::make_shared<SceneGeometry>();
    GeometryObject metal;
    metal.name = "metal";
    metal.mesh = makeBoxMesh(c - glm::vec3(0.3f, 0.2f, 0.2f) * e, c - glm::vec3(0.1f, 0.0f, 0.0f) * e);
    metal.material.metalness = 1.0f;
    metal.material.roughness = 0.15f;
    g->objects.push_back(metal);
    GeometryObject glass;
    glass.name = "glass";
    glass.mesh = makeBoxMesh(c - glm::vec3(0.2f, 0.3f, 0.3f) * e, c + glm::vec3(0.3f, 0.2f, 0.3f) * e);
    glass.material.glass = true;
    g->objects.push_back(glass);
    GeometryObject ball;  // rough and diffuse: lit mostly by the map's ambient
    ball.name = "ball";
    ball.mesh = makeSphereMesh(c + glm::vec3(0.0f, 0.0f, 0.45f * e.z), 0.12f * e.y);
    ball.material.baseColor = {0.8f, 0.8f, 0.8f};
    ball.material.roughness = 0.9f;
    g->objects.push_back(ball);
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    // 0: the studio; 1: the floor alone; 2: no background; 3: with the geometry;
    // 4: the geometry, shadows, a half-opaque liquid with foam, spray.
    const ShadowMode shadows = f.settings.shadows;
    for (int variant = 0; variant < 5; ++variant) {
        SCOPED_TRACE(variant);
        f.settings.scene.walls = variant != 1;
        f.settings.scene.background = variant != 2;
        f.settings.geometry = variant >= 3 ? g : nullptr;
        f.settings.shadows = variant == 4 ? ShadowMode::On : shadows;
        f.settings.shading.material.opacity = variant == 4 ? 0.5f : 0.0f;
        f.settings.noise.enabled = variant == 4;
        f.settings.spray.enabled = variant == 4;  // drops lit by the map (shared::sprayLight)
        auto a = cpu.render(f.positions, f.settings);
        auto b = gl->render(f.positions, f.settings);
        ASSERT_TRUE(a.ok()) << a.error().describe();
        ASSERT_TRUE(b.ok()) << b.error().describe();
        expectSame(*a, *b, f.settings.radiusM);
    }
}

// Shadows (docs/geometry.md#shadows): the real frame in its SPlisHSPlasH
// tank with a box over the liquid, the key light's maps and the shadows on
// both backends, every AOV within the pipeline's tolerances, the same
// renderers drawing again and after the box moved; the liquid's shadow alone
// (no geometry, shadows on) too.
TEST_F(GlBackend, ShadowsMatchCpu) {
    Frame f = realFrameSettings();
    ASSERT_FALSE(f.positions.empty());
    auto tank = readGeometry(testData("splishsplash_scene/scenes/DamBreakModel.json").string());
    ASSERT_TRUE(tank.ok()) << tank.error().describe();
    auto g = std::make_shared<SceneGeometry>(std::move(*tank));
    Bounds box;
    for (const glm::vec3& p : f.positions) box.extend(p);
    const glm::vec3 c = box.center(), e = box.extent();
    GeometryObject lid;
    lid.name = "box";
    lid.mesh = makeBoxMesh(c + glm::vec3(-0.2f, 0.6f, -0.2f) * e, c + glm::vec3(0.1f, 0.7f, 0.2f) * e);
    g->objects.push_back(lid);
    f.settings.geometry = g;
    f.settings.shadows = ShadowMode::On;
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    // The same renderers again (the casters' depth kept), with the box moved
    // (another geometry object: drawn again), then without geometry.
    auto moved = std::make_shared<SceneGeometry>(*g);
    moved->objects.back().mesh = makeBoxMesh(c + glm::vec3(0.0f, 0.5f, -0.3f) * e, c + glm::vec3(0.3f, 0.6f, 0.1f) * e);
    for (int k = 0; k < 4; ++k) {
        if (k == 2) f.settings.geometry = moved;
        if (k == 3) f.settings.geometry = nullptr;
        std::vector<StageTime> times;
        auto a = cpu.render(f.positions, f.settings, &times);
        auto b = gl->render(f.positions, f.settings);
        ASSERT_TRUE(a.ok() && b.ok());
        bool ran = false;
        for (const StageTime& t : times) ran = ran || t.stage == "shadows";
        EXPECT_TRUE(ran);
        expectSame(*a, *b, f.settings.radiusM);
    }
}

TEST(Backends, NamesParseAndCpuIsTheDefault) {
    BackendChoice c;
    EXPECT_TRUE(backendFromName("cpu", &c) && c == BackendChoice::Cpu);
    EXPECT_TRUE(backendFromName("gl", &c) && c == BackendChoice::Gl);
    EXPECT_TRUE(backendFromName("auto", &c) && c == BackendChoice::Auto);
    EXPECT_FALSE(backendFromName("vulkan", &c));
    EXPECT_EQ(Renderer().backendName(), "cpu");
    std::string note;
    auto cpu = Renderer::create(BackendChoice::Cpu, &note);
    ASSERT_TRUE(cpu.ok());
    EXPECT_EQ(cpu->backendName(), "cpu");
    EXPECT_TRUE(note.empty());
}

// Auto takes the GL backend on a GPU and the CPU backend, with a note naming
// the rasteriser, when the only GL is a software one (llvmpipe on CI), where
// the CPU backend is about twice as fast.
TEST(Backends, AutoPrefersTheCpuOverASoftwareGl) {
    auto gl = Renderer::create(BackendChoice::Gl);
    if (!gl) GTEST_SKIP() << "no GL context: " << gl.error().describe();
    const std::string glName = gl->backendName();
    std::string note;
    auto autoPick = Renderer::create(BackendChoice::Auto, &note);
    ASSERT_TRUE(autoPick);
    if (glName.find("llvmpipe") != std::string::npos || glName.find("softpipe") != std::string::npos) {
        EXPECT_EQ(autoPick->backendName(), "cpu");
        EXPECT_NE(note.find("software rasteriser, " + glName + "; using the CPU backend"), std::string::npos) << note;
    } else {
        EXPECT_EQ(autoPick->backendName(), glName);
        EXPECT_TRUE(note.empty()) << note;
    }
}

// The CLI: --backend gl and --backend cpu write the same picture (PNG bytes
// within 2 steps, as above); a bad name is a usage error naming the choices.
TEST_F(GlBackend, CliBackendsWriteTheSameImage) {
    const auto dir = tempDir();
    const std::string in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo").string();
    std::string out;
    for (const char* b : {"cpu", "gl"}) {
        const std::string cmd = cliPath() + " render " + in + " -o " + (dir / (std::string(b) + ".png")).string() +
                                " --width 160 --height 90 --filter curvature-flow --backend " + b;
        ASSERT_EQ(runCommand(cmd, &out), 0) << out;
    }
    const PngData a = readPng(dir / "cpu.png"), g = readPng(dir / "gl.png");
    ASSERT_EQ(a.bytes.size(), g.bytes.size());
    ASSERT_FALSE(a.bytes.empty());
    int worst = 0;
    for (std::size_t k = 0; k < a.bytes.size(); ++k) worst = std::max(worst, std::abs(int(a.bytes[k]) - int(g.bytes[k])));
    EXPECT_LE(worst, 2);
    EXPECT_NE(runCommand(cliPath() + " render " + in + " -o " + (dir / "x.png").string() + " --backend vulkan", &out), 0);
    EXPECT_NE(out.find("cpu, gl, auto"), std::string::npos) << out;
    EXPECT_FALSE(std::filesystem::exists(dir / "x.png"));
}

// Every stage with a CPU driver has its GL twin's driver, which can make its
// programs on a GL context (the stage list's prepareStages).
TEST(GlStageDrivers, EveryImageStageHasItsGlDriver) {
    for (const StageDecl& s : frameStages()) {
        if (!s.cpu) {
            EXPECT_EQ(s.gl, nullptr) << s.name;
            continue;
        }
        ASSERT_NE(s.gl, nullptr) << s.name << " has a CPU driver and no GL one";
        EXPECT_NE(s.gl->run, nullptr) << s.name;
        EXPECT_NE(s.gl->prepare, nullptr) << s.name << ": its GL programs are made before the first frame";
    }
}
}  // namespace gl_backend_test_local
