// Tests of the CPU shading and compositing stage (docs/pipeline.md#shading) and the
// material presets.
#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "cpu/normals.h"
#include "cpu/shading.h"
#include "cpu/sky.h"
#include "cpu/splat.h"
#include "meniscus/io.h"
#include "meniscus/params.h"
#include "meniscus/particles.h"
#include "test_util.h"

namespace meniscus {
namespace {

constexpr float kInf = INFINITY;

// A checkerboard scene layer at a constant depth, opaque.
cpu::SceneLayer checkerScene(int w, int h, float depth) {
    cpu::SceneLayer s{Image<glm::vec4>(w, h), Image<float>(w, h, depth)};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            s.color.at(x, y) = ((x / 4 + y / 4) % 2) ? glm::vec4(0.8f, 0.7f, 0.6f, 1.0f)
                                                     : glm::vec4(0.1f, 0.2f, 0.3f, 1.0f);
    return s;
}

// Unit normals facing the eye along each pixel's view ray.
Image<glm::vec3> facingNormals(const Camera& cam) {
    Image<glm::vec3> n(cam.width, cam.height);
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) n.at(x, y) = -glm::normalize(cam.pixelRay(float(x) + 0.5f, float(y) + 0.5f));
    return n;
}

glm::vec3 viewToWorldDir(const Camera& cam, const glm::vec3& v) { return cam.dirToWorld(v); }

bool bitEqual(const Image<glm::vec4>& a, const Image<glm::vec4>& b) {
    return a.size() == b.size() && std::memcmp(a.pixels.data(), b.pixels.data(), a.size() * sizeof(glm::vec4)) == 0;
}

// No fluid anywhere: the output is the scene colour, bit for bit, alpha included.
TEST(Shading, NoFluidGivesTheSceneExactly) {
    const Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, 40, 30);
    cpu::SceneLayer scene = checkerScene(40, 30, 5.0f);
    scene.color.at(3, 3) = glm::vec4(0.2f, 0.4f, 0.6f, 0.0f);  // a transparent pixel keeps its alpha
    scene.depth.at(3, 3) = kInf;
    const Image<float> depth(40, 30, kInf);
    const Image<glm::vec4> out =
        cpu::shadeAndComposite(cam, scene, depth, Image<glm::vec3>(40, 30), Image<float>(40, 30), ShadingParams{});
    EXPECT_TRUE(bitEqual(out, scene.color));
}

// Fluid at or behind the scene depth is hidden: scene colour, bit for bit.
TEST(Shading, FluidBehindTheSceneIsHidden) {
    const Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, 40, 30);
    const cpu::SceneLayer scene = checkerScene(40, 30, 5.0f);
    Image<float> depth(40, 30, 6.0f);
    for (int x = 0; x < 40; ++x) depth.at(x, 7) = 5.0f;  // exactly at the scene: hidden too
    const Image<glm::vec4> out = cpu::shadeAndComposite(cam, scene, depth, facingNormals(cam),
                                                        Image<float>(40, 30, 0.3f), ShadingParams{});
    EXPECT_TRUE(bitEqual(out, scene.color));
}

// Very thick fluid absorbs the background completely: with F0 = 0 (ior 1), no
// highlight and normals facing the eye (F = 0), the output is the fluid colour
// (1e-6), alpha 1.
TEST(Shading, ThickFluidShowsTheFluidColour) {
    const Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, 40, 30);
    const cpu::SceneLayer scene = checkerScene(40, 30, 5.0f);
    ShadingParams p;
    p.material.ior = 1.0f;
    p.material.specular = 0.0f;
    const Image<glm::vec4> out = cpu::shadeAndComposite(cam, scene, Image<float>(40, 30, 2.0f), facingNormals(cam),
                                                        Image<float>(40, 30, 1000.0f), p);
    for (const glm::vec4& c : out.pixels) {
        ASSERT_NEAR(c.r, p.material.fluidColor.r, 1e-6f);
        ASSERT_NEAR(c.g, p.material.fluidColor.g, 1e-6f);
        ASSERT_NEAR(c.b, p.material.fluidColor.b, 1e-6f);
        ASSERT_EQ(c.a, 1.0f);
    }
}

