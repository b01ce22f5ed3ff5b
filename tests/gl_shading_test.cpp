// GL shading and compositing (docs/pipeline.md#shading, src/gl/shading.cpp)
// against the CPU reference cpu::shadeAndComposite, on the real frame's CPU
// AOVs (scene layer, smoothed depth, normals, thickness) uploaded as the
// inputs: water, lava and every other preset, the background off, foam from a
// surface noise image, white water from a velocity whitening map (with and
// without foam), and the edge cases: no fluid, no scene, fluid hidden behind
// the scene, missing normals / thickness.
// Skips only when no headless GL 4.3 context can be created at all.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/scene.h"
#include "cpu/shading.h"
#include "gl/shading.h"
#include "gl/uniforms.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "gl_test_util.h"
#include "test_util.h"

namespace gl_shading_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlShading : public GlTest {};

constexpr float kInf = std::numeric_limits<float>::infinity();

// Tolerances. The shader runs shadeBatch's operations in the CPU's order,
// `precise`, with the same sky source (src/shared/sky.h) and the same
// refracted-ray march (src/shared/refraction.h: its crossings are decided by
// the same bits on both sides); the one difference is
// exp/log: the driver's built-ins against the CPU's Cephes polynomials (both
// ~1e-7 relative), amplified by the (n.h)^120 highlight (120 ln(n.h)) and by
// absorption's exp(-kT):
//  - colour: at most 1 8-bit sRGB step in any channel, on at most 0.1% of the
//    pixels more than 0 steps (alpha exactly 1 on fluid, the scene's elsewhere);
//  - linear: |gl - cpu| <= 1e-5 per channel on fluid pixels (measured up to
//    5.5e-6 on the real frame; highlights reach ~1, so ~1e-5 relative);
//    non-fluid pixels exactly the scene's (copied, never recomputed).
constexpr int kColorSteps = 1;
constexpr double kFractionOver0 = 1e-3;
constexpr double kLinearAbs = 1e-5;

struct RealAovs {
    Camera camera;
    cpu::SceneLayer scene, sceneOff;
    Aovs aovs;
    float radius = 0.0f;
};

