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

namespace meniscus::shading_test_local {
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

// ---- Refraction (docs/pipeline.md#shading): the refracted view ray.

// The background each fluid pixel shows, recovered from the shaded colour:
// the output is affine in the background per channel (absorption, Fresnel,
// the reflection below the horizon and the highlight do not depend on where
// the background is sampled), so with the scene painted `color`, then black,
// then white (same depths, so the same sample points), S = (C - C0) / (C1 -
// C0). NaN where the pixel is not shaded fluid.
Image<glm::vec3> seenBackground(const Camera& cam, const Image<glm::vec4>& color, const Image<float>& sceneDepth,
                                const Image<float>& depth, const Image<glm::vec3>& normals,
                                const Image<float>& thick, const ShadingParams& p) {
    const int W = cam.width, H = cam.height;
    const cpu::SceneLayer painted{color, sceneDepth};
    const cpu::SceneLayer black{Image<glm::vec4>(W, H, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f)), sceneDepth};
    const cpu::SceneLayer white{Image<glm::vec4>(W, H, glm::vec4(1.0f)), sceneDepth};
    const Image<glm::vec4> c = cpu::shadeAndComposite(cam, painted, depth, normals, thick, p);
    const Image<glm::vec4> c0 = cpu::shadeAndComposite(cam, black, depth, normals, thick, p);
    const Image<glm::vec4> c1 = cpu::shadeAndComposite(cam, white, depth, normals, thick, p);
    Image<glm::vec3> s(W, H, glm::vec3(NAN));
    for (std::size_t i = 0; i < s.size(); ++i)
        if (depth.pixels[i] < sceneDepth.pixels[i])
            s.pixels[i] = (glm::vec3(c.pixels[i]) - glm::vec3(c0.pixels[i])) /
                          (glm::vec3(c1.pixels[i]) - glm::vec3(c0.pixels[i]));
    return s;
}

// A flat slab of liquid of thickness D over the floor y = 0, seen from a
// camera `degrees` from the slab's normal (+y): the inputs built directly.
// The floor's colour encodes its world position (r = 0.5 + 0.1 x, g = 0.5 +
// 0.1 z), its depth is the floor's eye depth; the liquid's depth is the top
// plane's, its normals the plane's, its thickness the chord along each view
// ray down to the floor.
struct Slab {
    Camera cam;
    Image<glm::vec4> floorColor;
    Image<float> floorDepth, depth, thick;
    Image<glm::vec3> normals;
};
constexpr float kSlabD = 0.3f;
Slab flatSlab(float degrees) {
    Slab s;
    const float a = glm::radians(degrees), L = 3.0f;
    s.cam = test::lookAt(glm::vec3(0.0f, L * std::cos(a), L * std::sin(a)), glm::vec3(0.0f), 160, 120);
    s.cam.fovYDegrees = 30.0f;
    const int W = s.cam.width, H = s.cam.height;
    s.floorColor = Image<glm::vec4>(W, H);
    s.floorDepth = s.depth = s.thick = Image<float>(W, H, kInf);
    const glm::vec3 up = glm::vec3(0.0f, 1.0f, 0.0f);
    s.normals = Image<glm::vec3>(W, H, glm::vec3(glm::dot(up, s.cam.right()), glm::dot(up, s.cam.trueUp()),
                                                 glm::dot(up, s.cam.back())));
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const glm::vec3 r = s.cam.dirToWorld(s.cam.pixelRay(float(x) + 0.5f, float(y) + 0.5f));  // eye depth 1
            const float tTop = (kSlabD - s.cam.eye.y) / r.y, tFloor = -s.cam.eye.y / r.y;
            const glm::vec3 f = s.cam.eye + tFloor * r;
            s.floorColor.at(x, y) = glm::vec4(0.5f + 0.1f * f.x, 0.5f + 0.1f * f.z, 0.5f, 1.0f);
            s.floorDepth.at(x, y) = tFloor;
            s.depth.at(x, y) = tTop;
            s.thick.at(x, y) = (tFloor - tTop) * glm::length(r);
        }
    return s;
}