// Beer-Lambert absorption (eq. 18) uses a polynomial exp (relative error
// < 2e-7, see shading.cpp): with F = 0 (ior 1, normals facing the eye), no
// highlight and no refraction offset, every pixel is C + (S - C) exp(-k T),
// checked against double exp over thicknesses 0..0.6 m (down to exp(-3.6)) and
// one very thick pixel, tolerance 1e-6 absolute (colours <= 1).
TEST(Shading, BeerLambertMatchesExp) {
    const int W = 64, H = 32;
    const Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, W, H);
    cpu::SceneLayer scene{Image<glm::vec4>(W, H, glm::vec4(0.9f, 0.6f, 0.3f, 1.0f)), Image<float>(W, H, 10.0f)};
    ShadingParams p;
    p.material.ior = 1.0f;
    p.material.specular = 0.0f;
    p.material.refraction = 0.0f;
    Image<float> thick(W, H);
    for (int i = 0; i < W * H; ++i) thick.pixels[std::size_t(i)] = 0.6f * float(i) / float(W * H - 1);
    thick.pixels[5] = 50.0f;
    const Image<glm::vec4> out =
        cpu::shadeAndComposite(cam, scene, Image<float>(W, H, 2.0f), facingNormals(cam), thick, p);
    for (int i = 0; i < W * H; ++i)
        for (int c = 0; c < 3; ++c) {
            const double C = p.material.fluidColor[c], S = scene.color.pixels[std::size_t(i)][c];
            const double e = C + (S - C) * std::exp(-double(p.material.absorptionPerM[c]) * thick.pixels[std::size_t(i)]);
            ASSERT_NEAR(out.pixels[std::size_t(i)][c], e, 1e-6) << i << " channel " << c;
        }
}

// Schlick at normal incidence is F0 = ((ior-1)/(ior+1))^2 = 0.0200593... for
// water (1e-6), and 1 at grazing incidence.
TEST(Shading, SchlickFresnel) {
    const double q = (1.33 - 1.0) / (1.33 + 1.0);
    EXPECT_NEAR(cpu::schlickFresnel(cpu::fresnelF0(1.33f), 1.0f), q * q, 1e-6);
    EXPECT_NEAR(cpu::fresnelF0(1.33f), 0.0200593, 1e-6);
    EXPECT_NEAR(cpu::schlickFresnel(cpu::fresnelF0(1.33f), 0.0f), 1.0, 1e-6);
    EXPECT_NEAR(cpu::schlickFresnel(0.04f, 0.5f), 0.04 + 0.96 / 32.0, 1e-6);
}

// Zero thickness, normals facing the eye: no refraction offset and no
// absorption, so C = S (1 - F0) + F0 * sky(reflect) + k_s (n.h)^shininess with
// the reflection straight back along the view ray. Expected value computed
// here independently (double for the blend), tolerance 1e-5.
TEST(Shading, ZeroThicknessFacingTheCamera) {
    Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, 40, 30);
    cam.eye = glm::vec3(1.0f, 0.8f, 2.0f);  // a general view: the light is not along the axis
    const cpu::SceneLayer scene = checkerScene(40, 30, 5.0f);
    ShadingParams p;
    p.lightDirWorld = glm::normalize(cam.eye - cam.target + glm::vec3(0.3f, 0.2f, 0.0f));  // light near the eye: visible highlight
    const Image<glm::vec3> n = facingNormals(cam);
    const Image<glm::vec4> out =
        cpu::shadeAndComposite(cam, scene, Image<float>(40, 30, 2.0f), n, Image<float>(40, 30, 0.0f), p);
    const double f0 = std::pow((1.33 - 1.0) / (1.33 + 1.0), 2.0);
    const glm::vec3 lView = glm::normalize(glm::vec3(glm::dot(p.lightDirWorld, cam.right()),
                                                     glm::dot(p.lightDirWorld, cam.trueUp()),
                                                     glm::dot(p.lightDirWorld, cam.back())));
    double maxSpec = 0.0;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            const glm::vec3 v = n.at(x, y);
            const glm::vec3 b = cpu::skyColor(viewToWorldDir(cam, v), shared::sunDirection(p.lightDirWorld));
            double spec = 0.0;
            if (glm::dot(v, lView) > 0.0f)
                spec = p.material.specular * std::pow(double(glm::dot(v, glm::normalize(lView + v))),
                                                      double(p.material.shininess));
            maxSpec = std::max(maxSpec, spec);
            for (int c = 0; c < 3; ++c) {
                const double e = scene.color.at(x, y)[c] * (1.0 - f0) + f0 * b[c] + spec;
                ASSERT_NEAR(out.at(x, y)[c], e, 1e-5) << x << "," << y << " channel " << c;
            }
            ASSERT_EQ(out.at(x, y).a, 1.0f);
        }
    EXPECT_GT(maxSpec, 0.01);  // the highlight term was really exercised
}