// The real frame's CPU AOVs at w x h (what the GL shading stage will get from
// the earlier GL stages).
RealAovs makeRealAovs(int w, int h) {
    RealAovs out;
    auto set = readParticles(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
    EXPECT_TRUE(set.ok()) << set.error().describe();
    if (!set) return out;
    out.radius = estimateRadius(set->positions).radius;
    Camera base;
    base.width = w;
    base.height = h;
    out.camera = autoFrameCamera(set->positions, out.radius, base);
    RenderSettings s;
    s.camera = out.camera;
    s.radiusM = out.radius;
    auto aovs = renderFrame(set->positions, s);
    EXPECT_TRUE(aovs.ok()) << aovs.error().describe();
    if (aovs) out.aovs = std::move(*aovs);
    const Bounds box = computeBounds(set->positions);
    out.scene = cpu::castScene(
        out.camera, shared::makeStudio(box, out.radius, out.camera, SceneParams{}, ShadingParams{}.lightDirWorld));
    SceneParams off;
    off.background = false;
    out.sceneOff =
        cpu::castScene(out.camera, shared::makeStudio(box, out.radius, out.camera, off, ShadingParams{}.lightDirWorld));
    return out;
}

const RealAovs& real320() {
    static const RealAovs a = makeRealAovs(320, 180);
    return a;
}

struct ShadeDiff {
    ColorDiff color;
    int fluid = 0;              // pixels the CPU shaded (alpha 1 over a transparent scene, or depth in front)
    int over0 = 0;              // pixels with any channel off by >= 1 step
    double maxAbsFluid = 0.0;   // max |gl - cpu| on shaded pixels, linear
    double maxAbsOther = 0.0;   // max |gl - cpu| elsewhere (must be 0: the scene copied)
    Image<glm::vec4> gl;
};

// GL inputs: empty images stay un-uploaded (absent), as the CPU's empty Images.
// With `noise` (and `noiseParams`): foam from that surface noise on both sides;
// with `whitening` (and `whiteningParams`): white water from that map.
ShadeDiff compareWithCpu(const Camera& cam, float r, const cpu::SceneLayer& scene, const Image<float>& depth,
                         const Image<glm::vec3>& normals, const Image<float>& thickness, const ShadingParams& shading,
                         const Image<float>* noise = nullptr, const NoiseParams* noiseParams = nullptr,
                         const Image<float>* whitening = nullptr, const WhiteningParams* whiteningParams = nullptr) {
    ShadeDiff d;
    auto shader = gl::Shading::create();
    EXPECT_TRUE(shader.ok()) << shader.error().describe();
    if (!shader) return d;
    const gl::FrameParams p = gl::packFrameParams(cam, r, FilterParams{}, ThicknessParams{}, shading);
    gl::FrameParamsBlock block;
    block.upload(p);
    gl::GpuImage sc, sd, z, n, t, out, nz, wm;
    if (!scene.color.empty()) sc.upload(scene.color);
    if (!scene.depth.empty()) sd.upload(scene.depth);
    z.upload(depth);
    if (!normals.empty()) n.upload(normals);
    if (!thickness.empty()) t.upload(thickness);
    if (noise) nz.upload(*noise);
    if (whitening) wm.upload(*whitening);
    shader->run(p, sc, sd, z, n, t, out, noise ? &nz : nullptr, noiseParams, whitening ? &wm : nullptr,
                whiteningParams);
    d.gl = out.download<glm::vec4>();
    const Image<glm::vec4> ref = cpu::shadeAndComposite(cam, scene, depth, normals, thickness, shading, noise,
                                                        noiseParams, whitening, whiteningParams, nullptr,
                                                        ThicknessParams{}.minRadii, r);
    d.color = compareColor(ref, d.gl);
    const bool hasScene = scene.depth.width == depth.width && scene.depth.height == depth.height;
    for (std::size_t k = 0; k < ref.size() && k < d.gl.size(); ++k) {
        const float zk = depth.pixels[k];
        const bool fluid = (hasScene ? zk < scene.depth.pixels[k] : zk < kInf) && zk > 0.0f;
        d.fluid += fluid;
        double m = 0.0;
        int steps = 0;
        for (int c = 0; c < 4; ++c) {
            m = std::max(m, double(std::abs(ref.pixels[k][c] - d.gl.pixels[k][c])));
            if (c < 3) steps = std::max(steps, std::abs(srgb8(ref.pixels[k][c]) - srgb8(d.gl.pixels[k][c])));
        }
        d.over0 += steps > 0;
        (fluid ? d.maxAbsFluid : d.maxAbsOther) = std::max(fluid ? d.maxAbsFluid : d.maxAbsOther, m);
    }
    return d;
}

void expectWithinTolerance(const ShadeDiff& d, std::size_t pixels, const std::string& what) {
    std::printf("%s: %d shaded of %zu pixels, colour max %d steps, %d pixels off by >= 1 step, linear max %.3g"
                " (shaded) %.3g (others)\n",
                what.c_str(), d.fluid, pixels, d.color.maxSteps, d.over0, d.maxAbsFluid, d.maxAbsOther);
    EXPECT_LE(d.color.maxSteps, kColorSteps) << what;
    EXPECT_LE(d.over0, int(kFractionOver0 * double(pixels))) << what;
    EXPECT_LE(d.maxAbsFluid, kLinearAbs) << what;
    EXPECT_EQ(d.maxAbsOther, 0.0) << what;
}

ShadingParams preset(const std::string& name) {
    ShadingParams s;
    EXPECT_TRUE(materialPreset(name, &s.material)) << name;
    return s;
}

}  // namespace

TEST_F(GlShading, RealFrameWaterMatchesCpu) {
    const RealAovs& a = real320();
    ASSERT_FALSE(a.aovs.depth.empty());
    const ShadeDiff d =
        compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, a.aovs.normal, a.aovs.thickness, preset("water"));
    EXPECT_GT(d.fluid, 320 * 180 / 10);
    expectWithinTolerance(d, a.aovs.depth.size(), "water");
}