// Snell's law, computed here: the view ray through pixel centre (x, y) enters
// the slab's top at P with incidence theta_i from the normal, goes on at
// sin(theta_t) = sin(theta_i) / ior in the plane of incidence and meets the
// floor at P + (D / cos(theta_t)) t. Returns that floor point (double).
glm::dvec3 snellFloorHit(const Camera& cam, int x, int y, double ior) {
    const glm::dvec3 eye(cam.eye);
    const glm::dvec3 r(cam.dirToWorld(cam.pixelRay(float(x) + 0.5f, float(y) + 0.5f)));
    const glm::dvec3 P = eye + ((double(kSlabD) - eye.y) / r.y) * r;
    const glm::dvec3 i = glm::normalize(r);
    const double sinI = std::sqrt(i.x * i.x + i.z * i.z), sinT = sinI / ior, cosT = std::sqrt(1.0 - sinT * sinT);
    const glm::dvec2 across = glm::dvec2(i.x, i.z) / sinI;  // horizontal direction of the plane of incidence
    const glm::dvec3 t(sinT * across.x, -cosT, sinT * across.y);
    return P + (double(kSlabD) / cosT) * t;
}

glm::vec2 projectWorld(const Camera& cam, const glm::dvec3& w) { return cam.projectView(cam.toView(glm::vec3(w))); }

// A flat slab over a floor seen at 30 and at 60 degrees from its normal: every
// floor point seen (decoded from the colour) is within 1 px of where Snell's
// law puts it (both projected onto the image). The refracted floor lies well
// away from the point straight behind (> 5 px at 60 degrees), so the test sees
// the refraction.
TEST(Shading, RefractionFollowsSnellsLawThroughAFlatSlab) {
    for (const float degrees : {30.0f, 60.0f}) {
        const Slab s = flatSlab(degrees);
        ShadingParams p;
        p.material.refraction = 1.0f;
        p.material.ior = 1.33f;
        const Image<glm::vec3> seen =
            seenBackground(s.cam, s.floorColor, s.floorDepth, s.depth, s.normals, s.thick, p);
        const int W = s.cam.width, H = s.cam.height;
        double worst = 0.0, shift = 0.0;
        int checked = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const glm::vec2 want = projectWorld(s.cam, snellFloorHit(s.cam, x, y, p.material.ior));
                if (want.x < 2.0f || want.y < 2.0f || want.x > float(W) - 2.0f || want.y > float(H) - 2.0f) continue;
                const glm::vec3 c = seen.at(x, y);
                ASSERT_TRUE(std::isfinite(c.r) && std::isfinite(c.g)) << x << "," << y;
                const glm::dvec3 floor((double(c.r) - 0.5) / 0.1, 0.0, (double(c.g) - 0.5) / 0.1);
                const glm::vec2 got = projectWorld(s.cam, floor);
                worst = std::max(worst, double(glm::length(got - want)));
                shift = std::max(shift, double(glm::length(want - glm::vec2(float(x) + 0.5f, float(y) + 0.5f))));
                ++checked;
            }
        std::printf("%.0f degrees: %d pixels, worst %.3f px from Snell's law, refraction shift up to %.1f px\n",
                    double(degrees), checked, worst, shift);
        EXPECT_GT(checked, W * H * 3 / 4) << degrees;
        EXPECT_LE(worst, 1.0) << degrees;
        EXPECT_GT(shift, degrees > 45.0f ? 5.0 : 2.0) << degrees;
    }
}

