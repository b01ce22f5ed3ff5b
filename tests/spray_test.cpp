// Spray (docs/pipeline.md#classification): the classification
// by density against hand-made density fields, the SPH estimate without a
// density attribute, and the drops drawn on the CPU (src/cpu/spray.cpp): hidden
// behind nearer fluid, streaked along their velocity, the same bits in any
// order, lit by an HDR environment map's ambient.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "core/spray.h"
#include "cpu/spray.h"
#include "meniscus/renderer.h"
#include "shared/environment.h"
#include "shared/shading.h"
#include "shared/spray.h"
#include "test_util.h"

namespace spray_test_local {

using namespace meniscus;

namespace {

constexpr float kR = 0.01f;

Camera straightCamera(int w = 160, int h = 120) { return test::faceOnCamera({0.0f, 0.0f, -1.0f}, 1.0f, w, h); }

SprayParams onParams() {
    SprayParams p;
    p.enabled = true;
    return p;
}

// A block of nx x ny x nz particles at spacing 2r from `origin`.
std::vector<glm::vec3> lattice(glm::ivec3 n, glm::vec3 origin) { return test::jitteredBlock(n, 2.0f * kR, 0.0f, origin); }

}  // namespace

TEST(SprayClassification, FromTheDensityAttribute) {
    // A hand-made density field: 1000 in the bulk, lower where marked.
    const std::vector<glm::vec3> p(6, glm::vec3(0.0f));
    const std::vector<float> rho{1000, 1000, 1000, 499, 501, 120};
    ParticleView v(p);
    v.density = StridedView<float>(std::span<const float>(rho));
    const std::vector<std::uint8_t> spray = classifySpray(v, kR, onParams());  // 0.5 of the median (1000)
    EXPECT_EQ(spray, (std::vector<std::uint8_t>{0, 0, 0, 1, 0, 1}));
    SprayParams q = onParams();
    q.restDensityKgM3 = 2000.0f;  // a stated rest density instead of the median
    EXPECT_EQ(classifySpray(v, kR, q), (std::vector<std::uint8_t>{0, 0, 0, 1, 1, 1}));
}

TEST(SprayClassification, SphEstimateWithoutTheAttribute) {
    // A block at rest spacing plus a lone drop far from it.
    auto p = lattice({12, 12, 12}, {0.0f, 0.0f, 0.0f});
    p.push_back({1.0f, 1.0f, 1.0f});
    const std::vector<float> rel = relativeDensity(ParticleView(p), kR, 0.0f);
    // The block's interior (two layers in from every face) reads 1; the lone
    // drop only its own kernel's peak, W(0) (2r)^3 over the lattice sum: 0.318.
    int interior = 0;
    for (std::size_t i = 0; i + 1 < p.size(); ++i) {
        const glm::vec3 c = p[i] / (2.0f * kR);
        if (std::min({c.x, c.y, c.z}) >= 2.0f && std::max({c.x, c.y, c.z}) <= 9.0f) {
            EXPECT_NEAR(rel[i], 1.0f, 1e-4f) << i;
            ++interior;
        }
    }
    EXPECT_GT(interior, 500);
    EXPECT_NEAR(rel.back(), 0.318f, 0.002f);
    const std::vector<std::uint8_t> spray = classifySpray(ParticleView(p), kR, onParams());
    EXPECT_EQ(spray.back(), 1);
    EXPECT_EQ(std::count(spray.begin(), spray.end(), 1), 1 + std::count_if(rel.begin(), rel.end() - 1, [](float r) {
                                                             return r < 0.5f;
                                                         }));
}

TEST(SprayDrops, HiddenBehindNearerFluid) {
    const Camera cam = straightCamera();
    const std::vector<glm::vec3> drops{{0.0f, 0.0f, -0.5f}};
    Image<glm::vec4> color(cam.width, cam.height, glm::vec4(0.1f, 0.2f, 0.3f, 1.0f));
    const Image<glm::vec4> before = color;
    // Fluid in front of the drop everywhere: nothing drawn.
    const Image<float> nearer(cam.width, cam.height, 0.4f);
    const Image<float> c0 = cpu::drawSpray(cam, drops, {}, kR, nearer, nullptr, onParams(), {0, 1, 0}, color);
    EXPECT_EQ(0, std::memcmp(color.pixels.data(), before.pixels.data(), color.pixels.size() * sizeof(glm::vec4)));
    for (float v : c0.pixels) EXPECT_EQ(v, 0.0f);
    // Fluid behind it: a round drop centred on the image, brighter at its middle.
    const Image<float> behind(cam.width, cam.height, 0.6f);
    const Image<float> c1 = cpu::drawSpray(cam, drops, {}, kR, behind, nullptr, onParams(), {0, 1, 0}, color);
    const int cx = cam.width / 2, cy = cam.height / 2;
    EXPECT_GT(c1.at(cx, cy), 0.3f);
    EXPECT_GT(c1.at(cx, cy), c1.at(cx + 2, cy));
    EXPECT_NEAR(c1.at(cx - 1, cy), c1.at(cx, cy), 0.05f);  // symmetric about the centre (pixel centres at +1/2)
    EXPECT_GT(color.at(cx, cy).x, before.at(cx, cy).x);  // toward the light drop colour
}

// With an HDR map the drops take its ambient (shared::sprayLight): with the
// key light behind them (n.l < 0 for a drop's mean normal, toward the eye)
// white drops over black show cover times the map's E(n) / pi, which for a
// constant map of radiance L is L (its projection on the spherical harmonics
// is exact in band 0 and 0 above): a tinted map tints them. Without a map
// they are grey, the studio's kOpaqueAmbient.
TEST(SprayDrops, LitByTheEnvironmentMapsAmbient) {
    const Camera cam = straightCamera();
    const std::vector<glm::vec3> drops{{0.0f, 0.0f, -0.5f}};
    const glm::vec3 L{0.9f, 0.5f, 0.2f};
    const test::ConstantEnvironment constant(L);
    const shared::EnvironmentMap& env = constant.map;
    SprayParams p = onParams();
    p.color = glm::vec3(1.0f);
    const glm::vec3 behindTheDrops = -cam.back();
    const Image<float> fluid(cam.width, cam.height, 0.6f);
    Image<glm::vec4> tinted(cam.width, cam.height, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f)), grey = tinted;
    const Image<float> c1 = cpu::drawSpray(cam, drops, {}, kR, fluid, nullptr, p, behindTheDrops, tinted, env);
    const Image<float> c0 = cpu::drawSpray(cam, drops, {}, kR, fluid, nullptr, p, behindTheDrops, grey);
    const int cx = cam.width / 2, cy = cam.height / 2;
    const float c = c1.at(cx, cy);
    ASSERT_GT(c, 0.3f);
    EXPECT_EQ(c0.at(cx, cy), c);  // the light changes the colour, not the cover
    const glm::vec4 t = tinted.at(cx, cy), g = grey.at(cx, cy);
    EXPECT_NEAR(t.x / c, L.x, 0.01f);
    EXPECT_NEAR(t.y / c, L.y, 0.01f);
    EXPECT_NEAR(t.z / c, L.z, 0.01f);
    EXPECT_NEAR(g.x / c, shared::kOpaqueAmbient, 1e-5f);
    EXPECT_EQ(g.x, g.y);
    EXPECT_EQ(g.y, g.z);
    // The key light facing the drops adds its share, white, to both.
    Image<glm::vec4> lit(cam.width, cam.height, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    cpu::drawSpray(cam, drops, {}, kR, fluid, nullptr, p, cam.back(), lit, env);
    EXPECT_NEAR(lit.at(cx, cy).x / c, L.x + (1.0f - shared::kOpaqueAmbient), 0.01f);
    EXPECT_NEAR(lit.at(cx, cy).z / c, L.z + (1.0f - shared::kOpaqueAmbient), 0.01f);
}

TEST(SprayDrops, StreakedAlongTheirVelocityAndFainter) {
    const Camera cam = straightCamera();
    const std::vector<glm::vec3> drops{{0.0f, 0.0f, -0.5f}};
    const std::vector<glm::vec3> fast{{4.0f, 0.0f, 0.0f}};  // 4 m/s to the right: a 4 cm streak at 10 ms
    const Image<float> none(cam.width, cam.height, INFINITY);
    Image<glm::vec4> a(cam.width, cam.height, glm::vec4(0.0f)), b = a;
    const Image<float> round = cpu::drawSpray(cam, drops, {}, kR, none, nullptr, onParams(), {0, 1, 0}, a);
    const Image<float> streak = cpu::drawSpray(cam, drops, fast, kR, none, nullptr, onParams(), {0, 1, 0}, b);
    auto width = [&](const Image<float>& c, bool rows) {
        int n = 0;
        for (int k = 0; k < (rows ? cam.width : cam.height); ++k)
            n += (rows ? c.at(k, cam.height / 2) : c.at(cam.width / 2, k)) > 0.0f;
        return n;
    };
    EXPECT_GT(width(streak, true), 2 * width(round, true));  // long along x
    EXPECT_EQ(width(streak, false), width(round, false));    // as thick as the drop across
    EXPECT_LT(streak.at(cam.width / 2, cam.height / 2), round.at(cam.width / 2, cam.height / 2));
}

TEST(SprayDrops, SameBitsInAnyOrder) {
    const Camera cam = straightCamera(200, 150);
    std::vector<glm::vec3> p, v;
    for (int i = 0; i < 300; ++i) {
        p.push_back({0.002f * float(i % 37) - 0.03f, 0.0017f * float(i % 29) - 0.02f, -0.5f - 0.001f * float(i % 7)});
        v.push_back({float(i % 5) - 2.0f, float(i % 3) - 1.0f, 0.5f * float(i % 2)});
    }
    const Image<float> none(cam.width, cam.height, INFINITY);
    Image<glm::vec4> a(cam.width, cam.height, glm::vec4(0.2f)), b = a;
    const Image<float> ca = cpu::drawSpray(cam, p, v, kR, none, nullptr, onParams(), {0, 1, 0}, a);
    std::reverse(p.begin(), p.end());
    std::reverse(v.begin(), v.end());
    const Image<float> cb = cpu::drawSpray(cam, p, v, kR, none, nullptr, onParams(), {0, 1, 0}, b);
    EXPECT_EQ(0, std::memcmp(ca.pixels.data(), cb.pixels.data(), ca.pixels.size() * sizeof(float)));
    EXPECT_EQ(0, std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec4)));
}

