// The surface-noise stage on the CPU (src/cpu/surface_noise.cpp,
// docs/pipeline.md#noise-and-foam; the NVIDIA SSFR patent's eqs. 14-17): N is a
// deterministic function of the particles' ids and positions, its pattern
// travels with a particle, only particles at the surface count, it bumps the
// normals by its gradient, the shading lays foam by its magnitude, and the
// renderer keeps the turbulence of a sequence.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "cpu/normals.h"
#include "cpu/scene.h"
#include "cpu/shading.h"
#include "cpu/splat.h"
#include "cpu/surface_noise.h"
#include "meniscus/io.h"
#include "meniscus/renderer.h"
#include "shared/surface_noise.h"
#include "test_util.h"

namespace surface_noise_test_local {

using namespace meniscus;

namespace {

constexpr float kR = 0.01f;

// Looking down -z from the origin: view space is world space.
Camera straightCamera(int w = 160, int h = 120) { return test::faceOnCamera({0.0f, 0.0f, -1.0f}, 1.0f, w, h); }

// A flat surface at eye depth z everywhere (the smoothed depth a particle's
// front touches when z = its centre's depth - r).
Image<float> flatDepth(const Camera& c, float z) { return Image<float>(c.width, c.height, z); }

NoiseParams onParams() {
    NoiseParams p;
    p.enabled = true;
    return p;
}

std::vector<float> idzOf(const std::vector<std::int64_t>& ids) {
    std::vector<float> z;
    for (auto id : ids) z.push_back(shared::noiseIdCoordinate(id));
    return z;
}

int nonZero(const Image<float>& img) {
    return int(std::count_if(img.pixels.begin(), img.pixels.end(), [](float v) { return v != 0.0f; }));
}

// A slab of particles (a lattice of spacing 2r, `layers` deep below z = -zTop)
// with ids scrambled.
struct Slab {
    std::vector<glm::vec3> positions;
    std::vector<std::int64_t> ids;
};
Slab slab(int nx, int ny, int layers, float zTop) {
    Slab s;
    std::mt19937 rng(5);
    for (int k = 0; k < layers; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                s.positions.push_back({(float(i) - 0.5f * float(nx)) * 2.0f * kR,
                                       (float(j) - 0.5f * float(ny)) * 2.0f * kR, -(zTop + 2.0f * kR * float(k))});
                s.ids.push_back(std::int64_t(rng() % 1000000));
            }
    return s;
}

}  // namespace

TEST(SurfaceNoise, IdCoordinateWrapsIntoThePeriod) {
    EXPECT_EQ(shared::noiseIdCoordinate(0), 0.0f);
    EXPECT_EQ(shared::noiseIdCoordinate(5), 5.0f);
    EXPECT_EQ(shared::noiseIdCoordinate(shared::kNoiseIdPeriod + 3), 3.0f);
    EXPECT_EQ(shared::noiseIdCoordinate(-1), float(shared::kNoiseIdPeriod - 1));
}

TEST(SurfaceNoise, NoiseExpFollowsExp) {
    for (float x = -20.0f; x <= 0.0f; x += 0.013f)
        EXPECT_NEAR(shared::noiseExp(x), std::exp(x), 3e-7f * std::exp(x)) << x;
    EXPECT_EQ(shared::noiseExp(0.0f), 1.0f);
    EXPECT_GT(shared::noiseExp(-1000.0f), 0.0f);  // clamped at e^-87, no underflow to a denormal
}

TEST(SurfaceNoise, OneSurfaceParticleMakesASpriteOfItsRadius) {
    const Camera cam = straightCamera();
    const float z = 0.5f;
    const std::vector<glm::vec3> p{{0.0f, 0.0f, -z}};
    const auto idz = idzOf({42});
    const NoiseParams np = onParams();
    const Image<float> N = cpu::splatNoise(cam, p, kR, flatDepth(cam, z - kR), idz, {}, np);
    // Every non-zero pixel lies within the sprite radius of the projected centre.
    const float R = np.spriteRadii * kR * cam.focalPx() / z;
    ASSERT_GT(R, 4.0f);
    int inside = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            const float dx = float(x) + 0.5f - 0.5f * float(cam.width), dy = float(y) + 0.5f - 0.5f * float(cam.height);
            const bool in = dx * dx + dy * dy < R * R;
            inside += in;
            if (!in) {
                EXPECT_EQ(N.at(x, y), 0.0f) << x << " " << y;
            }
        }
    // The noise has zeros only on lines: most of the disc is non-zero, of both signs.
    EXPECT_GT(nonZero(N), inside * 3 / 4);
    const auto [lo, hi] = std::minmax_element(N.pixels.begin(), N.pixels.end());
    EXPECT_LT(*lo, -0.02f);
    EXPECT_GT(*hi, 0.02f);
    EXPECT_LE(std::max(-*lo, *hi), 1.05f);  // |noise| <= ~1.04, Gaussian <= 1, weight 1
}

