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
#include "shared/geometry_shade.h"
#include "shared/studio.h"
#include "test_util.h"

namespace environment_test_local {

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

// A W x H map of colour `top` above the horizon (the upper half of the rows)
// and `bottom` below.
EnvironmentImage twoHalves(int w, int h, glm::vec3 top, glm::vec3 bottom) {
    EnvironmentImage m;
    m.width = w;
    m.height = h;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const glm::vec3 c = 2 * j < h ? top : bottom;
            m.rgb.insert(m.rgb.end(), {c.x, c.y, c.z});
        }
    return m;
}

// The map's view with its irradiance projected, as the pipeline makes it.
shared::EnvironmentMap lit(const EnvironmentImage& m, float rotation = 0.0f, float intensity = 1.0f) {
    shared::EnvironmentMap e = view(m, rotation, intensity);
    shared::environmentIrradianceSh(m.rgb.data(), m.width, m.height, rotation, intensity, e.irradiance);
    return e;
}

glm::vec3 irradiance(const shared::EnvironmentMap& e, glm::vec3 n) {
    return shared::environmentIrradiance(n.x, n.y, n.z, e);
}

// Unit directions spread over the sphere (a Fibonacci lattice) and the axes.
std::vector<glm::vec3> directions() {
    std::vector<glm::vec3> out = {{0, 1, 0}, {0, -1, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}};
    const int n = 64;
    for (int k = 0; k < n; ++k) {
        const float y = 1.0f - 2.0f * (float(k) + 0.5f) / float(n), r = std::sqrt(1.0f - y * y);
        const float phi = float(k) * 2.39996323f;
        out.push_back({r * std::cos(phi), y, r * std::sin(phi)});
    }
    return out;
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
    // pixels (its reflection) and, through its ambient light, the studio's.
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
    EXPECT_GT(changedOther, 1000);

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

// ---- The ambient light from the map (Ramamoorthi & Hanrahan 2001) ----------

// A map of constant radiance L: E(n) = pi L for every n, so the diffuse
// ambient E / pi of an albedo-1 surface is L (times the intensity), whatever
// the rotation.
TEST(EnvironmentIrradiance, AConstantMapGivesPiLEverywhere) {
    const glm::vec3 L(0.3f, 0.5f, 0.7f);
    const EnvironmentImage m = twoHalves(64, 32, L, L);
    const shared::EnvironmentMap e = lit(m, 0.37f, 2.0f);
    for (const glm::vec3& n : directions()) {
        const glm::vec3 E = irradiance(e, n);
        // Within the texels' midpoint rule (the rows' solid angles are exact,
        // their directions the centres'): a few parts in 10^4 at 32 rows.
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(E[c], kPi * 2.0f * L[c], 2e-3f * kPi * 2.0f * L[c]) << n.x << "," << n.y << "," << n.z;
        const glm::vec3 a = shared::environmentAmbient(n.x, n.y, n.z, e);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], 2.0f * L[c], 2e-3f * 2.0f * L[c]);
    }
    // The constant band holds it all: exactly 4 pi L pi Y00 = 2 pi^(3/2) L.
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(e.irradiance[0][c], 2.0f * kPi * std::sqrt(kPi) * 2.0f * L[c], 1e-4f);
    for (int k = 1; k < 4; ++k) EXPECT_NEAR(glm::length(e.irradiance[k]), 0.0f, 1e-5f) << k;
}

// A map of radiance 1 above the horizon and 0 below: the exact irradiance is
// E(n) = pi (1 + n.y) / 2 (a plane facing up sees the whole bright
// hemisphere, one facing down none, a wall half of it), which bands 0 and 1
// hold exactly (their coefficients pi / 2 and pi / 2 n.y; band 2 is 0).
TEST(EnvironmentIrradiance, TheUpperHemisphereMatchesTheClosedForm) {
    const EnvironmentImage m = twoHalves(128, 64, glm::vec3(1.0f), glm::vec3(0.0f));
    const shared::EnvironmentMap e = lit(m);
    EXPECT_NEAR(irradiance(e, {0, 1, 0}).x, kPi, 0.01f * kPi);
    EXPECT_NEAR(irradiance(e, {0, -1, 0}).x, 0.0f, 0.01f * kPi);
    EXPECT_NEAR(irradiance(e, {1, 0, 0}).x, 0.5f * kPi, 0.01f * kPi);
    EXPECT_GT(irradiance(e, {0, 1, 0}).x, irradiance(e, {0, -1, 0}).x + 3.0f);
    for (const glm::vec3& n : directions())
        EXPECT_NEAR(irradiance(e, n).y, 0.5f * kPi * (1.0f + n.y), 0.02f * kPi) << n.x << "," << n.y << "," << n.z;
    // The map upside down: the other way round.
    const shared::EnvironmentMap flipped = lit(twoHalves(128, 64, glm::vec3(0.0f), glm::vec3(1.0f)));
    EXPECT_NEAR(irradiance(flipped, {0, -1, 0}).z, kPi, 0.01f * kPi);
    EXPECT_NEAR(irradiance(flipped, {0, 1, 0}).z, 0.0f, 0.01f * kPi);
}