TEST(SprayRenderer, DropsLeaveTheSurface) {
    // A block and, above it, a few lone drops: with the spray on they are not
    // splatted (the depth has no fluid there) but drawn (the spray AOV has them).
    auto p = lattice({10, 4, 10}, {-0.1f, -0.2f, -0.1f});
    const std::size_t block = p.size();
    for (int i = 0; i < 5; ++i) p.push_back({-0.06f + 0.03f * float(i), 0.1f, 0.0f});
    RenderSettings s;
    s.camera = test::faceOnCamera({0.0f, 0.0f, 0.0f}, 1.0f, 160, 120);
    s.radiusM = kR;
    s.spray = onParams();
    Renderer r;
    auto a = r.render(ParticleView(p), s);
    ASSERT_TRUE(a.ok()) << a.error().describe();
    int drops = 0, dropFluid = 0;
    for (std::size_t i = 0; i < a->spray.size(); ++i) {
        drops += a->spray.pixels[i] > 0.0f;
        dropFluid += a->spray.pixels[i] > 0.0f && a->rawDepth.pixels[i] < INFINITY;
    }
    EXPECT_GT(drops, 5);
    EXPECT_EQ(dropFluid, 0);  // the drops are not in the splat
    (void)block;
    // The spray view, and its error without the spray on.
    s.view = View::Spray;
    EXPECT_TRUE(r.render(ParticleView(p), s).ok());
    s.spray.enabled = false;
    EXPECT_FALSE(r.render(ParticleView(p), s).ok());
}