// Refraction: with a scene colour that is a ramp (red = 0.01 * column, green =
// 0.01 * row) and a uniform tilted normal, the background is sampled
// beta = refraction * T * f / z pixels along (n.x, -n.y) (row 0 is the top):
// red = 0.01 (x + beta n.x), green = 0.01 (y - beta n.y). No absorption; the
// Fresnel blend with the sky is undone with the same formula. 1e-5.
TEST(Shading, RefractionOffsetFollowsTheNormal) {
    const int W = 80, H = 60;
    const Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, W, H);
    cpu::SceneLayer scene{Image<glm::vec4>(W, H), Image<float>(W, H, 10.0f)};
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) scene.color.at(x, y) = glm::vec4(0.01f * float(x), 0.01f * float(y), 0.5f, 1.0f);
    ShadingParams p;
    p.material.absorptionPerM = glm::vec3(0.0f);
    p.material.specular = 0.0f;
    p.material.refraction = 0.6f;
    const glm::vec3 nrm = glm::normalize(glm::vec3(0.3f, 0.4f, 0.9f));
    const float z = 2.0f, T = 0.3f;
    const float beta = p.material.refraction * T * cam.focalPx() / z;  // ~7.4 px
    ASSERT_GT(beta * nrm.y, 1.5f);  // a real shift of more than a pixel
    const Image<glm::vec4> out = cpu::shadeAndComposite(cam, scene, Image<float>(W, H, z),
                                                        Image<glm::vec3>(W, H, nrm), Image<float>(W, H, T), p);
    const float f0 = cpu::fresnelF0(p.material.ior);
    for (int y = 10; y < H - 10; ++y)
        for (int x = 10; x < W - 10; ++x) {
            const glm::vec3 v = -glm::normalize(cam.pixelRay(float(x) + 0.5f, float(y) + 0.5f));
            const float nv = glm::dot(nrm, v);
            const float F = cpu::schlickFresnel(f0, nv);
            const glm::vec3 b =
                cpu::skyColor(cam.dirToWorld(2.0f * nv * nrm - v), shared::sunDirection(p.lightDirWorld));
            const glm::vec3 s = (glm::vec3(out.at(x, y)) - F * b) / (1.0f - F);
            ASSERT_NEAR(s.r, 0.01f * (float(x) + beta * nrm.x), 1e-5f) << x << "," << y;
            ASSERT_NEAR(s.g, 0.01f * (float(y) - beta * nrm.y), 1e-5f) << x << "," << y;
        }
}

// The sky's sun follows the light (both what a transparent background lets
// through and what the fluid reflects): with the light along the view
// direction, the sky seen through zero-thickness fluid carries the sun glow
// (0.6); with the light behind the camera, the reflection carries it, weighted
// by Fresnel F0 only. Each pixel matches the formula with
// skyColor(dir, sunDirection(light)), 1e-5; the centre changes by > 0.4.
TEST(Shading, SkySunFollowsTheLight) {
    const int W = 41, H = 31;
    Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, W, H);
    cam.eye = glm::vec3(0.5f, 1.5f, 2.0f);
    const cpu::SceneLayer clear{Image<glm::vec4>(W, H, glm::vec4(0.0f)), Image<float>(W, H, kInf)};
    const Image<glm::vec3> n = facingNormals(cam);
    const Image<float> depth(W, H, 2.0f), thick(W, H, 0.0f);
    const glm::vec3 viewDir = glm::normalize(cam.target - cam.eye);
    const float f0 = cpu::fresnelF0(ShadingParams{}.material.ior);
    float centre[2];
    for (int k = 0; k < 2; ++k) {
        ShadingParams p;
        p.material.specular = 0.0f;  // the sky alone
        p.lightDirWorld = k == 0 ? viewDir : -viewDir;
        const glm::vec3 sun = shared::sunDirection(p.lightDirWorld);
        const Image<glm::vec4> out = cpu::shadeAndComposite(cam, clear, depth, n, thick, p);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const glm::vec3 ray = cam.dirToWorld(cam.pixelRay(float(x) + 0.5f, float(y) + 0.5f));
                // Facing normals: no refraction offset, the reflection straight back.
                const glm::vec3 want = cpu::skyColor(ray, sun) * (1.0f - f0) + cpu::skyColor(-ray, sun) * f0;
                for (int c = 0; c < 3; ++c) ASSERT_NEAR(out.at(x, y)[c], want[c], 1e-5f) << x << "," << y;
            }
        centre[k] = out.at(W / 2, H / 2).r;
    }
    EXPECT_GT(centre[0] - centre[1], 0.4f);
}