TEST_F(GlShading, RealFrameLavaMatchesCpu) {
    // Opaque: the Lambert-lit fluid colour, faded mirror reflection.
    const RealAovs& a = real320();
    ASSERT_FALSE(a.aovs.depth.empty());
    const ShadingParams lava = preset("lava");
    ASSERT_GT(lava.material.opacity, 0.0f);
    const ShadeDiff d =
        compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, a.aovs.normal, a.aovs.thickness, lava);
    expectWithinTolerance(d, a.aovs.depth.size(), "lava");
}

TEST_F(GlShading, RealFrameEveryPresetAndAnotherLightMatchCpu) {
    const RealAovs& a = real320();
    ASSERT_FALSE(a.aovs.depth.empty());
    for (const char* name : {"murky", "milk", "sand"}) {
        const ShadeDiff d =
            compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, a.aovs.normal, a.aovs.thickness, preset(name));
        expectWithinTolerance(d, a.aovs.depth.size(), name);
    }
    ShadingParams s = preset("water");
    s.lightDirWorld = glm::normalize(glm::vec3(0.7f, 0.4f, -0.2f));  // a light from the side
    s.material.shininess = 30.0f;
    const ShadeDiff d = compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, a.aovs.normal, a.aovs.thickness, s);
    expectWithinTolerance(d, a.aovs.depth.size(), "water, side light, shininess 30");
}

TEST_F(GlShading, RefractedRayMatchesCpu) {
    // The refracted view ray marched to the studio's depth (src/shared/
    // refraction.h) over the real frame: water at Snell's strength, then the
    // liquid four times as thick and the bend doubled (long paths: the most
    // march steps, crossings on the inner segment where the back passes the
    // floor). Each matches the CPU within the tolerances above, and the
    // refraction shows: the image differs from strength 0 by many steps.
    const RealAovs& a = real320();
    ASSERT_FALSE(a.aovs.depth.empty());
    Image<float> thick = a.aovs.thickness;
    for (float& t : thick.pixels) t *= 4.0f;
    ShadingParams s = preset("water");
    ASSERT_EQ(s.material.refraction, 1.0f);
    const ShadeDiff snell =
        compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, a.aovs.normal, a.aovs.thickness, s);
    expectWithinTolerance(snell, a.aovs.depth.size(), "refraction 1");
    s.material.refraction = 2.0f;
    const ShadeDiff strong = compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, a.aovs.normal, thick, s);
    expectWithinTolerance(strong, a.aovs.depth.size(), "refraction 2, 4x thickness");
    s.material.refraction = 0.0f;
    const ShadeDiff none = compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, a.aovs.normal, thick, s);
    expectWithinTolerance(none, a.aovs.depth.size(), "refraction 0, 4x thickness");
    EXPECT_GT(compareColor(none.gl, strong.gl).maxSteps, 20);
}

TEST_F(GlShading, SkySunFollowsTheLightAsOnTheCpu) {
    // A transparent background (the sky refracted and reflected everywhere)
    // under lights from three directions: GL matches the CPU for each, and the
    // GL image changes with the light (its sun is the light's, not a fixed one:
    // with no highlight and a transparent material nothing else depends on it).
    const RealAovs& a = real320();
    ASSERT_FALSE(a.aovs.depth.empty());
    ShadingParams s = preset("water");
    s.material.specular = 0.0f;  // the sky alone changes
    std::vector<Image<glm::vec4>> images;
    for (const glm::vec3& light : {glm::vec3(0.0f, 1.0f, 0.0f), glm::normalize(glm::vec3(0.8f, 0.5f, 0.3f)),
                                   glm::normalize(glm::vec3(-0.3f, 0.2f, -1.0f))}) {
        s.lightDirWorld = light;
        const ShadeDiff d =
            compareWithCpu(a.camera, a.radius, a.sceneOff, a.aovs.depth, a.aovs.normal, a.aovs.thickness, s);
        expectWithinTolerance(d, a.aovs.depth.size(), "background off, another sun");
        images.push_back(d.gl);
    }
    for (std::size_t k = 1; k < images.size(); ++k) {
        ASSERT_EQ(images[k].size(), images[0].size());
        double maxDiff = 0.0;
        for (std::size_t i = 0; i < images[0].size(); ++i)
            maxDiff = std::max(maxDiff, double(glm::length(images[0].pixels[i] - images[k].pixels[i])));
        EXPECT_GT(maxDiff, 1e-3) << "light " << k;  // 0 if the sun ignored the light; measured >= 0.019
    }
}

