// Geometry stage (docs/geometry.md#how-it-is-drawn, src/cpu/geometry.cpp): a
// box's face at its analytic eye depth and shaded by the shared formula, the
// studio kept around it, nothing drawn behind the scene, the cut-away of a
// container, the same bits for any thread count; through the Renderer, an
// object in front hides the liquid and one behind it is what the liquid
// refracts, and the studio's floor goes under the objects.
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "core/geometry_draw.h"
#include "cpu/geometry.h"
#include "cpu/scene.h"
#include "meniscus/geometry.h"
#include "meniscus/options.h"
#include "meniscus/renderer.h"
#include "shared/geometry_shade.h"
#include "shared/sky.h"
#include "test_util.h"

namespace geometry_stage_test_local {

using namespace meniscus;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A camera on +z at `dist` from the origin, looking at it.
Camera frontCamera(float dist, int w = 96, int h = 72) {
    Camera c;
    c.eye = {0.0f, 0.0f, dist};
    c.target = {0.0f, 0.0f, 0.0f};
    c.width = w;
    c.height = h;
    c.fovYDegrees = 40.0f;
    c.nearM = 0.01f;
    return c;
}

GeometryObject boxObject(glm::vec3 min, glm::vec3 max, glm::vec3 color = glm::vec3(0.8f, 0.1f, 0.1f)) {
    GeometryObject o;
    o.name = "box";
    o.mesh = makeBoxMesh(min, max);
    o.material.baseColor = color;
    return o;
}

// A block of liquid of n particles of radius kR from `origin`, and the
// settings that look at it from +z.
constexpr float kR = 0.02f;
std::vector<glm::vec3> liquidBlock(glm::ivec3 n, glm::vec3 origin) {
    return test::jitteredBlock(n, 2.0f * kR, 0.0f, origin);
}
RenderSettings liquidSettings(float dist, int w, int h) {
    RenderSettings s;
    s.radiusM = kR;
    s.camera = frontCamera(dist, w, h);
    s.anisotropy.enabled = false;
    return s;
}

shared::Studio studioFor(const Camera& cam) {
    Bounds box;
    box.extend({-1.0f, -1.0f, -1.0f});
    box.extend({1.0f, 1.0f, 1.0f});
    return shared::makeStudio(box, 0.02f, cam, SceneParams{}, ShadingParams{}.lightDirWorld);
}

bool sameBits(const Image<float>& a, const Image<float>& b) {
    return a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}
bool sameBits(const Image<glm::vec4>& a, const Image<glm::vec4>& b) {
    return a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec4)) == 0;
}

}  // namespace

TEST(GeometryDraw, CutAwayDropsTheFacesWhoseOutsideFacesTheEye) {
    GeometryObject tank = boxObject({-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f});
    TriangleMesh scratch;
    EXPECT_EQ(facesSeenFrom(tank.mesh, {0.0f, 0.0f, 5.0f}, sceneFaces(tank), &scratch).triangleCount(), 12u);  // not a container
    tank.cutaway = true;
    // From the front: the +z wall goes; from above a corner, the +x, +y and +z walls.
    EXPECT_EQ(facesSeenFrom(tank.mesh, {0.0f, 0.0f, 5.0f}, sceneFaces(tank), &scratch).triangleCount(), 10u);
    const TriangleMesh& corner = facesSeenFrom(tank.mesh, {3.0f, 4.0f, 5.0f}, sceneFaces(tank), &scratch);
    EXPECT_EQ(corner.triangleCount(), 6u);
    for (std::size_t t = 0; t < corner.indices.size(); t += 3) {
        const glm::vec3 a = corner.positions[corner.indices[t]], b = corner.positions[corner.indices[t + 1]],
                        c = corner.positions[corner.indices[t + 2]];
        const glm::vec3 outward = glm::cross(b - a, c - a);
        EXPECT_LE(glm::dot(outward, glm::vec3(3.0f, 4.0f, 5.0f) - a), 0.0f);
    }
    tank.visible = false;
    EXPECT_FALSE(drawsObject(tank));
}