// No streaks: a block of liquid at rest (the box |x| <= 0.5, |z| <= 0.5, 0
// <= y <= 0.6) seen through its flat front face, 25 degrees off its normal
// and from a little above, against a wall (z = -2) whose colour encodes its
// position. Where the view ray leaves the block through the parallel back
// face (a parallel-sided slab), the wall seen is displaced (in pixels, from
// the point straight behind) smoothly over the whole face: its second
// differences are at most 0.15 px (the march's refinement), nothing like the
// streaks or starburst of an offset that follows the thickness. The
// displacement is the slab's: within 1.5 px of the parallel shift Snell's law
// gives through front and back faces, computed here (the model puts the back
// at the eye depth where the view ray leaves, not on the tilted back face:
// measured 0.96 px), and a real one (> 3 px,
// toward +x: the camera is off to +x and the ray bends toward the normal).
TEST(Shading, RefractionThroughAFlatFaceHasNoStreaks) {
    const int W = 160, H = 120;
    const float a = glm::radians(25.0f);
    Camera cam = test::lookAt(glm::vec3(4.0f * std::sin(a), 0.9f, 4.0f * std::cos(a)), glm::vec3(0.0f, 0.3f, 0.0f),
                              W, H);
    cam.fovYDegrees = 12.0f;
    const glm::vec3 n(0.0f, 0.0f, 1.0f);
    const glm::vec3 nView(glm::dot(n, cam.right()), glm::dot(n, cam.trueUp()), glm::dot(n, cam.back()));
    Image<glm::vec4> wallColor(W, H);
    Image<float> wallDepth(W, H), depth(W, H, kInf), thick(W, H, kInf);
    Image<unsigned char> slab(W, H, 0);  // the ray leaves through the back face
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const glm::vec3 r = cam.dirToWorld(cam.pixelRay(float(x) + 0.5f, float(y) + 0.5f));
            const float tWall = (-2.0f - cam.eye.z) / r.z;
            const glm::vec3 w = cam.eye + tWall * r;
            wallColor.at(x, y) = glm::vec4(0.5f + 0.1f * w.x, 0.5f + 0.1f * w.y, 0.5f, 1.0f);
            wallDepth.at(x, y) = tWall;
            const float tFront = (0.5f - cam.eye.z) / r.z;
            const glm::vec3 f = cam.eye + tFront * r;
            if (std::abs(f.x) > 0.5f || f.y < 0.0f || f.y > 0.6f) continue;
            // Where the ray leaves the box: the nearest of the back and side faces, top and bottom.
            float tOut = (-0.5f - cam.eye.z) / r.z;
            for (const float t : {(0.5f - cam.eye.x) / r.x, (-0.5f - cam.eye.x) / r.x, (0.0f - cam.eye.y) / r.y,
                                  (0.6f - cam.eye.y) / r.y})
                if (t > tFront) tOut = std::min(tOut, t);
            depth.at(x, y) = tFront;
            thick.at(x, y) = (tOut - tFront) * glm::length(r);
            slab.at(x, y) = tOut == (-0.5f - cam.eye.z) / r.z;
        }
    ShadingParams p;
    p.material.refraction = 1.0f;
    const Image<glm::vec3> seen =
        seenBackground(cam, wallColor, wallDepth, depth, Image<glm::vec3>(W, H, nView), thick, p);
    // Displacement of the wall point seen from the one straight behind, pixels;
    // the worst distance from the slab's analytic shift.
    Image<glm::vec2> disp(W, H, glm::vec2(NAN));
    float worstSnell = 0.0f;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            if (!slab.at(x, y)) continue;
            const glm::vec3 c = seen.at(x, y);
            const glm::vec3 w((c.r - 0.5f) / 0.1f, (c.g - 0.5f) / 0.1f, -2.0f);
            const glm::vec2 got = cam.projectView(cam.toView(w));
            disp.at(x, y) = got - glm::vec2(float(x) + 0.5f, float(y) + 0.5f);
            // Snell's law through the front face (normal +z), out through the
            // back face parallel to the view ray, on to the wall.
            const glm::dvec3 i = glm::normalize(glm::dvec3(cam.dirToWorld(cam.pixelRay(float(x) + 0.5f, float(y) + 0.5f))));
            const glm::dvec3 e(cam.eye);
            const glm::dvec3 front = e + ((0.5 - e.z) / i.z) * i;
            const double sinI = std::sqrt(i.x * i.x + i.y * i.y), sinT = sinI / double(p.material.ior);
            const glm::dvec2 across = glm::dvec2(i.x, i.y) / sinI;
            const glm::dvec3 t(sinT * across.x, sinT * across.y, -std::sqrt(1.0 - sinT * sinT));
            const glm::dvec3 back = front + (-1.0 / t.z) * t;
            const glm::dvec3 wall = back + ((-2.0 - back.z) / i.z) * i;
            worstSnell = std::max(worstSnell, glm::length(got - projectWorld(cam, wall)));
        }
    glm::vec2 lo(1e9f), hi(-1e9f);
    float worstSecond = 0.0f;
    int inside = 0;
    for (int y = 1; y < H - 1; ++y)
        for (int x = 1; x < W - 1; ++x) {
            const glm::vec2 d = disp.at(x, y);
            if (!(d.x == d.x)) continue;
            lo = glm::min(lo, d);
            hi = glm::max(hi, d);
            ++inside;
            const glm::vec2 l = disp.at(x - 1, y), r = disp.at(x + 1, y), u = disp.at(x, y - 1), b = disp.at(x, y + 1);
            if (l.x == l.x && r.x == r.x) worstSecond = std::max(worstSecond, glm::length(l - 2.0f * d + r));
            if (u.x == u.x && b.x == b.x) worstSecond = std::max(worstSecond, glm::length(u - 2.0f * d + b));
        }
    std::printf("flat face: %d pixels, displacement x %.2f..%.2f y %.2f..%.2f px, worst second difference %.3f px, "
                "worst %.3f px from the slab's Snell shift\n",
                inside, double(lo.x), double(hi.x), double(lo.y), double(hi.y), double(worstSecond),
                double(worstSnell));
    ASSERT_GT(inside, 1000);
    EXPECT_LE(worstSecond, 0.15f);
    EXPECT_LE(worstSnell, 1.5f);
    EXPECT_GT(lo.x, 3.0f);
}