TEST(SurfaceNoise, SameImageForTheSameInputsAndAnyThreadCount) {
    const Camera cam = straightCamera(200, 150);
    const Slab s = slab(24, 18, 3, 0.6f);
    const auto idz = idzOf(s.ids);
    std::vector<float> amp(s.positions.size());
    for (std::size_t i = 0; i < amp.size(); ++i) amp[i] = 1.0f + float(i % 3);
    const Image<float> depth = cpu::splatDepth(cam, s.positions, kR);
    const NoiseParams np = onParams();
    Image<float> one, two;
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
        one = cpu::splatNoise(cam, s.positions, kR, depth, idz, amp, np);
    }
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
        two = cpu::splatNoise(cam, s.positions, kR, depth, idz, amp, np);
    }
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    EXPECT_EQ(0, std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(float)));
    EXPECT_GT(nonZero(one), 1000);
    // The order of the particles does not matter either (the sums are exact).
    std::vector<std::size_t> order(s.positions.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = order.size() - 1 - i;
    std::vector<glm::vec3> p2;
    std::vector<float> idz2, amp2;
    for (std::size_t i : order) {
        p2.push_back(s.positions[i]);
        idz2.push_back(idz[i]);
        amp2.push_back(amp[i]);
    }
    const Image<float> reversed = cpu::splatNoise(cam, p2, kR, depth, idz2, amp2, np);
    EXPECT_EQ(0, std::memcmp(one.pixels.data(), reversed.pixels.data(), one.pixels.size() * sizeof(float)));
}

TEST(SurfaceNoise, APatternTravelsWithItsParticle) {
    const Camera cam = straightCamera();
    const float z = 0.5f, f = cam.focalPx();
    const NoiseParams np = onParams();
    const auto idz = idzOf({777});
    const Image<float> depth = flatDepth(cam, z - kR);
    // Moved by exactly 7 pixels right and 4 down (in the image plane).
    const std::vector<glm::vec3> a{{0.0f, 0.0f, -z}};
    const std::vector<glm::vec3> b{{7.0f * z / f, -4.0f * z / f, -z}};
    const Image<float> Na = cpu::splatNoise(cam, a, kR, depth, idz, {}, np);
    const Image<float> Nb = cpu::splatNoise(cam, b, kR, depth, idz, {}, np);
    double diff = 0.0, mag = 0.0;
    for (int y = 0; y + 4 < cam.height; ++y)
        for (int x = 0; x + 7 < cam.width; ++x) {
            diff = std::max(diff, double(std::fabs(Nb.at(x + 7, y + 4) - Na.at(x, y))));
            mag = std::max(mag, double(std::fabs(Na.at(x, y))));
        }
    EXPECT_GT(mag, 0.02);
    EXPECT_LT(diff, 1e-3 * mag) << "the pattern did not move with the particle";
    // Another id at the same place draws another pattern.
    const Image<float> Nc = cpu::splatNoise(cam, a, kR, depth, idzOf({778}), {}, np);
    double other = 0.0;
    for (std::size_t i = 0; i < Na.size(); ++i) other = std::max(other, double(std::fabs(Nc.pixels[i] - Na.pixels[i])));
    EXPECT_GT(other, 0.2 * mag);
}