// Below the horizon the liquid mirrors what it shows through itself, not the
// sky's brown ground (with the ground, grazing crests drew brown lines): a face turned
// down and grazing (n.v about 0.31, F about 0.17) so that reflect(-v, n) points
// well below the horizon (world y about -0.59, no sun glow) shows
// a = C_fluid + (S - C_fluid) exp(-k T) whatever its Fresnel weight, 1e-5. The
// sky's ground there would differ by more than 0.02.
TEST(Shading, BelowTheHorizonTheLiquidMirrorsWhatItShowsThrough) {
    const int W = 40, H = 30;
    const Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, W, H, 10.0f);  // narrow: all rays alike
    const glm::vec4 sceneColor(0.5f, 0.6f, 0.7f, 1.0f);
    const cpu::SceneLayer scene{Image<glm::vec4>(W, H, sceneColor), Image<float>(W, H, 10.0f)};
    ShadingParams p;
    p.material.specular = 0.0f;
    const glm::vec3 nrm = glm::normalize(glm::vec3(0.0f, -0.95f, 0.31f));
    const float T = 0.1f;
    const Image<glm::vec4> out = cpu::shadeAndComposite(cam, scene, Image<float>(W, H, 2.0f),
                                                        Image<glm::vec3>(W, H, nrm), Image<float>(W, H, T), p);
    const Material& m = p.material;
    const glm::vec3 a = m.fluidColor + (glm::vec3(sceneColor) - m.fluidColor) * glm::exp(-m.absorptionPerM * T);
    const glm::vec3 sun = shared::sunDirection(p.lightDirWorld);
    const float f0 = cpu::fresnelF0(m.ior);
    float worstGround = 1.0f;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            for (int c = 0; c < 3; ++c) ASSERT_NEAR(out.at(x, y)[c], a[c], 1e-5f) << x << "," << y;
            const glm::vec3 v = -glm::normalize(cam.pixelRay(float(x) + 0.5f, float(y) + 0.5f));
            const glm::vec3 e = cam.dirToWorld(2.0f * glm::dot(nrm, v) * nrm - v);
            ASSERT_LT(e.y / glm::length(e), -0.5f);  // past the ground blend (-0.25)
            const float F = cpu::schlickFresnel(f0, glm::dot(nrm, v));
            const glm::vec3 ground = a * (1.0f - F) + cpu::skyColor(e, sun) * F;
            worstGround = std::min(worstGround, glm::length(ground - a));
        }
    EXPECT_GT(worstGround, 0.02f);
}

// A transparent scene (alpha 0, colour garbage) refracts the sky along the view
// ray: the result equals that of an opaque scene painted with exactly that sky
// (1e-6).
TEST(Shading, TransparentSceneRefractsTheSky) {
    const int W = 40, H = 30;
    Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, W, H);
    cam.eye = glm::vec3(0.5f, 1.5f, 2.0f);
    cpu::SceneLayer clear{Image<glm::vec4>(W, H, glm::vec4(1.0f, 0.0f, 1.0f, 0.0f)), Image<float>(W, H, kInf)};
    cpu::SceneLayer painted{Image<glm::vec4>(W, H), Image<float>(W, H, kInf)};
    const glm::vec3 sun = shared::sunDirection(ShadingParams{}.lightDirWorld);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            painted.color.at(x, y) =
                glm::vec4(cpu::skyColor(cam.dirToWorld(cam.pixelRay(float(x) + 0.5f, float(y) + 0.5f)), sun), 1.0f);
    const Image<glm::vec3> n = facingNormals(cam);
    const Image<float> depth(W, H, 2.0f), thick(W, H, 0.0f);
    const Image<glm::vec4> a = cpu::shadeAndComposite(cam, clear, depth, n, thick, ShadingParams{});
    const Image<glm::vec4> b = cpu::shadeAndComposite(cam, painted, depth, n, thick, ShadingParams{});
    for (std::size_t i = 0; i < a.size(); ++i)
        for (int c = 0; c < 4; ++c) ASSERT_NEAR(a.pixels[i][c], b.pixels[i][c], 1e-6f) << i;
}