// Without a density attribute a block's own surface is not spray: its faces,
// edges and corners read 0.85, 0.72 and 0.61 of the bulk, above the default 0.5.
TEST(SprayClassification, ABlocksSurfaceIsNotSpray) {
    auto p = lattice({12, 12, 12}, {0.0f, 0.0f, 0.0f});
    const std::vector<float> rel = relativeDensity(ParticleView(p), kR, 0.0f);
    auto at = [&](int i, int j, int k) { return rel[std::size_t((k * 12 + j) * 12 + i)]; };
    EXPECT_NEAR(at(6, 6, 0), 0.850f, 0.005f);
    EXPECT_NEAR(at(6, 0, 0), 0.720f, 0.005f);
    EXPECT_NEAR(at(0, 0, 0), 0.607f, 0.005f);
    const std::vector<std::uint8_t> spray = classifySpray(ParticleView(p), kR, onParams());
    EXPECT_EQ(std::count(spray.begin(), spray.end(), 1), 0);
}

// The diffuse layer (RenderSettings::diffuse, the whitewater) with the spray
// off: spray drawn as drops, foam on the surface lifted so it shows, bubbles
// not drawn; the body of water is splatted whole.
TEST(SprayRenderer, DiffuseLayerDrawsSprayAndFoamNotBubbles) {
    auto p = lattice({10, 10, 4}, {-0.09f, -0.09f, -0.3f});  // a block facing the camera; front centres at z = -0.24
    RenderSettings s;
    s.camera = test::faceOnCamera({0.0f, 0.0f, 0.0f}, 1.0f, 160, 120);
    s.radiusM = kR;
    // On the block's front face (the surface the camera sees): one foam, one
    // bubble, one spray particle, each at its own place.
    const float front = p.back().z;
    std::vector<glm::vec3> pos = {{-0.04f, 0.0f, front}, {0.04f, 0.0f, front - 0.03f}, {0.0f, 0.2f, 0.0f}};
    std::vector<std::int64_t> kind = {0, 2, 1};
    Renderer r;
    auto plain = r.render(ParticleView(p), s);
    ASSERT_TRUE(plain.ok());
    EXPECT_TRUE(plain->spray.empty());  // no layer, no spray: no cover AOV
    s.diffuse.positions = pos;
    s.diffuse.kind = kind;
    auto a = r.render(ParticleView(p), s);
    ASSERT_TRUE(a.ok()) << a.error().describe();
    auto coverNear = [&](const glm::vec3& w) {
        const glm::vec3 d = w - s.camera.eye;
        const float z = -glm::dot(d, s.camera.back()), f = s.camera.focalPx();
        const glm::vec2 px(0.5f * float(s.camera.width) + glm::dot(d, s.camera.right()) * f / z,
                           0.5f * float(s.camera.height) - glm::dot(d, s.camera.trueUp()) * f / z);
        float c = 0.0f;
        for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx)
                c = std::max(c, a->spray.at(int(px.x) + dx, int(px.y) + dy));
        return c;
    };
    EXPECT_GT(coverNear(pos[0]), 0.1f);   // foam: lifted over the surface it floats on
    EXPECT_EQ(coverNear(pos[1]), 0.0f);   // a bubble: not drawn
    EXPECT_GT(coverNear(pos[2]), 0.1f);   // spray in the air
    EXPECT_EQ(a->rawDepth.pixels, plain->rawDepth.pixels);  // the water is the same
    // Not lifted (drawn as spray where it lies), the foam hides under the surface.
    kind[0] = 1;
    auto b = r.render(ParticleView(p), s);
    ASSERT_TRUE(b.ok());
    a = std::move(b);
    EXPECT_EQ(coverNear(pos[0]), 0.0f);
    // A kind list of the wrong length is an error.
    kind.pop_back();
    s.diffuse.kind = kind;
    EXPECT_FALSE(r.render(ParticleView(p), s).ok());
}
}  // namespace spray_test_local