TEST(SurfaceNoise, OnlyParticlesNearTheSurfaceCount) {
    const Camera cam = straightCamera();
    const float z = 0.5f;
    const NoiseParams np = onParams();  // falloff 1 r
    const std::vector<glm::vec3> p{{0.0f, 0.0f, -z}};
    const auto idz = idzOf({9});
    auto peak = [&](float surface) {
        const Image<float> N = cpu::splatNoise(cam, p, kR, flatDepth(cam, surface), idz, {}, np);
        float m = 0.0f;
        for (float v : N.pixels) m = std::max(m, std::fabs(v));
        return m;
    };
    const float atSurface = peak(z - kR);
    EXPECT_GT(atSurface, 0.02f);
    // Front one falloff below the surface: weight e^-1.
    EXPECT_NEAR(peak(z - 2.0f * kR), atSurface * std::exp(-1.0f), 2.0f / shared::kNoiseFixedScale + 1e-4f * atSurface);
    // Deep below (front 3 falloffs down: e^-9 ~ 1.2e-4 < kNoiseMinWeight): left out.
    EXPECT_EQ(peak(z - 4.0f * kR), 0.0f);
    // No fluid at its centre: no contribution.
    EXPECT_EQ(peak(INFINITY), 0.0f);
}

TEST(SurfaceNoise, NoneWhereThereIsNoFluid) {
    const Camera cam = straightCamera();
    const float z = 0.5f;
    const std::vector<glm::vec3> p{{0.0f, 0.0f, -z}};
    Image<float> depth = flatDepth(cam, z - kR);
    for (int y = 0; y < cam.height; ++y)
        for (int x = cam.width / 2 + 2; x < cam.width; ++x) depth.at(x, y) = INFINITY;  // the right side is empty
    const Image<float> N = cpu::splatNoise(cam, p, kR, depth, idzOf({3}), {}, onParams());
    int left = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            if (x >= cam.width / 2 + 2) {
                EXPECT_EQ(N.at(x, y), 0.0f);
            } else {
                left += N.at(x, y) != 0.0f;
            }
        }
    EXPECT_GT(left, 20);
}

TEST(SurfaceNoise, AmplitudeScalesTheNoise) {
    const Camera cam = straightCamera();
    const float z = 0.5f;
    const std::vector<glm::vec3> p{{0.0f, 0.0f, -z}};
    const Image<float> depth = flatDepth(cam, z - kR);
    const auto idz = idzOf({11});
    const std::vector<float> one{1.0f}, three{3.0f};
    const Image<float> a = cpu::splatNoise(cam, p, kR, depth, idz, one, onParams());
    const Image<float> b = cpu::splatNoise(cam, p, kR, depth, idz, three, onParams());
    for (std::size_t i = 0; i < a.size(); ++i)
        EXPECT_NEAR(b.pixels[i], 3.0f * a.pixels[i], 2.0f / shared::kNoiseFixedScale + 1e-6f);
}

TEST(SurfaceNoise, ScaleInvariant) {
    // Particles, radius and camera scaled by 4: the same image.
    const Camera cam = straightCamera(120, 90);
    const Slab s = slab(10, 8, 2, 0.5f);
    const auto idz = idzOf(s.ids);
    const NoiseParams np = onParams();
    const Image<float> a = cpu::splatNoise(cam, s.positions, kR, cpu::splatDepth(cam, s.positions, kR), idz, {}, np);
    std::vector<glm::vec3> big;
    for (auto q : s.positions) big.push_back(4.0f * q);
    Camera cam4 = cam;
    cam4.nearM *= 4.0f;
    const Image<float> b =
        cpu::splatNoise(cam4, big, 4.0f * kR, cpu::splatDepth(cam4, big, 4.0f * kR), idz, {}, np);
    double worst = 0.0, mag = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        worst = std::max(worst, double(std::fabs(a.pixels[i] - b.pixels[i])));
        mag = std::max(mag, double(std::fabs(a.pixels[i])));
    }
    EXPECT_GT(mag, 0.02);
    EXPECT_LT(worst, 1e-3 * mag + 4.0 / shared::kNoiseFixedScale);
}