// An opaque material (sand, opacity 1) hides the background completely: two
// different scenes give the same fluid pixels, bit for bit.
TEST(Shading, OpaqueMaterialIgnoresTheBackground) {
    const Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, 40, 30);
    ShadingParams p;
    ASSERT_TRUE(materialPreset("sand", &p.material));
    cpu::SceneLayer s1 = checkerScene(40, 30, 5.0f), s2 = checkerScene(40, 30, 5.0f);
    for (auto& c : s2.color.pixels) c = glm::vec4(1.0f) - c;
    const Image<float> depth(40, 30, 2.0f), thick(40, 30, 0.01f);
    const Image<glm::vec3> n = facingNormals(cam);
    EXPECT_TRUE(bitEqual(cpu::shadeAndComposite(cam, s1, depth, n, thick, p),
                         cpu::shadeAndComposite(cam, s2, depth, n, thick, p)));
}

TEST(Materials, PresetsParseAndUnknownFails) {
    for (const char* name : {"water", "murky", "milk", "lava", "sand"}) {
        Material m;
        m.name = "?";
        ASSERT_TRUE(materialPreset(name, &m)) << name;
        EXPECT_EQ(m.name, name);
        EXPECT_NE(materialPresetNames().find(name), std::string::npos) << name;
        EXPECT_GE(m.opacity, 0.0f);
        EXPECT_LE(m.opacity, 1.0f);
        EXPECT_GT(m.ior, 1.0f);
    }
    // water is exactly the Material{} defaults
    Material w, d;
    ASSERT_TRUE(materialPreset("water", &w));
    EXPECT_EQ(w.fluidColor, d.fluidColor);
    EXPECT_EQ(w.absorptionPerM, d.absorptionPerM);
    EXPECT_EQ(w.ior, d.ior);
    EXPECT_EQ(w.refraction, d.refraction);
    EXPECT_EQ(w.specular, d.specular);
    EXPECT_EQ(w.shininess, d.shininess);
    EXPECT_EQ(w.opacity, d.opacity);
    // unknown names fail and leave the output alone
    Material m;
    m.name = "keep";
    EXPECT_FALSE(materialPreset("mercury", &m));
    EXPECT_FALSE(materialPreset("", &m));
    EXPECT_FALSE(materialPreset("Water ", &m));
    EXPECT_EQ(m.name, "keep");
    // sand is opaque, water is not
    Material sand;
    ASSERT_TRUE(materialPreset("sand", &sand));
    EXPECT_EQ(sand.opacity, 1.0f);
    EXPECT_EQ(w.opacity, 0.0f);
}

// A realistic input: a splatted block of particles, its normals, a constant
// thickness, a checker scene partly in front of the fluid.
struct Realistic {
    Camera cam;
    cpu::SceneLayer scene;
    Image<float> depth, thick;
    Image<glm::vec3> normals;
};
Realistic realistic() {
    Realistic r;
    r.cam = test::faceOnCamera(glm::vec3(0.05f, 0.1f, 0.0f), 1.2f, 160, 120);
    r.cam.eye += glm::vec3(0.4f, 0.3f, 0.0f);
    const float spacing = 0.02f, radius = 0.01f;
    const auto pts = test::jitteredBlock({30, 20, 10}, spacing, 0.3f, glm::vec3(-0.3f, -0.2f, -0.1f));
    r.scene = checkerScene(160, 120, 1.3f);
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 20; ++x) r.scene.depth.at(x, y) = 0.5f;  // a post in front of the fluid
    r.depth = cpu::splatDepth(r.cam, pts, radius);
    r.normals = cpu::computeNormals(r.depth, r.cam, radius, defaults::kDepthJumpRadii);
    r.thick = Image<float>(160, 120, 0.15f);
    return r;
}

TEST(Shading, BitIdenticalForAnyThreadCount) {
    const Realistic r = realistic();
    for (const char* mat : {"water", "milk"}) {
        ShadingParams p;
        ASSERT_TRUE(materialPreset(mat, &p.material));
        Image<glm::vec4> one;
        {
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
            one = cpu::shadeAndComposite(r.cam, r.scene, r.depth, r.normals, r.thick, p);
        }
        int fluid = 0;
        for (std::size_t i = 0; i < r.depth.size(); ++i) fluid += r.depth.pixels[i] < r.scene.depth.pixels[i];
        EXPECT_GT(fluid, 2500);
        for (int threads : {2, 3, 8}) {
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
            EXPECT_TRUE(bitEqual(one, cpu::shadeAndComposite(r.cam, r.scene, r.depth, r.normals, r.thick, p)));
        }
    }
}

}  // namespace
}  // namespace meniscus