TEST(GeometryStage, ABoxFaceAtItsAnalyticDepthShadedByTheSharedFormula) {
    const Camera cam = frontCamera(5.0f);
    const shared::Studio studio = studioFor(cam);
    cpu::SceneLayer layer = cpu::castScene(cam, studio);
    const cpu::SceneLayer before = layer;
    SceneGeometry g;
    g.objects.push_back(boxObject({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}));
    cpu::drawGeometry(cam, g, studio, layer.color, layer.depth);
    // The centre pixels see the +z face at eye depth 4.5 (the eye depth of a
    // plane facing the camera is the same at every pixel).
    const int cx = cam.width / 2, cy = cam.height / 2;
    for (int y = cy - 2; y <= cy + 1; ++y)
        for (int x = cx - 2; x <= cx + 1; ++x) EXPECT_NEAR(layer.depth.at(x, y), 4.5f, 1e-5f) << x << "," << y;
    // Its colour: the formula with the face's normal, the view ray and the studio's light.
    const glm::vec3 light = shared::sunDirection(studio.lightDirWorld);
    const float f = cam.focalPx();
    const glm::vec3 d((float(cx) + 0.5f - 0.5f * cam.width) / f, -(float(cy) + 0.5f - 0.5f * cam.height) / f, -1.0f);
    const glm::vec3 v = -glm::normalize(d);  // the camera's axes are the world's here
    const GeometryMaterial& m = g.objects[0].material;
    const glm::vec3 want = shared::geometryRadiance({0.0f, 0.0f, 1.0f}, v, light, m.baseColor, m.roughness, m.metalness, {});
    const glm::vec4 got = layer.color.at(cx, cy);
    EXPECT_NEAR(got.r, want.r, 1e-5f);
    EXPECT_NEAR(got.g, want.g, 1e-5f);
    EXPECT_NEAR(got.b, want.b, 1e-5f);
    EXPECT_EQ(got.a, 1.0f);
    EXPECT_GT(got.r, 2.0f * got.g);  // a red box
    // Outside the box the studio is untouched.
    EXPECT_EQ(layer.depth.at(0, 0), before.depth.at(0, 0));
    EXPECT_EQ(layer.color.at(0, 0), before.color.at(0, 0));
    EXPECT_EQ(layer.depth.at(cam.width - 1, cam.height - 1), before.depth.at(cam.width - 1, cam.height - 1));
}

// A base colour map (shared/texture.h): the checker quad of
// tests/data/geometry (four blocks of 2 x 2 texels) seen from above, each
// quarter shaded as an untextured quad of that block's colour would be.
TEST(GeometryStage, ATexturedQuadShowsItsMapWhereItsCoordinatesPutIt) {
    Camera cam;
    cam.eye = {0.5f, 2.0f, 0.5f};
    cam.target = {0.5f, 0.0f, 0.5f};
    cam.up = {0.0f, 0.0f, -1.0f};  // the image's top is -z, its right +x
    cam.width = cam.height = 64;
    cam.fovYDegrees = 20.0f;
    cam.nearM = 0.01f;
    const shared::Studio studio = studioFor(cam);
    auto quad = readGeometryMesh(test::testData("geometry/textured_quad.obj"));
    ASSERT_TRUE(quad.ok()) << quad.error().describe();
    ASSERT_TRUE(quad->material.baseColorTexture);
    const auto drawn = [&](const GeometryObject& o) {
        cpu::SceneLayer layer = cpu::castScene(cam, studio);
        SceneGeometry g;
        g.objects.push_back(o);
        cpu::drawGeometry(cam, g, studio, layer.color, layer.depth);
        return layer.color;
    };
    const Image<glm::vec4> textured = drawn(*quad);
    // The quarters' centres: the map's top-left block (red) at the image's top-left.
    const struct {
        int x, y;
        glm::vec3 color;
    } quarters[] = {{20, 20, {1, 0, 0}}, {44, 20, {0, 1, 0}}, {20, 44, {0, 0, 1}}, {44, 44, {1, 1, 1}}};
    for (const auto& q : quarters) {
        GeometryObject plain = *quad;
        plain.material.baseColorTexture = nullptr;
        plain.material.baseColor = q.color;
        const glm::vec4 want = drawn(plain).at(q.x, q.y), got = textured.at(q.x, q.y);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 1e-6f) << q.x << "," << q.y << " channel " << k;
    }
    // Without its coordinates the map is not drawn: the base colour (white) alone.
    GeometryObject noUv = *quad;
    noUv.uvs.clear();
    GeometryObject white = *quad;
    white.material.baseColorTexture = nullptr;
    EXPECT_TRUE(sameBits(drawn(noUv), drawn(white)));
}

