// The HDR environment map (docs/pipeline.md#environment-map): the shared
// sampling (src/shared/environment.h) on maps of known texels, the reader's
// errors and bounds, and the CPU pipeline with a map: the background and the
// liquid's reflection take its colours, the default stays the procedural sky.
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/sky.h"
#include "meniscus/environment.h"
#include "meniscus/io.h"
#include "meniscus/options.h"
#include "meniscus/renderer.h"
#include "shared/environment.h"
#include "test_util.h"

using namespace meniscus;
using namespace meniscus::test;

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// The unit direction of map coordinates (u, v) without rotation (the inverse
// of the convention in src/shared/environment.h).
glm::vec3 directionOf(float u, float v) {
    const float phi = (u - 0.5f) * 2.0f * kPi, theta = v * kPi;
    return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

// A W x H map whose texel (i, j) is (i, j, 100 + i + 10 j).
EnvironmentImage indexMap(int w, int h) {
    EnvironmentImage m;
    m.width = w;
    m.height = h;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            m.rgb.push_back(float(i));
            m.rgb.push_back(float(j));
            m.rgb.push_back(100.0f + float(i) + 10.0f * float(j));
        }
    return m;
}

shared::EnvironmentMap view(const EnvironmentImage& m, float rotation = 0.0f, float intensity = 1.0f) {
    shared::EnvironmentMap e;
    e.texels = m.rgb.data();
    e.width = m.width;
    e.height = m.height;
    e.rotation = rotation;
    e.intensity = intensity;
    return e;
}

glm::vec3 sample(const shared::EnvironmentMap& e, glm::vec3 d) {
    return shared::environmentMapRadiance(d.x, d.y, d.z, e);
}

}  // namespace

TEST(EnvironmentMap, Atan2MatchesTheLibrary) {
    for (int k = 0; k < 720; ++k) {
        const float a = float(k) * kPi / 360.0f - kPi;
        for (float r : {0.001f, 1.0f, 30.0f})
            EXPECT_NEAR(shared::environmentAtan2(r * std::sin(a), r * std::cos(a)),
                        std::atan2(r * std::sin(a), r * std::cos(a)), 2e-5f)
                << a;
    }
    EXPECT_EQ(shared::environmentAtan2(0.0f, 0.0f), 0.0f);
}

TEST(EnvironmentMap, TexelCentresGiveTheirTexels) {
    const EnvironmentImage m = indexMap(8, 4);
    const shared::EnvironmentMap e = view(m);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 8; ++i) {
            const glm::vec3 c = sample(e, directionOf((float(i) + 0.5f) / 8.0f, (float(j) + 0.5f) / 4.0f));
            EXPECT_NEAR(c.x, float(i), 1e-3f) << i << "," << j;
            EXPECT_NEAR(c.y, float(j), 1e-3f) << i << "," << j;
        }
    // Not unit: the same texel.
    const glm::vec3 d = 7.0f * directionOf(2.5f / 8.0f, 1.5f / 4.0f);
    EXPECT_NEAR(sample(e, d).x, 2.0f, 1e-3f);
    // The zenith and the nadir: the first and last rows (clamped in v).
    EXPECT_NEAR(sample(e, {0.0f, 1.0f, 0.0f}).y, 0.0f, 1e-6f);
    EXPECT_NEAR(sample(e, {0.0f, -1.0f, 0.0f}).y, 3.0f, 1e-6f);
    // Intensity multiplies.
    EXPECT_NEAR(sample(view(m, 0.0f, 2.0f), directionOf(2.5f / 8.0f, 1.5f / 4.0f)).z, 2.0f * 112.0f, 1e-2f);
}

TEST(EnvironmentMap, TheSeamWrapsAndIsContinuous) {
    const EnvironmentImage m = indexMap(8, 4);
    const shared::EnvironmentMap e = view(m);
    // u = 0 (toward +z) lies halfway between the last column's centre and the first's.
    const glm::vec3 seam = sample(e, directionOf(0.0f, 1.5f / 4.0f));
    EXPECT_NEAR(seam.x, 3.5f, 1e-3f);  // (7 + 0) / 2
    // Just either side of it: the blend of the same two columns.
    const glm::vec3 before = sample(e, directionOf(1.0f - 1e-3f, 1.5f / 4.0f));
    const glm::vec3 after = sample(e, directionOf(1e-3f, 1.5f / 4.0f));
    EXPECT_NEAR(before.x, 3.5f + 7.0f * 8e-3f, 2e-3f);
    EXPECT_NEAR(after.x, 3.5f - 7.0f * 8e-3f, 2e-3f);
}

