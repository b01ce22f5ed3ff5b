// GL scene stage (docs/pipeline.md#scene, src/gl/scene.cpp) against the CPU reference
// cpu::castScene: the studio of the real frame, a synthetic box seen from all
// four sides and from above and near the horizon (far fade, sky), the
// floor-only studio of a moving camera, the background switched off, the light direction (planes' lighting, the sun). Skips only when no headless GL 4.3 context can be
// created at all.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/scene.h"
#include "gl/scene.h"
#include "gl/uniforms.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "gl_test_util.h"
#include "test_util.h"

namespace gl_scene_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlScene : public GlTest {};

// Tolerances (same arithmetic in the same order on both sides, `precise` in the
// shader; the sky formula is the same source, src/shared/sky.h):
//  - colour: 0 8-bit sRGB steps, and |gl - cpu| <= 1e-5 in linear units (an
//    ulp or two of division/sqrt rounding on llvmpipe, amplified at most by the
//    sun glow's s^64);
//  - depth: relative 1e-6 where both hit a plane;
//  - hit / sky coverage: a pixel may differ only where its ray grazes a plane's
//    edge (the wall top, the corner): at most 0.01% of the pixels, plus 2.
constexpr int kColorSteps = 0;
constexpr double kColorAbs = 1e-5;
constexpr double kDepthRel = 1e-6;
constexpr double kCoverageFraction = 1e-4;

struct SceneDiff {
    DepthDiff depth;
    ColorDiff color;
    double maxAbs = 0.0;  // max |gl - cpu| of any colour channel, linear
};

// Runs both backends for (camera, studio) and compares.
SceneDiff compareScene(const Camera& cam, const shared::Studio& studio, cpu::SceneLayer* cpuOut = nullptr,
                       Image<glm::vec4>* glColorOut = nullptr, Image<float>* glDepthOut = nullptr) {
    SceneDiff d;
    auto caster = gl::SceneCaster::create();
    EXPECT_TRUE(caster.ok()) << caster.error().describe();
    if (!caster) return d;
    const gl::FrameParams p = gl::packFrameParams(cam, 0.01f, FilterParams{}, ThicknessParams{}, ShadingParams{});
    gl::FrameParamsBlock block;
    block.upload(p);
    gl::GpuImage color, depth;
    caster->run(p, studio, color, depth);
    const Image<glm::vec4> glColor = color.download<glm::vec4>();
    const Image<float> glDepth = depth.download<float>();
    const cpu::SceneLayer ref = cpu::castScene(cam, studio);
    d.depth = compareDepth(ref.depth, glDepth);
    d.color = compareColor(ref.color, glColor);
    for (std::size_t k = 0; k < ref.color.size() && k < glColor.size(); ++k)
        for (int c = 0; c < 4; ++c)
            d.maxAbs = std::max(d.maxAbs, double(std::abs(ref.color.pixels[k][c] - glColor.pixels[k][c])));
    if (cpuOut) *cpuOut = ref;
    if (glColorOut) *glColorOut = glColor;
    if (glDepthOut) *glDepthOut = glDepth;
    return d;
}

void expectWithinTolerance(const SceneDiff& d, int pixels, const char* what) {
    std::printf("%s: %d of %d pixels hit a plane, %d hit/sky differences, depth max rel %.3g, colour max %d steps"
                " (max abs %.3g)\n",
                what, d.depth.coveredCpu, pixels, d.depth.coverageDiffer, d.depth.maxRel, d.color.maxSteps, d.maxAbs);
    EXPECT_LE(d.depth.coverageDiffer, int(kCoverageFraction * pixels) + 2) << what;
    EXPECT_LE(d.depth.maxRel, kDepthRel) << what;
    EXPECT_LE(d.color.maxSteps, kColorSteps) << what;
    EXPECT_LE(d.maxAbs, kColorAbs) << what;
}



// A camera at azimuth/elevation (degrees) around the box centre, at `dist`.
Camera orbitCamera(const Bounds& box, float azimuthDeg, float elevationDeg, float dist, int w, int h) {
    Camera c;
    const float az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
    c.target = box.center();
    c.eye = c.target + dist * glm::vec3(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
    c.width = w;
    c.height = h;
    c.fovYDegrees = 50.0f;
    c.nearM = 0.01f;
    return c;
}

}  // namespace

TEST_F(GlScene, RealFrameStudioMatchesCpu) {
    const RealFrame& f = realFrame();
    ASSERT_FALSE(f.positions.empty());
    const Camera cam = realFrameCamera(320, 180);
    const shared::Studio studio =
        shared::makeStudio(computeBounds(f.positions), f.radius, cam, SceneParams{}, ShadingParams{}.lightDirWorld);
    const SceneDiff d = compareScene(cam, studio);
    EXPECT_GT(d.depth.coveredCpu, 320 * 180 / 4);  // the studio fills much of the frame
    expectWithinTolerance(d, 320 * 180, "real frame studio");
}