TEST(SurfaceNoise, BumpTiltsNormalsAgainstTheGradient) {
    const Camera cam = straightCamera(40, 30);
    const float z = 0.5f;
    const Image<float> depth = flatDepth(cam, z);
    // N = a x (columns): dN/dx = a per pixel, 0 along rows.
    const float a = 0.1f;
    Image<float> N(cam.width, cam.height, 0.0f);
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) N.at(x, y) = a * float(x);
    Image<glm::vec3> n(cam.width, cam.height, glm::vec3(0.0f, 0.0f, 1.0f));
    NoiseParams np = onParams();
    np.bump = 0.5f;
    cpu::bumpNormals(cam, kR, depth, N, np, n);
    const float spritePx = np.spriteRadii * kR * cam.focalPx() / z;
    const glm::vec3 want = glm::normalize(glm::vec3(-np.bump * a * spritePx, 0.0f, 1.0f));
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {  // edges one-sided: the same slope
            EXPECT_NEAR(n.at(x, y).x, want.x, 1e-5f);
            EXPECT_NEAR(n.at(x, y).y, 0.0f, 1e-6f);
            EXPECT_NEAR(glm::length(n.at(x, y)), 1.0f, 1e-6f);
        }
    EXPECT_LT(want.x, -0.05f);  // tilted toward -x: the surface rises toward +x
    // Zero noise leaves normals exactly as they were.
    Image<glm::vec3> m(cam.width, cam.height, glm::normalize(glm::vec3(0.2f, -0.3f, 1.0f)));
    const Image<glm::vec3> before = m;
    cpu::bumpNormals(cam, kR, depth, Image<float>(cam.width, cam.height, 0.0f), np, m);
    EXPECT_EQ(0, std::memcmp(m.pixels.data(), before.pixels.data(), m.pixels.size() * sizeof(glm::vec3)));
}

TEST(SurfaceNoise, BumpNeverDifferencesAcrossADepthJump) {
    const Camera cam = straightCamera(40, 30);
    Image<float> depth(cam.width, cam.height, 0.5f);
    Image<float> N(cam.width, cam.height, 0.0f);
    for (int y = 0; y < cam.height; ++y)
        for (int x = 20; x < cam.width; ++x) {
            depth.at(x, y) = 0.9f;  // another body far behind
            N.at(x, y) = 0.5f;      // with another noise level
        }
    Image<glm::vec3> n(cam.width, cam.height, glm::vec3(0.0f, 0.0f, 1.0f));
    cpu::bumpNormals(cam, kR, depth, N, onParams(), n);
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) EXPECT_EQ(n.at(x, y), glm::vec3(0.0f, 0.0f, 1.0f)) << x << " " << y;
}

TEST(SurfaceNoise, FoamCoverFromTheMagnitude) {
    EXPECT_EQ(shared::noiseFoamCover(0.05f, 0.1f, 4.0f), 0.0f);
    EXPECT_FLOAT_EQ(shared::noiseFoamCover(0.2f, 0.1f, 4.0f), 0.4f);
    EXPECT_FLOAT_EQ(shared::noiseFoamCover(-0.2f, 0.1f, 4.0f), 0.4f);  // by |N|
    EXPECT_EQ(shared::noiseFoamCover(2.0f, 0.1f, 4.0f), 1.0f);
}