TEST(EnvironmentMap, RotationTurnsThePictureAboutTheVertical) {
    const EnvironmentImage m = indexMap(8, 4);
    const shared::EnvironmentMap e = view(m), quarter = view(m, 0.25f);
    for (int i = 0; i < 8; ++i) {
        // What direction phi showed, direction phi + 90 degrees shows with a quarter turn.
        const glm::vec3 before = sample(e, directionOf((float(i) + 0.5f) / 8.0f, 2.5f / 4.0f));
        const glm::vec3 after = sample(quarter, directionOf((float(i) + 0.5f + 2.0f) / 8.0f, 2.5f / 4.0f));
        EXPECT_NEAR(before.x, after.x, 1e-3f) << i;
        EXPECT_NEAR(before.y, after.y, 1e-3f) << i;
    }
    // A quarter turn is a quarter turn of the directions: -z now shows what +x... showed before.
    const glm::vec3 d(0.6f, 0.3f, -0.74f);
    const glm::vec3 turned(-d.z, d.y, d.x);  // d turned 90 degrees from -z toward +x about +y
    const glm::vec3 a = sample(e, d), b = sample(quarter, turned);
    EXPECT_NEAR(a.x, b.x, 1e-3f);
    EXPECT_NEAR(a.z, b.z, 1e-3f);
}

TEST(EnvironmentMap, ReaderReadsWhatTheExrWriterWrote) {
    const auto dir = tempDir();
    Image<float> r(4, 2), g(4, 2), b(4, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) {
            r.at(x, y) = float(x);
            g.at(x, y) = float(y) + 0.5f;
            b.at(x, y) = -1.0f;  // negative: clamped to 0
        }
    r.at(1, 1) = std::numeric_limits<float>::quiet_NaN();
    ASSERT_TRUE(writeExr(dir / "e.exr", {{"R", &r}, {"G", &g}, {"B", &b}}).ok());
    auto m = readEnvironmentMap(dir / "e.exr");
    ASSERT_TRUE(m.ok()) << m.error().describe();
    ASSERT_EQ(m->width, 4);
    ASSERT_EQ(m->height, 2);
    EXPECT_EQ(m->rgb[3 * 2 + 0], 2.0f);
    EXPECT_EQ(m->rgb[3 * (4 + 2) + 1], 1.5f);
    EXPECT_EQ(m->rgb[3 * (4 + 1) + 0], 0.0f);  // NaN
    EXPECT_EQ(m->rgb[2], 0.0f);                // negative
}

TEST(EnvironmentMap, ReaderErrorsNameTheFile) {
    const auto dir = tempDir();
    auto missing = readEnvironmentMap(dir / "missing.exr");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().describe().find("missing.exr"), std::string::npos);
    writeText(dir / "bad.exr", "not an exr at all");
    auto bad = readEnvironmentMap(dir / "bad.exr");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().describe().find("bad.exr"), std::string::npos) << bad.error().describe();
    Image<float> y(2, 2, 1.0f);
    ASSERT_TRUE(writeExr(dir / "grey.exr", {{"Y", &y}}).ok());
    auto grey = readEnvironmentMap(dir / "grey.exr");
    ASSERT_FALSE(grey.ok());
    EXPECT_NE(grey.error().message.find("RGB"), std::string::npos) << grey.error().describe();
    // Radiance pictures are read (io_environment_hdr_test.cpp); a missing one
    // is an error naming it like any other.
    auto hdr = readEnvironmentMap(dir / "sky.hdr");
    ASSERT_FALSE(hdr.ok());
    EXPECT_NE(hdr.error().describe().find("sky.hdr"), std::string::npos) << hdr.error().describe();
}

TEST(EnvironmentMap, TheTestMapReads) {
    auto m = readEnvironmentMap(testData("environment/sky_128x64.exr"));
    ASSERT_TRUE(m.ok()) << m.error().describe();
    EXPECT_EQ(m->width, 128);
    EXPECT_EQ(m->height, 64);
}