TEST_F(GlShading, RealFrameBackgroundOffMatchesCpu) {
    // Transparent scene: refraction samples the sky, non-fluid pixels (0,0,0,0).
    const RealAovs& a = real320();
    ASSERT_FALSE(a.aovs.depth.empty());
    for (const char* name : {"water", "lava"}) {
        const ShadeDiff d = compareWithCpu(a.camera, a.radius, a.sceneOff, a.aovs.depth, a.aovs.normal,
                                           a.aovs.thickness, preset(name));
        expectWithinTolerance(d, a.aovs.depth.size(), std::string("background off, ") + name);
        int transparent = 0;
        for (const glm::vec4& c : d.gl.pixels) transparent += c == glm::vec4(0.0f);
        EXPECT_EQ(transparent, int(a.aovs.depth.size()) - d.fluid);
    }
}

TEST_F(GlShading, NoFluidGivesTheSceneExactly) {
    const RealAovs& a = real320();
    ASSERT_FALSE(a.scene.color.empty());
    const Image<float> none(a.camera.width, a.camera.height, kInf);
    const ShadeDiff d =
        compareWithCpu(a.camera, a.radius, a.scene, none, a.aovs.normal, a.aovs.thickness, preset("water"));
    EXPECT_EQ(d.fluid, 0);
    ASSERT_EQ(d.gl.size(), a.scene.color.size());
    for (std::size_t k = 0; k < d.gl.size(); ++k) ASSERT_EQ(d.gl.pixels[k], a.scene.color.pixels[k]) << k;
    // And without any scene: transparent black.
    const ShadeDiff e = compareWithCpu(a.camera, a.radius, cpu::SceneLayer{}, none, {}, {}, preset("water"));
    for (const glm::vec4& c : e.gl.pixels) ASSERT_EQ(c, glm::vec4(0.0f));
}

TEST_F(GlShading, FluidBehindTheSceneIsHidden) {
    // A scene depth nearer than the fluid over the left half: the scene shows
    // there, the fluid on the right; the refraction still samples the whole scene.
    const RealAovs& a = real320();
    ASSERT_FALSE(a.aovs.depth.empty());
    cpu::SceneLayer scene = a.scene;
    for (int y = 0; y < a.camera.height; ++y)
        for (int x = 0; x < a.camera.width / 2; ++x) scene.depth.at(x, y) = 1e-3f;
    const ShadeDiff d =
        compareWithCpu(a.camera, a.radius, scene, a.aovs.depth, a.aovs.normal, a.aovs.thickness, preset("water"));
    expectWithinTolerance(d, a.aovs.depth.size(), "left half hidden");
    for (int y = 0; y < a.camera.height; ++y)
        for (int x = 0; x < a.camera.width / 2; ++x) ASSERT_EQ(d.gl.at(x, y), scene.color.at(x, y));
}

TEST_F(GlShading, NoSceneNoNormalsNoThicknessMatchCpu) {
    // Absent inputs (empty images on the CPU, never-uploaded GpuImages on GL):
    // transparent background with the sky refracted, normals facing the eye,
    // zero thickness.
    const RealAovs& a = real320();
    ASSERT_FALSE(a.aovs.depth.empty());
    const ShadeDiff d = compareWithCpu(a.camera, a.radius, cpu::SceneLayer{}, a.aovs.depth, a.aovs.normal,
                                       a.aovs.thickness, preset("water"));
    expectWithinTolerance(d, a.aovs.depth.size(), "no scene");
    const ShadeDiff e = compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, {}, {}, preset("water"));
    expectWithinTolerance(e, a.aovs.depth.size(), "no normals, no thickness");
}