TEST_F(GlScene, EverySideAndHeightMatchesCpu) {
    // A 1 m x 0.5 m x 0.8 m box: the walls flip sides with the camera (both
    // normal signs), a high camera sees mostly floor, a low one the far fade
    // into the sky and sky above the walls; an odd image size checks the
    // column/row bounds of the dispatch.
    Bounds box;
    box.extend({-0.5f, 0.0f, -0.4f});
    box.extend({0.5f, 0.5f, 0.4f});
    const float r = 0.05f;
    const float azimuths[] = {35.0f, 125.0f, 215.0f, 305.0f};
    const float elevations[] = {2.0f, 25.0f, 70.0f};
    for (float az : azimuths)
        for (float el : elevations) {
            const Camera cam = orbitCamera(box, az, el, 3.0f, 203, 117);
            const shared::Studio studio = shared::makeStudio(box, r, cam, SceneParams{}, ShadingParams{}.lightDirWorld);
            char what[64];
            std::snprintf(what, sizeof what, "azimuth %.0f elevation %.0f", az, el);
            const SceneDiff d = compareScene(cam, studio);
            expectWithinTolerance(d, cam.width * cam.height, what);
            EXPECT_GT(d.depth.coveredCpu, 0) << what;
        }
}

TEST_F(GlScene, FloorOnlyStudioMatchesCpu) {
    // The floor-only studio of a moving camera (SceneParams::walls = false):
    // from every side, high and low (the radial far fade, sky where the walls
    // would stand), and the real frame's camera; it must differ from the walled
    // studio, so the GL side really takes the other branch.
    Bounds box;
    box.extend({-0.5f, 0.0f, -0.4f});
    box.extend({0.5f, 0.5f, 0.4f});
    SceneParams floorOnly;
    floorOnly.walls = false;
    for (float az : {35.0f, 125.0f, 215.0f, 305.0f})
        for (float el : {2.0f, 25.0f, 70.0f}) {
            const Camera cam = orbitCamera(box, az, el, 3.0f, 97, 61);
            const shared::Studio studio = shared::makeStudio(box, 0.05f, cam, floorOnly, ShadingParams{}.lightDirWorld);
            char what[64];
            std::snprintf(what, sizeof what, "floor only, azimuth %.0f elevation %.0f", az, el);
            expectWithinTolerance(compareScene(cam, studio), cam.width * cam.height, what);
        }
    const Camera cam = realFrameCamera(160, 90);
    const Bounds real = computeBounds(realFrame().positions);
    Image<glm::vec4> floorColor, walledColor;
    const SceneDiff d = compareScene(
        cam, shared::makeStudio(real, realFrame().radius, cam, floorOnly, ShadingParams{}.lightDirWorld), nullptr,
        &floorColor);
    expectWithinTolerance(d, 160 * 90, "floor only, real frame");
    compareScene(cam, shared::makeStudio(real, realFrame().radius, cam, SceneParams{}, ShadingParams{}.lightDirWorld),
                 nullptr, &walledColor);
    EXPECT_NE(floorColor.pixels, walledColor.pixels);
}

TEST_F(GlScene, FarFloorFadesIntoTheSkyAsOnTheCpu) {
    // Eye just above a big floor looking at the horizon: most floor pixels are
    // beyond the fade start (24 squares), the blend of the checker and the sky.
    Bounds box;
    box.extend({-0.1f, 0.0f, -0.1f});
    box.extend({0.1f, 0.1f, 0.1f});
    Camera cam;
    cam.eye = {3.0f, 0.3f, 3.0f};
    cam.target = {50.0f, 0.2f, 50.0f};  // looking away from the walls, toward the open floor
    cam.width = 256;
    cam.height = 128;
    cam.fovYDegrees = 30.0f;
    shared::Studio studio = shared::makeStudio(box, 0.01f, cam, SceneParams{}, ShadingParams{}.lightDirWorld);
    cpu::SceneLayer ref;
    const SceneDiff d = compareScene(cam, studio, &ref);
    int faded = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x)
            faded += std::isfinite(ref.depth.at(x, y)) &&
                     ref.depth.at(x, y) > 24.0f * studio.checkerM + glm::length(cam.eye);
    EXPECT_GT(faded, 100);  // the fade is really exercised
    expectWithinTolerance(d, cam.width * cam.height, "far fade");
}

TEST_F(GlScene, BackgroundOffIsTransparentAndInfinite) {
    const Camera cam = realFrameCamera(160, 90);
    SceneParams params;
    params.background = false;
    const shared::Studio studio = shared::makeStudio(computeBounds(realFrame().positions), realFrame().radius, cam,
                                                     params, ShadingParams{}.lightDirWorld);
    ASSERT_FALSE(studio.enabled);
    cpu::SceneLayer ref;
    Image<glm::vec4> glColor;
    Image<float> glDepth;
    const SceneDiff d = compareScene(cam, studio, &ref, &glColor, &glDepth);
    ASSERT_EQ(glColor.size(), std::size_t(160 * 90));
    ASSERT_EQ(glDepth.size(), std::size_t(160 * 90));
    for (std::size_t k = 0; k < glColor.size(); ++k) {
        ASSERT_EQ(glColor.pixels[k], glm::vec4(0.0f)) << k;  // exactly the CPU's (0,0,0,0)
        ASSERT_TRUE(std::isinf(glDepth.pixels[k]) && glDepth.pixels[k] > 0.0f) << k;
    }
    EXPECT_EQ(d.depth.coverageDiffer, 0);
    EXPECT_EQ(d.maxAbs, 0.0);
}