// Refraction strength 0: the background straight behind, whatever the
// normal and the thickness (1e-5 on a ramp scene); strength 1 over the same
// inputs is a real shift (more than 1 px).
TEST(Shading, RefractionStrengthZeroSeesStraightBehind) {
    const int W = 80, H = 60;
    const Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, W, H);
    Image<glm::vec4> ramp(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) ramp.at(x, y) = glm::vec4(0.01f * float(x), 0.01f * float(y), 0.5f, 1.0f);
    const Image<float> sceneDepth(W, H, 3.0f), depth(W, H, 2.0f), thick(W, H, 0.5f);
    const Image<glm::vec3> nrm(W, H, glm::normalize(glm::vec3(0.3f, 0.4f, 0.9f)));
    ShadingParams p;
    p.material.refraction = 0.0f;
    const Image<glm::vec3> still = seenBackground(cam, ramp, sceneDepth, depth, nrm, thick, p);
    p.material.refraction = 1.0f;
    const Image<glm::vec3> bent = seenBackground(cam, ramp, sceneDepth, depth, nrm, thick, p);
    float maxShift = 0.0f;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            ASSERT_NEAR(still.at(x, y).r, 0.01f * float(x), 1e-5f) << x << "," << y;
            ASSERT_NEAR(still.at(x, y).g, 0.01f * float(y), 1e-5f) << x << "," << y;
            maxShift = std::max(maxShift, 100.0f * glm::length(glm::vec2(bent.at(x, y) - still.at(x, y))));
        }
    EXPECT_GT(maxShift, 1.0f);
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
}  // namespace meniscus::shading_test_local