TEST(SurfaceNoise, ShadingLaysFoamWhereTheNoiseIsStrong) {
    const Camera cam = straightCamera(32, 24);
    const Image<float> depth = flatDepth(cam, 0.5f);
    const Image<glm::vec3> normals(cam.width, cam.height, glm::vec3(0.0f, 0.0f, 1.0f));
    const Image<float> thickness(cam.width, cam.height, 0.05f);
    Image<float> N(cam.width, cam.height, 0.0f);
    for (int y = 0; y < cam.height; ++y)
        for (int x = 16; x < cam.width; ++x) N.at(x, y) = 1.0f;  // full foam on the right half
    const cpu::SceneLayer none;
    ShadingParams sp;
    NoiseParams np = onParams();
    const Image<glm::vec4> plain = cpu::shadeAndComposite(cam, none, depth, normals, thickness, sp);
    const Image<glm::vec4> foamy = cpu::shadeAndComposite(cam, none, depth, normals, thickness, sp, &N, &np);
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            if (x < 16) {
                EXPECT_EQ(foamy.at(x, y), plain.at(x, y));  // N = 0: no foam
            } else {
                // Cover 1: the lit foam colour alone.
                const glm::vec3 L = glm::normalize(glm::vec3(glm::dot(sp.lightDirWorld, cam.right()),
                                                             glm::dot(sp.lightDirWorld, cam.trueUp()),
                                                             glm::dot(sp.lightDirWorld, cam.back())));
                const float lit = 0.35f + 0.65f * std::max(L.z, 0.0f);
                EXPECT_NEAR(foamy.at(x, y).x, np.foamColor.x * lit, 1e-3f);
                EXPECT_NEAR(foamy.at(x, y).z, np.foamColor.z * lit, 1e-3f);
            }
        }
}

TEST(SurfaceNoise, ParametersOutOfRangeAreNamed) {
    NoiseParams p = onParams();
    EXPECT_EQ(checkNoiseParams(p), "");
    p.octaves = 7;
    EXPECT_NE(checkNoiseParams(p).find("octaves"), std::string::npos);
    p = onParams();
    p.spriteRadii = NAN;
    EXPECT_NE(checkNoiseParams(p).find("spriteRadii"), std::string::npos);
    p = onParams();
    p.turbulence.boost = 0.5f;
    EXPECT_NE(checkNoiseParams(p).find("boost"), std::string::npos);
}

// ---- Through the renderer ---------------------------------------------------

namespace {
RenderSettings oneParticleSettings() {
    RenderSettings s;
    s.camera = straightCamera(96, 72);
    s.radiusM = kR;
    s.noise = onParams();
    s.scene.background = false;
    s.filter = NoFilter{};  // the sphere's own front is the surface: weight 1
    return s;
}
float peakNoise(const Aovs& a) {
    float m = 0.0f;
    for (float v : a.noise.pixels) m = std::max(m, std::fabs(v));
    return m;
}
}  // namespace

TEST(SurfaceNoiseRenderer, NoiseAndFoamAovsAndViews) {
    RenderSettings s = oneParticleSettings();
    const std::vector<glm::vec3> p{{0.0f, 0.0f, -0.3f}};
    Renderer r;
    auto a = r.render(p, s);
    ASSERT_TRUE(a.ok()) << a.error().describe();
    EXPECT_EQ(a->noise.width, 96);
    EXPECT_EQ(a->foam.width, 96);
    EXPECT_GT(peakNoise(*a), 0.02f);
    s.view = View::Noise;
    auto v = r.render(p, s);
    ASSERT_TRUE(v.ok());
    EXPECT_EQ(v->color.width, 96);
    s.noise.enabled = false;
    auto bad = r.render(p, s);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("noise"), std::string::npos);
    s.view = View::Final;
    auto off = r.render(p, s);
    ASSERT_TRUE(off.ok());
    EXPECT_TRUE(off->noise.empty());
    s.noise.enabled = true;
    s.noise.octaves = 0;
    auto wrong = r.render(p, s);
    ASSERT_FALSE(wrong.ok());
    EXPECT_NE(wrong.error().message.find("octaves"), std::string::npos);
}