TEST_F(GlShading, FoamMatchesCpu) {
    // Foam over the shaded fluid (docs/pipeline.md#noise-and-foam) from a
    // synthetic noise image: stripes of |N| from 0 to 0.5, so the cover runs
    // from none to full.
    const RealAovs& a = real320();
    ASSERT_FALSE(a.aovs.depth.empty());
    Image<float> noise(a.camera.width, a.camera.height, 0.0f);
    for (int y = 0; y < noise.height; ++y)
        for (int x = 0; x < noise.width; ++x) noise.at(x, y) = 0.5f * std::sin(0.11f * float(x) + 0.07f * float(y));
    NoiseParams np;
    np.foamColor = {0.9f, 0.85f, 0.8f};
    for (const char* name : {"water", "lava"}) {
        const ShadeDiff d = compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, a.aovs.normal, a.aovs.thickness,
                                           preset(name), &noise, &np);
        expectWithinTolerance(d, a.aovs.depth.size(), std::string("foam, ") + name);
        // The foam shows: the image differs from the one without it.
        const ShadeDiff plain =
            compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, a.aovs.normal, a.aovs.thickness, preset(name));
        EXPECT_GT(compareColor(plain.gl, d.gl).maxSteps, 20) << name;
    }
}

TEST_F(GlShading, WhiteWaterMatchesCpu) {
    // White water over the shaded fluid (docs/pipeline.md#noise-and-foam,
    // Instant Liquids §4) from a synthetic whitening map: stripes from 0 to 1,
    // so the cover runs from none to the full strength; alone and over the foam
    // of FoamMatchesCpu.
    const RealAovs& a = real320();
    ASSERT_FALSE(a.aovs.depth.empty());
    Image<float> map(a.camera.width, a.camera.height, 0.0f), noise = map;
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x) {
            map.at(x, y) = 0.5f + 0.5f * std::sin(0.05f * float(x) - 0.13f * float(y));
            noise.at(x, y) = 0.5f * std::sin(0.11f * float(x) + 0.07f * float(y));
        }
    WhiteningParams wp;
    wp.enabled = true;
    wp.strength = 0.8f;
    wp.color = {0.95f, 0.9f, 0.85f};
    NoiseParams np;
    for (const char* name : {"water", "lava"}) {
        const ShadeDiff d = compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, a.aovs.normal, a.aovs.thickness,
                                           preset(name), nullptr, nullptr, &map, &wp);
        expectWithinTolerance(d, a.aovs.depth.size(), std::string("white water, ") + name);
        const ShadeDiff both = compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, a.aovs.normal,
                                              a.aovs.thickness, preset(name), &noise, &np, &map, &wp);
        expectWithinTolerance(both, a.aovs.depth.size(), std::string("foam and white water, ") + name);
        // The white water shows: the image differs from the one without it.
        const ShadeDiff plain =
            compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, a.aovs.normal, a.aovs.thickness, preset(name));
        EXPECT_GT(compareColor(plain.gl, d.gl).maxSteps, 20) << name;
        // A map of another size counts as absent, on both sides.
        const Image<float> small(8, 8, 1.0f);
        const ShadeDiff none = compareWithCpu(a.camera, a.radius, a.scene, a.aovs.depth, a.aovs.normal,
                                              a.aovs.thickness, preset(name), nullptr, nullptr, &small, &wp);
        expectWithinTolerance(none, a.aovs.depth.size(), std::string("white water of another size, ") + name);
        EXPECT_EQ(compareColor(plain.gl, none.gl).maxSteps, 0) << name;
    }
}
}  // namespace gl_shading_test_local