TEST(GeometryStage, NothingIsDrawnAtOrBehindTheSceneDepth) {
    const Camera cam = frontCamera(5.0f);
    Image<glm::vec4> color(cam.width, cam.height, glm::vec4(0.0f));
    Image<float> depth(cam.width, cam.height, 3.0f);  // a wall 3 m from the eye, in front of the box
    SceneGeometry g;
    g.objects.push_back(boxObject({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}));
    cpu::drawGeometry(cam, g, studioFor(cam), color, depth);
    for (float z : depth.pixels) EXPECT_EQ(z, 3.0f);
    for (const glm::vec4& c : color.pixels) EXPECT_EQ(c, glm::vec4(0.0f));
}

TEST(GeometryStage, ACutAwayTankShowsItsFarWallFromInside) {
    const Camera cam = frontCamera(5.0f);
    Image<glm::vec4> color(cam.width, cam.height, glm::vec4(0.0f));
    Image<float> depth(cam.width, cam.height, kInf);
    SceneGeometry g;
    g.objects.push_back(boxObject({-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}, glm::vec3(0.6f)));
    g.objects.back().cutaway = true;
    cpu::drawGeometry(cam, g, studioFor(cam), color, depth);
    // The near wall (z = 1, eye depth 4) is cut away: the far wall's inside (z = -1) shows.
    EXPECT_NEAR(depth.at(cam.width / 2, cam.height / 2), 6.0f, 1e-5f);
    // Lit from the inside's side: its normal turned toward the viewer.
    EXPECT_GT(color.at(cam.width / 2, cam.height / 2).g, 0.1f);
}

TEST(GeometryStage, SameBitsForAnyThreadCount) {
    const Camera cam = frontCamera(4.0f, 160, 120);
    const shared::Studio studio = studioFor(cam);
    SceneGeometry g;
    g.objects.push_back(boxObject({-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}, glm::vec3(0.5f)));
    g.objects.back().cutaway = true;
    GeometryObject ball;
    ball.name = "sphere";
    ball.mesh = makeSphereMesh({0.2f, -0.4f, 0.1f}, 0.45f);
    ball.material.metalness = 1.0f;
    ball.material.roughness = 0.2f;
    ball.material.baseColor = {0.9f, 0.7f, 0.3f};
    g.objects.push_back(ball);
    auto drawWith = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        cpu::SceneLayer layer = cpu::castScene(cam, studio);
        cpu::drawGeometry(cam, g, studio, layer.color, layer.depth);
        return layer;
    };
    const cpu::SceneLayer one = drawWith(1);
    for (int threads : {2, 3}) {
        const cpu::SceneLayer many = drawWith(threads);
        EXPECT_TRUE(sameBits(one.depth, many.depth)) << threads;
        EXPECT_TRUE(sameBits(one.color, many.color)) << threads;
    }
}

// Through the Renderer: a block of liquid, a box in front of its left half and
// a bright box behind its right half.
TEST(GeometryStage, InFrontHidesTheLiquidBehindIsRefractedThrough) {
    const std::vector<glm::vec3> pts = liquidBlock({20, 10, 5}, {-0.4f, -0.2f, -0.1f});
    RenderSettings s = liquidSettings(2.5f, 160, 120);
    auto plain = renderFrame(pts, s);
    ASSERT_TRUE(plain.ok()) << plain.error().describe();

    auto g = std::make_shared<SceneGeometry>();
    g->objects.push_back(boxObject({-0.6f, -0.5f, 0.3f}, {-0.05f, 0.5f, 0.4f}, glm::vec3(0.2f, 0.8f, 0.2f)));
    g->objects.push_back(boxObject({0.05f, -0.5f, -0.6f}, {0.6f, 0.5f, -0.5f}, glm::vec3(1.0f, 0.05f, 0.05f)));
    s.geometry = g;
    std::vector<StageTime> times;
    auto with = renderFrame(pts, s, &times);
    ASSERT_TRUE(with.ok()) << with.error().describe();
    // The stage ran and was timed.
    bool timed = false;
    for (const StageTime& t : times) timed = timed || t.stage == "geometry";
    EXPECT_TRUE(timed);

    const int y = s.camera.height / 2;
    const int left = s.camera.width / 2 - 20, right = s.camera.width / 2 + 20;
    // Left: liquid without the box, none with it (hidden), the green box seen.
    EXPECT_LT(plain->depth.at(left, y), kInf);
    EXPECT_EQ(with->depth.at(left, y), kInf);
    EXPECT_GT(with->color.at(left, y).g, 2.0f * with->color.at(left, y).r);
    // Right: still liquid, now over red: what it transmits is redder.
    ASSERT_LT(with->depth.at(right, y), kInf);
    const glm::vec4 a = plain->color.at(right, y), b = with->color.at(right, y);
    EXPECT_GT(b.r - b.b, a.r - a.b + 0.02f);

    // The studio's floor goes under the objects, not through them.
    RenderSettings low = s;
    auto deep = std::make_shared<SceneGeometry>(*g);
    deep->objects.push_back(boxObject({-0.2f, -1.5f, -0.2f}, {0.2f, -1.2f, 0.2f}));
    low.geometry = deep;
    EXPECT_TRUE(renderFrame(pts, low).ok());

    // An invalid mesh is an error naming the object.
    auto bad = std::make_shared<SceneGeometry>(*g);
    bad->objects[0].mesh.indices[0] = 999;
    s.geometry = bad;
    auto refused = renderFrame(pts, s);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("geometry: object 0 (box)"), std::string::npos)
        << refused.error().message;
}