// A map red above the horizon and green below: the sky's pixels turn red,
// the liquid reflects red; without a map the render is the procedural sky's.
TEST(EnvironmentMap, PipelineBackgroundAndReflectionTakeTheMapsColours) {
    const ParticleSet& set = smallFrame21();
    RenderSettings s = autoFramedSettings(set, 160, 90);
    s.scene.walls = false;  // the floor alone: sky above the horizon
    // Lowered to look level at the liquid, so the upper half of the picture is sky.
    const glm::vec3 eye = s.camera.eye, target = s.camera.target;
    s.camera.eye = glm::vec3(eye.x, target.y, eye.z);
    Renderer renderer;
    auto plain = renderer.render(set.positions, s);
    ASSERT_TRUE(plain.ok()) << plain.error().describe();

    auto redGreen = std::make_shared<EnvironmentImage>();
    redGreen->width = 16;
    redGreen->height = 16;
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) {
            redGreen->rgb.push_back(j < 8 ? 1.0f : 0.0f);
            redGreen->rgb.push_back(j < 8 ? 0.0f : 1.0f);
            redGreen->rgb.push_back(0.0f);
        }
    RenderSettings withMap = s;
    withMap.scene.environment = redGreen;
    auto red = renderer.render(set.positions, withMap);
    ASSERT_TRUE(red.ok()) << red.error().describe();

    // Without fluid, a pixel whose ray rises more than 10 degrees is sky:
    // the procedural sky before, pure red now.
    const Camera& cam = s.camera;
    const float invF = 1.0f / cam.focalPx();
    int skyPixels = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            if (std::isfinite(plain->depth.at(x, y))) continue;
            const glm::vec3 d = glm::normalize(((float(x) + 0.5f - 0.5f * float(cam.width)) * invF) * cam.right() -
                                               ((float(y) + 0.5f - 0.5f * float(cam.height)) * invF) * cam.trueUp() -
                                               cam.back());
            if (d.y < 0.12f) continue;  // above the blend of the map's rows 7 and 8
            ++skyPixels;
            const glm::vec4 c = red->color.at(x, y);
            EXPECT_NEAR(c.r, 1.0f, 1e-4f) << x << "," << y;
            EXPECT_NEAR(c.g, 0.0f, 1e-4f);
            const glm::vec3 sky = cpu::skyColor(d, shared::sunDirection(s.shading.lightDirWorld));
            EXPECT_NEAR(plain->color.at(x, y).b, sky.z, 1e-3f) << x << "," << y;
        }
    EXPECT_GT(skyPixels, 50);

    // The liquid: more red (its reflection of the upper hemisphere) than in a
    // render with a black map, whose fluid pixels reflect nothing.
    auto black = std::make_shared<EnvironmentImage>(*redGreen);
    for (float& v : black->rgb) v = 0.0f;
    RenderSettings dark = s;
    dark.scene.environment = black;
    auto none = renderer.render(set.positions, dark);
    ASSERT_TRUE(none.ok());
    double redSum = 0.0, darkSum = 0.0;
    int fluid = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x)
            if (std::isfinite(red->depth.at(x, y))) {
                redSum += red->color.at(x, y).r;
                darkSum += none->color.at(x, y).r;
                ++fluid;
            }
    ASSERT_GT(fluid, 100);
    EXPECT_GT(redSum / fluid, darkSum / fluid + 0.02) << redSum / fluid << " vs " << darkSum / fluid;

    // In the studio with walls no sky is seen: the map changes the liquid's
    // pixels (its reflection) and nothing else.
    RenderSettings walls = autoFramedSettings(set, 160, 90);
    auto wallsPlain = renderer.render(set.positions, walls);
    walls.scene.environment = redGreen;
    auto wallsRed = renderer.render(set.positions, walls);
    ASSERT_TRUE(wallsPlain.ok() && wallsRed.ok());
    int changedFluid = 0, changedOther = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            const bool changed = wallsPlain->color.at(x, y) != wallsRed->color.at(x, y);
            if (std::isfinite(wallsPlain->depth.at(x, y))) changedFluid += changed ? 1 : 0;
            else changedOther += changed ? 1 : 0;
        }
    EXPECT_GT(changedFluid, 100);
    EXPECT_EQ(changedOther, 0);

    // Rendering without the map again gives the default picture, bit for bit.
    auto again = renderer.render(set.positions, s);
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(differingBits(plain->color, again->color), 0);
}

TEST(EnvironmentMap, OptionsMakeTheSettings) {
    RenderOptions o;
    o.environment = testData("environment/sky_128x64.exr").string();
    o.environmentRotation = 90.0f;
    o.environmentIntensity = 2.0f;
    auto s = renderSettings(o);
    ASSERT_TRUE(s.ok()) << s.error().describe();
    ASSERT_TRUE(s->scene.environment);
    EXPECT_EQ(s->scene.environment->width, 128);
    EXPECT_EQ(s->scene.environmentRotationDeg, 90.0f);
    EXPECT_EQ(s->scene.environmentIntensity, 2.0f);
    o.environment = "no/such/map.exr";
    auto bad = renderSettings(o);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().describe().find("--environment"), std::string::npos) << bad.error().describe();
    EXPECT_NE(bad.error().describe().find("map.exr"), std::string::npos) << bad.error().describe();
}