TEST_F(GlScene, ReusedAcrossSizesAndStudios) {
    // One caster, the buffers reused: a big frame, then a small one with the
    // background off, then the big one again must give the same as fresh.
    const RealFrame& f = realFrame();
    auto caster = gl::SceneCaster::create();
    ASSERT_TRUE(caster.ok()) << caster.error().describe();
    gl::FrameParamsBlock block;
    gl::GpuImage color, depth;
    const Camera big = realFrameCamera(320, 180), small = realFrameCamera(64, 36);
    const shared::Studio on =
        shared::makeStudio(computeBounds(f.positions), f.radius, big, SceneParams{}, ShadingParams{}.lightDirWorld);
    shared::Studio off = on;
    off.enabled = false;
    const gl::FrameParams pBig = gl::packFrameParams(big, f.radius, FilterParams{}, ThicknessParams{}, ShadingParams{});
    const gl::FrameParams pSmall =
        gl::packFrameParams(small, f.radius, FilterParams{}, ThicknessParams{}, ShadingParams{});
    block.upload(pBig);
    caster->run(pBig, on, color, depth);
    block.upload(pSmall);
    caster->run(pSmall, off, color, depth);
    EXPECT_EQ(color.width, 64);
    EXPECT_EQ(depth.height, 36);
    block.upload(pBig);
    caster->run(pBig, on, color, depth);
    const cpu::SceneLayer ref = cpu::castScene(big, on);
    const ColorDiff c = compareColor(ref.color, color.download<glm::vec4>());
    const DepthDiff z = compareDepth(ref.depth, depth.download<float>());
    EXPECT_LE(c.maxSteps, kColorSteps);
    EXPECT_LE(z.coverageDiffer, int(kCoverageFraction * 320 * 180) + 2);
    EXPECT_LE(z.maxRel, kDepthRel);
}

TEST_F(GlScene, LightDirectionLightsThePlanesAndPlacesTheSunAsOnTheCpu) {
    // Three lights (straight up, from the side, low behind the walls): the
    // studio seen from the real frame's camera, and the sky seen from high
    // above looking along each light (the sun glow in the middle). Both
    // backends agree for every light and camera; the GL image really changes
    // with the light (the planes' lighting, the sun at the centre).
    const RealFrame& f = realFrame();
    const Bounds box = computeBounds(f.positions);
    const glm::vec3 lights[] = {{0.0f, 1.0f, 0.0f},
                                glm::normalize(glm::vec3(0.8f, 0.5f, 0.3f)),
                                glm::normalize(glm::vec3(-0.3f, 0.2f, -1.0f))};
    auto skyCamera = [&](const glm::vec3& along) {
        Camera c;
        c.eye = box.center() + glm::vec3(0.0f, 50.0f * glm::length(box.extent()), 0.0f);
        c.target = c.eye + along;
        c.up = std::abs(along.y) > 0.9f ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
        c.width = 65;
        c.height = 65;
        return c;
    };
    const Camera studioCam = realFrameCamera(160, 90);
    std::vector<Image<glm::vec4>> studioImages;
    for (int k = 0; k < 3; ++k) {
        char what[64];
        std::snprintf(what, sizeof what, "light %d, studio", k);
        Image<glm::vec4> glColor;
        const shared::Studio studio = shared::makeStudio(box, f.radius, studioCam, SceneParams{}, lights[k]);
        expectWithinTolerance(compareScene(studioCam, studio, nullptr, &glColor), 160 * 90, what);
        studioImages.push_back(glColor);
        // The sky camera looks along light k; the sun is there only for light k.
        const Camera skyCam = skyCamera(lights[k]);
        std::snprintf(what, sizeof what, "light %d, sky", k);
        Image<glm::vec4> own, other;
        expectWithinTolerance(
            compareScene(skyCam, shared::makeStudio(box, f.radius, skyCam, SceneParams{}, lights[k]), nullptr, &own),
            65 * 65, what);
        compareScene(skyCam, shared::makeStudio(box, f.radius, skyCam, SceneParams{}, lights[(k + 1) % 3]), nullptr,
                     &other);
        ASSERT_EQ(own.size(), std::size_t(65 * 65));
        ASSERT_EQ(other.size(), own.size());
        EXPECT_GT(own.at(32, 32).r - other.at(32, 32).r, 0.5f) << what;  // nearly the full glow of 0.6
    }
    for (int k = 1; k < 3; ++k) {
        double maxDiff = 0.0;
        for (std::size_t i = 0; i < studioImages[0].size(); ++i)
            maxDiff = std::max(maxDiff, double(glm::length(studioImages[0].pixels[i] - studioImages[k].pixels[i])));
        EXPECT_GT(maxDiff, 0.1) << "light " << k;
    }
}
}  // namespace gl_scene_test_local