// The irradiance turns with the map: a map bright in one quarter of its
// columns, turned by a quarter, lights the normal turned by a quarter as the
// unturned map lit the normal before, the same direction the sampling turns.
TEST(EnvironmentIrradiance, RotationTurnsTheLightWithThePicture) {
    EnvironmentImage m = twoHalves(64, 32, glm::vec3(0.0f), glm::vec3(0.0f));
    for (int j = 0; j < 32; ++j)
        for (int i = 32; i < 48; ++i) m.rgb[std::size_t(3 * (j * 64 + i))] = 4.0f;  // u in [0.5, 0.75): red
    const shared::EnvironmentMap still = lit(m), turned = lit(m, 0.25f);
    // The bright quarter is around phi = pi / 4: x > 0, z < 0.
    const glm::vec3 toward = glm::normalize(glm::vec3(1.0f, 0.0f, -1.0f));
    EXPECT_GT(irradiance(still, toward).x, 3.0f * irradiance(still, -toward).x);
    // Turned by a quarter (pi / 2 in phi): x' = x cos a + ... the direction of phi + pi / 2.
    for (const glm::vec3& n : directions()) {
        const float phi = std::atan2(n.x, -n.z), r = std::sqrt(n.x * n.x + n.z * n.z);
        const glm::vec3 t(r * std::sin(phi + 0.5f * kPi), n.y, -r * std::cos(phi + 0.5f * kPi));
        EXPECT_NEAR(irradiance(turned, t).x, irradiance(still, n).x, 1e-3f) << n.x << "," << n.y << "," << n.z;
        // The sampled radiance agrees: what the map showed along n it shows
        // along t (away from the poles, where the azimuth is undefined).
        if (r > 1e-3f) {
            EXPECT_NEAR(sample(turned, t).x, sample(still, n).x, 1e-2f);
        }
    }
}

// Without a map nothing changes: the studio's lighting and a geometry
// colour are those of the constant ambient.
TEST(EnvironmentIrradiance, TheStudioAndGeometryTakeTheMapsTint) {
    shared::Studio studio;
    studio.lightDirWorld = glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f));
    const shared::StudioShading plain = shared::studioShading(studio);
    const float keyFloor = shared::kStudioKey * studio.lightDirWorld.y;
    EXPECT_EQ(plain.litFloor, glm::vec3(shared::kStudioAmbient + keyFloor));
    // A constant blue-green map: the floor's ambient is its radiance.
    const glm::vec3 L(0.1f, 0.4f, 0.8f);
    const EnvironmentImage m = twoHalves(128, 64, L, L);
    const shared::EnvironmentMap e = lit(m);
    const shared::StudioShading tinted = shared::studioShading(studio, e);
    // (Within the projection's midpoint rule, about 1e-4 at 64 rows.)
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(tinted.litFloor[c], L[c] + keyFloor, 3e-4f);
        EXPECT_NEAR(tinted.litWallX[c], L[c] + shared::kStudioKey * std::max(0.0f, studio.lightDirWorld.x), 3e-4f);
    }
    // A grey rough dielectric facing away from the key light: its colour is
    // the ambient's, grey without a map, the map's hue with it.
    const glm::vec3 n(0.0f, 0.0f, 1.0f), v(0.0f, 0.0f, 1.0f), light(0.0f, 0.0f, -1.0f), grey(0.5f);
    const glm::vec3 a = shared::geometryRadiance(n, v, light, grey, 1.0f, 0.0f, {});
    EXPECT_NEAR(a.x, a.z, 1e-6f);
    const glm::vec3 b = shared::geometryRadiance(n, v, light, grey, 1.0f, 0.0f, e);
    // Diffuse 0.5 L (1 - F) plus the rough specular's share F L; F = 0.04 at
    // normal incidence with roughness 1 (f90 = 0).
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(b[c], 0.5f * L[c] * 0.96f + 0.04f * L[c], 3e-4f) << c;
    EXPECT_GT(b.z, 4.0f * b.x);
}

// The whole pipeline: under a map red above the horizon and blue below, the
// studio's floor (facing the red sky) turns red; without the map the picture
// is the default's. (The geometry's tint: TheStudioAndGeometryTakeTheMapsTint
// above, and gl_backend_test's EnvironmentMapMatchesCpu on both backends.)
TEST(EnvironmentIrradiance, PipelineStudioTakesTheMapsColour) {
    const ParticleSet& set = smallFrame21();
    RenderSettings s = autoFramedSettings(set, 160, 90);
    auto redBlue = std::make_shared<EnvironmentImage>(twoHalves(16, 16, {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}));
    Renderer renderer;
    auto plain = renderer.render(set.positions, s);
    RenderSettings withMap = s;
    withMap.scene.environment = redBlue;
    auto red = renderer.render(set.positions, withMap);
    ASSERT_TRUE(plain.ok() && red.ok());
    // The studio's pixels (not the liquid): the floor (the picture's lowest
    // rows) lit by the red hemisphere turns red, the walls (lit half by each)
    // purple; without the map both are grey-ish (blue at least half the red).
    const Camera& cam = s.camera;
    auto ratio = [&](const Aovs& a, int y0, int y1) {
        double r = 0, b = 0;
        int n = 0;
        for (int y = y0; y < y1; ++y)
            for (int x = 0; x < cam.width; ++x) {
                if (std::isfinite(plain->depth.at(x, y))) continue;
                r += a.color.at(x, y).r;
                b += a.color.at(x, y).b;
                ++n;
            }
        EXPECT_GT(n, 200);
        return r / b;
    };
    const int floorRows = cam.height - cam.height / 8;
    EXPECT_LT(ratio(*plain, floorRows, cam.height), 2.0);
    EXPECT_GT(ratio(*red, floorRows, cam.height), 2.5 * ratio(*plain, floorRows, cam.height));
    EXPECT_GT(ratio(*red, 0, cam.height), 1.3 * ratio(*plain, 0, cam.height));
    // Rendering without the map again gives the default picture, bit for bit.
    auto again = renderer.render(set.positions, s);
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(differingBits(plain->color, again->color), 0);
}
}  // namespace environment_test_local