// A glass pane facing the camera over a flat grey picture: Beer-Lambert
// through the wall (tint per centimetre, a 1 cm wall: the tint once at
// normal incidence) and Schlick's F0 = ((ior - 1) / (ior + 1))^2 reflecting
// the environment; nothing drawn behind the liquid or the scene.
TEST(GeometryStage, GlassFrontAtNormalIncidenceFollowsBeerLambertAndFresnel) {
    const Camera cam = frontCamera(5.0f, 33, 33);
    SceneGeometry g;
    GeometryObject pane;
    pane.name = "pane";
    pane.mesh = makePlaneMesh({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, 2.0f);
    pane.material.glass = true;
    pane.material.ior = 1.5f;
    pane.material.tint = {0.5f, 0.8f, 1.0f};
    pane.material.thicknessM = 0.01f;
    g.objects.push_back(pane);
    const shared::Studio studio = studioFor(cam);
    const glm::vec4 grey(0.5f, 0.5f, 0.5f, 1.0f);
    Image<glm::vec4> color(cam.width, cam.height, grey);
    const Image<float> none(cam.width, cam.height, kInf);
    cpu::drawGlassFronts(cam, g, studio, none, none, color);
    const glm::vec4 c = color.at(16, 16);  // the centre pixel: normal incidence
    const glm::vec3 light = shared::sunDirection(studio.lightDirWorld);
    const glm::vec3 env = shared::skyRadiance(0.0f, 0.0f, 1.0f, light);
    const float F = 0.04f;
    EXPECT_NEAR(c.r, 0.5f * 0.5f * (1.0f - F) + F * env.r, 2e-4f);
    EXPECT_NEAR(c.g, 0.5f * 0.8f * (1.0f - F) + F * env.g, 2e-4f);
    EXPECT_NEAR(c.b, 0.5f * 1.0f * (1.0f - F) + F * env.b, 2e-4f);
    // Behind the liquid (at 4 m, the pane at 5 m): not drawn.
    Image<glm::vec4> again(cam.width, cam.height, grey);
    const Image<float> liquid(cam.width, cam.height, 4.0f);
    cpu::drawGlassFronts(cam, g, studio, liquid, none, again);
    for (const glm::vec4& p : again.pixels) EXPECT_EQ(p, grey);
}

// Liquid in a glass box: still seen (the glass hides nothing), tinted by the
// glass's front wall (a red-absorbing tint takes red away) and its back wall
// behind it; the liquid's depth the same bits as without the glass.
TEST(GeometryStage, LiquidInAGlassIsSeenThroughItsWalls) {
    const std::vector<glm::vec3> pts = liquidBlock({10, 10, 5}, {-0.2f, -0.2f, -0.1f});
    RenderSettings s = liquidSettings(2.0f, 120, 90);
    s.camera.eye = {0.4f, 0.5f, 2.0f};
    auto plain = renderFrame(pts, s);
    ASSERT_TRUE(plain.ok());
    auto g = std::make_shared<SceneGeometry>();
    GeometryObject glass;
    glass.name = "glass";
    glass.mesh = makeBoxMesh({-0.3f, -0.3f, -0.2f}, {0.3f, 0.4f, 0.2f});
    glass.material.glass = true;
    glass.material.tint = {0.2f, 0.95f, 0.95f};
    glass.material.thicknessM = 0.01f;
    g->objects.push_back(glass);
    s.geometry = g;
    std::vector<StageTime> times;
    auto with = renderFrame(pts, s, &times);
    ASSERT_TRUE(with.ok()) << with.error().describe();
    ASSERT_FALSE(times.empty());
    EXPECT_EQ(times.back().stage, "glass");  // the last stage, over the finished picture
    ASSERT_EQ(plain->depth.pixels.size(), with->depth.pixels.size());
    EXPECT_EQ(std::memcmp(plain->depth.pixels.data(), with->depth.pixels.data(),
                          plain->depth.pixels.size() * sizeof(float)),
              0);
    const int x = s.camera.width / 2, y = s.camera.height / 2;
    ASSERT_LT(with->depth.at(x, y), kInf);
    const glm::vec4 a = plain->color.at(x, y), b = with->color.at(x, y);
    EXPECT_LT(b.r, 0.7f * a.r) << a.r << " " << b.r;
    EXPECT_GT(b.g, 0.7f * a.g) << a.g << " " << b.g;
}

// One Renderer over frames: the scene with its geometry is drawn once and
// kept while the camera, studio and geometry stay; a new geometry object, a
// hidden object or a new camera draws it again (each frame the same as a
// fresh renderer's).
TEST(GeometryStage, AReusedRendererKeepsTheDrawnGeometryUntilItChanges) {
    const std::vector<glm::vec3> pts = liquidBlock({10, 6, 4}, {-0.2f, -0.1f, -0.1f});
    RenderSettings s = liquidSettings(2.0f, 96, 72);
    auto g = std::make_shared<SceneGeometry>();
    g->objects.push_back(boxObject({-0.5f, -0.3f, -0.5f}, {0.5f, -0.15f, -0.3f}));
    g->objects.push_back(boxObject({0.25f, -0.1f, 0.2f}, {0.4f, 0.1f, 0.3f}, glm::vec3(0.1f, 0.2f, 0.9f)));
    auto hidden = std::make_shared<SceneGeometry>(*g);
    hidden->objects[1].visible = false;
    Renderer reused;
    std::vector<Image<glm::vec4>> pictures;
    for (int k = 0; k < 5; ++k) {
        s.geometry = k == 2 ? hidden : g;
        if (k == 4) s.camera.eye.x += 0.3f;
        auto a = reused.render(pts, s);
        auto b = Renderer().render(pts, s);
        ASSERT_TRUE(a.ok() && b.ok());
        EXPECT_TRUE(sameBits(a->color, b->color)) << k;
        pictures.push_back(a->color);
    }
    EXPECT_TRUE(sameBits(pictures[0], pictures[1]));
    EXPECT_FALSE(sameBits(pictures[1], pictures[2]));  // the blue box hidden
    EXPECT_TRUE(sameBits(pictures[0], pictures[3]));   // and shown again
    EXPECT_FALSE(sameBits(pictures[3], pictures[4]));
}

// --geometry through the options: objects turned with z-up data as the
// particles are (z up becomes y up), --cut-away off keeps containers whole,
// the same list read once (the same object back), an error naming the option.
TEST(GeometryOptions, RenderGeometryTurnsCutsAndCaches) {
    const std::string box = R"({"box": {"min": [0, 0, 0], "max": [1, 2, 3]}, "cutaway": true})";
    auto up = renderGeometry({box}, {0.0f, 0.0f, 1.0f});
    ASSERT_TRUE(up.ok()) << up.error().describe();
    const Bounds b = (*up)->bounds();
    // (x, y, z) -> (x, z, -y): the box's 3 m along z now stand along y.
    EXPECT_NEAR(b.min.y, 0.0f, 1e-6f);
    EXPECT_NEAR(b.max.y, 3.0f, 1e-6f);
    EXPECT_NEAR(b.min.z, -2.0f, 1e-6f);
    EXPECT_TRUE((*up)->objects[0].cutaway);
    auto again = renderGeometry({box}, {0.0f, 0.0f, 1.0f});
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(again->get(), up->get());  // read once
    auto whole = renderGeometry({box}, {0.0f, 1.0f, 0.0f}, false);
    ASSERT_TRUE(whole.ok());
    EXPECT_FALSE((*whole)->objects[0].cutaway);
    EXPECT_NEAR((*whole)->bounds().max.z, 3.0f, 1e-6f);
    auto missing = renderGeometry({"/no/such/tank.stl"}, {0.0f, 1.0f, 0.0f});
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().describe().find("--geometry /no/such/tank.stl"), std::string::npos)
        << missing.error().describe();
    EXPECT_FALSE(missing.error().usage);  // the data's error, not the option's
    auto wrong = renderGeometry({R"({"sphere": {"radius": -1}})"}, {0.0f, 1.0f, 0.0f});
    ASSERT_FALSE(wrong.ok());
    EXPECT_TRUE(wrong.error().usage) << wrong.error().describe();  // a value of the option: exit 2
}
}  // namespace geometry_stage_test_local