TEST(SurfaceNoiseRenderer, KeepsTheTurbulenceOfASequence) {
    RenderSettings s = oneParticleSettings();
    s.noise.turbulence.tauMps = 0.5f;
    s.noise.turbulence.boost = 3.0f;
    s.noise.turbulence.holdFrames = 4;
    const std::vector<glm::vec3> p{{0.0f, 0.0f, -0.3f}};
    const std::vector<std::int64_t> id{5};
    std::vector<glm::vec3> v{{0.0f, 0.0f, 0.0f}};
    ParticleView view(p);
    view.id = StridedView<std::int64_t>(std::span<const std::int64_t>(id));
    view.velocity = StridedView<glm::vec3>(std::span<const glm::vec3>(v));
    Renderer r;
    auto frame = [&](std::int64_t index, glm::vec3 vel) {
        v[0] = vel;
        s.frameIndex = index;
        auto a = r.render(view, s);
        EXPECT_TRUE(a.ok());
        return a.ok() ? peakNoise(*a) : 0.0f;
    };
    const float calm = frame(0, {0, 0, 0});
    ASSERT_GT(calm, 0.02f);
    const float tol = 4.0f / shared::kNoiseFixedScale;
    EXPECT_NEAR(frame(1, {1, 0, 0}), 3.0f * calm, tol);    // jumped by 1 m/s > tau: boosted
    EXPECT_NEAR(frame(1, {1, 0, 0}), 3.0f * calm, tol);    // a redraw of frame 1 keeps its boost
    EXPECT_NEAR(frame(2, {1, 0, 0}), 2.5f * calm, tol);    // steady: fading over 4 frames
    EXPECT_NEAR(frame(7, {3, 0, 0}), calm, tol);           // a jump in the sequence starts afresh
    s.frameIndex = -1;                                     // a lone frame: no turbulence
    v[0] = {9, 0, 0};
    auto lone = r.render(view, s);
    ASSERT_TRUE(lone.ok());
    EXPECT_NEAR(peakNoise(*lone), calm, tol);
}

TEST(SurfaceNoiseRenderer, RealFrameGetsNoiseOnItsSurfaceOnly) {
    auto set = readParticles(test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
    ASSERT_TRUE(set.ok()) << set.error().describe();
    RenderSettings s;
    s.radiusM = 0.025f;
    Camera base;
    base.width = 320;
    base.height = 180;
    s.camera = autoFrameCamera(set->positions, s.radiusM, base);
    s.noise = onParams();
    Renderer r;
    auto a = r.render(ParticleView::of(*set), s);
    ASSERT_TRUE(a.ok()) << a.error().describe();
    int fluid = 0, noisy = 0, foamy = 0, stray = 0;
    for (std::size_t i = 0; i < a->depth.size(); ++i) {
        const bool f = a->depth.pixels[i] < INFINITY;
        fluid += f;
        noisy += f && a->noise.pixels[i] != 0.0f;
        foamy += f && a->foam.pixels[i] > 0.0f;
        stray += !f && a->noise.pixels[i] != 0.0f;
    }
    EXPECT_EQ(stray, 0);
    EXPECT_GT(noisy, fluid * 8 / 10) << "of " << fluid << " fluid pixels";
    EXPECT_GT(foamy, 0);
    EXPECT_LT(foamy, fluid / 2);
    // The noise changes the image, the normals and only the fluid's pixels.
    RenderSettings plain = s;
    plain.noise.enabled = false;
    auto b = r.render(ParticleView::of(*set), plain);
    ASSERT_TRUE(b.ok());
    int changed = 0;
    for (std::size_t i = 0; i < a->color.size(); ++i) {
        const bool differs = a->color.pixels[i] != b->color.pixels[i];
        changed += differs;
        if (!(a->depth.pixels[i] < INFINITY)) {
            EXPECT_FALSE(differs);
        }
    }
    EXPECT_GT(changed, fluid / 2);
}
}  // namespace surface_noise_test_local
