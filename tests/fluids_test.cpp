// Several fluids (docs/pipeline.md#several-fluids; Cords & Staadt 2008,
// "Instant Liquids" §5; src/shared/fluids.h, src/cpu/composite_fluids.cpp, the
// E/T split of src/cpu/shading.cpp, the pipeline's per-fluid layers): the split
// is exact (C over two backgrounds differs by T times their difference), a
// pixel with one fluid is that fluid rendered alone, two touching fluids keep a
// sharp border in depth and colour, an opaque fluid in front hides the one
// behind exactly, a clear one shows it, fluid indices and materials swapped
// together give the same picture, the fluid AOV and view, and the errors.
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/composite_fluids.h"
#include "cpu/shading.h"
#include "shared/fluids.h"
#include "meniscus/io.h"
#include "meniscus/particle_view.h"
#include "meniscus/renderer.h"
#include "test_util.h"

namespace fluids_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kR = 0.01f;  // particle radius, m

Material preset(const char* name) {
    Material m;
    EXPECT_TRUE(materialPreset(name, &m)) << name;
    return m;
}

// Particles with a fluid index each, and the view the renderer reads.
struct Bodies {
    std::vector<glm::vec3> positions;
    std::vector<std::int64_t> fluid;
    void add(const std::vector<glm::vec3>& p, int k) {
        positions.insert(positions.end(), p.begin(), p.end());
        fluid.insert(fluid.end(), p.size(), std::int64_t(k));
    }
    ParticleView view() const {
        ParticleView v{std::span<const glm::vec3>(positions)};
        v.fluid = StridedView<std::int64_t>(std::span<const std::int64_t>(fluid));
        return v;
    }
    // Fluid k's particles alone, without a fluid index.
    std::vector<glm::vec3> only(int k) const {
        std::vector<glm::vec3> out;
        for (std::size_t i = 0; i < positions.size(); ++i)
            if (fluid[i] == k) out.push_back(positions[i]);
        return out;
    }
    Bounds bounds() const {
        Bounds b;
        for (const glm::vec3& p : positions) b.extend(p);
        return b;
    }
};

// Face-on settings around the bodies, the studio fixed to their bounds (so
// every render of a subset sees the same scene).
RenderSettings settingsFor(const Bodies& b, glm::vec3 target, int w = 160, int h = 100) {
    RenderSettings s;
    s.camera = faceOnCamera(target, 0.5f, w, h);
    s.radiusM = kR;
    s.scene.studioBounds = b.bounds();
    return s;
}

Aovs render(const ParticleView& v, const RenderSettings& s) {
    auto r = renderFrame(v, s);
    EXPECT_TRUE(r.ok()) << r.error().describe();
    return r ? std::move(*r) : Aovs{};
}

// Fluid k rendered alone with its material.
Aovs solo(const Bodies& b, int k, RenderSettings s) {
    s.shading.material = s.fluidMaterials[std::size_t(k)];
    s.fluidMaterials.clear();
    const std::vector<glm::vec3> p = b.only(k);
    return render(std::span<const glm::vec3>(p), s);
}

bool sameBits(const glm::vec4& a, const glm::vec4& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Two blocks of 8 x 8 x 4 particles, their front faces facing the camera.
std::vector<glm::vec3> block(float x0, float zFront) {
    return jitteredBlock({8, 8, 4}, 2.0f * kR, 0.0f, {x0 + kR, kR, zFront - 7.0f * kR});
}

}  // namespace

// The shading is affine in the background it refracts: over two uniform
// opaque backgrounds S1, S2 a fluid pixel's colours differ by exactly T (S1 -
// S2), with foam, white water and a half-opaque material on, and E = C - T S.
TEST(SeveralFluids, TheSplitIntoEmissionAndTransmittanceIsExact) {
    const int W = 48, H = 32;
    Camera cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.0f, W, H);
    Image<float> depth(W, H, kInf), thickness(W, H, 0.0f), noise(W, H, 0.0f), white(W, H, 0.0f);
    Image<glm::vec3> normals(W, H, glm::vec3(0.0f));
    for (int y = 4; y < H - 4; ++y)
        for (int x = 4; x < W - 4; ++x) {
            const std::uint32_t i = std::uint32_t(y * W + x);
            depth.at(x, y) = 0.9f + 0.1f * hash01(i, 1);
            thickness.at(x, y) = 0.2f * hash01(i, 2);
            normals.at(x, y) = glm::normalize(glm::vec3(hash01(i, 3) - 0.5f, hash01(i, 4) - 0.5f, 1.0f));
            noise.at(x, y) = 2.0f * hash01(i, 5) - 1.0f;
            white.at(x, y) = hash01(i, 6);
        }
    ShadingParams sh;
    sh.material = preset("lava");
    sh.material.opacity = 0.5f;
    NoiseParams np;
    np.enabled = true;
    np.foamGain = 0.8f;
    WhiteningParams wp;
    wp.enabled = true;
    const glm::vec3 s1(0.2f, 0.5f, 0.7f), s2(0.9f, 0.1f, 0.4f);
    Image<glm::vec4> e1, t1, e2, t2;
    auto shadeOver = [&](glm::vec3 bg, Image<glm::vec4>& e, Image<glm::vec4>& t) {
        cpu::SceneLayer scene{Image<glm::vec4>(W, H, glm::vec4(bg, 1.0f)), Image<float>(W, H, 10.0f)};
        cpu::LayerSplit split{&e, &t};
        return cpu::shadeAndComposite(cam, scene, depth, normals, thickness, sh, &noise, &np, &white, &wp, &split);
    };
    const Image<glm::vec4> c1 = shadeOver(s1, e1, t1), c2 = shadeOver(s2, e2, t2);
    int fluid = 0;
    double maxErr = 0.0, maxT = 0.0;
    for (std::size_t i = 0; i < depth.size(); ++i) {
        if (!(depth.pixels[i] < kInf)) {
            EXPECT_EQ(e1.pixels[i], glm::vec4(0.0f));
            EXPECT_EQ(t1.pixels[i], glm::vec4(0.0f));
            continue;
        }
        ++fluid;
        EXPECT_EQ(t1.pixels[i], t2.pixels[i]);  // T does not depend on the background
        for (int c = 0; c < 3; ++c) {
            const double predicted = double(t1.pixels[i][c]) * (double(s1[c]) - double(s2[c]));
            maxErr = std::max(maxErr, std::abs(double(c1.pixels[i][c]) - double(c2.pixels[i][c]) - predicted));
            maxT = std::max(maxT, double(t1.pixels[i][c]));
            EXPECT_NEAR(e1.pixels[i][c], e2.pixels[i][c], 2e-6);  // nor does E
        }
    }
    EXPECT_EQ(fluid, (W - 8) * (H - 8));
    EXPECT_GT(maxT, 0.05);     // some light does pass
    EXPECT_LT(maxErr, 2e-6);   // float rounding only
}

// Each fluid keeps its own layer: where only one fluid is seen, the picture
// (colour and depth, bit for bit) is that fluid rendered alone with its
// material; elsewhere the scene. At full and at half resolution (each fluid
// upsampled and its edges blended on its own).
class SeveralFluidsAtScale : public testing::TestWithParam<float> {};
INSTANTIATE_TEST_SUITE_P(FullAndHalf, SeveralFluidsAtScale, testing::Values(1.0f, 0.5f));

TEST_P(SeveralFluidsAtScale, APixelWithOneFluidIsThatFluidAlone) {
    Bodies b;
    b.add(block(-0.2f, 0.0f), 0);
    b.add(block(0.04f, 0.0f), 1);
    RenderSettings s = settingsFor(b, {0.0f, 0.08f, 0.0f});
    s.fluidScale = GetParam();
    s.fluidMaterials = {preset("water"), preset("lava")};
    const Aovs both = render(b.view(), s);
    const Aovs a0 = solo(b, 0, s), a1 = solo(b, 1, s);
    int seen[2] = {0, 0}, differ = 0;
    for (std::size_t i = 0; i < both.color.size(); ++i) {
        const int k = int(both.fluid.pixels[i]);
        const Aovs& ref = k == 1 ? a1 : a0;
        if (k >= 0) ++seen[k];
        if (k >= 0 && !(ref.depth.pixels[i] < kInf)) ++differ;  // the solo render has fluid there too
        differ += !sameBits(both.color.pixels[i], ref.color.pixels[i]);
        if (k >= 0) differ += std::memcmp(&both.depth.pixels[i], &ref.depth.pixels[i], sizeof(float)) != 0;
    }
    EXPECT_GT(seen[0], 500);
    EXPECT_GT(seen[1], 500);
    EXPECT_EQ(differ, 0);
}

// Two touching fluids, the right one's face 3 radii behind the left one's (a
// step the smoothing would round off if they were one body): in the
// composite the depth steps from one face to the other within two pixels,
// and a few pixels either side of the border are each fluid alone.
TEST(SeveralFluids, TwoTouchingFluidsKeepASharpBorder) {
    Bodies b;
    b.add(block(-0.16f, 0.0f), 0);
    b.add(block(0.0f, -3.0f * kR), 1);
    // (The middle row through a row of particle centres, not between two.)
    RenderSettings s = settingsFor(b, {0.0f, 0.09f, 0.0f});
    s.fluidMaterials = {preset("water"), preset("lava")};
    const Aovs both = render(b.view(), s);
    const Aovs a0 = solo(b, 0, s), a1 = solo(b, 1, s);
    Bodies merged = b;
    merged.fluid.assign(merged.fluid.size(), 0);
    const Aovs one = render(merged.view(), s);
    const int W = s.camera.width, y = s.camera.height / 2;
    // The border column: where fluid 1 starts to be nearest on the middle row.
    int border = -1;
    for (int x = 0; x < W && border < 0; ++x)
        if (both.fluid.at(x, y) == 1.0f) border = x;
    ASSERT_GT(border, 10);
    const float zLeft = a0.depth.at(border - 6, y), zRight = a1.depth.at(border + 6, y);
    ASSERT_LT(zLeft, zRight);
    auto between = [&](const Image<float>& z) {
        int n = 0;
        for (int x = border - 12; x <= border + 12; ++x) {
            const float v = z.at(x, y);
            n += v > zLeft + 0.25f * (zRight - zLeft) && v < zRight - 0.25f * (zRight - zLeft);
        }
        return n;
    };
    std::printf("pixels between the two faces' depths on the middle row: several fluids %d, one fluid %d\n",
                between(both.depth), between(one.depth));
    EXPECT_LE(between(both.depth), 2);
    EXPECT_GT(between(one.depth), between(both.depth));  // one body: the step is smoothed into a ramp
    for (int d = 3; d <= 8; ++d) {
        EXPECT_TRUE(sameBits(both.color.at(border - d, y), a0.color.at(border - d, y))) << d;
        EXPECT_TRUE(sameBits(both.color.at(border + d, y), a1.color.at(border + d, y))) << d;
    }
}

// At a reduced-resolution edge of coverage c the layer's colour is blended
// into what is behind it: the split follows, E' + T' B = B + c (E + T B - B).
TEST(SeveralFluids, TheSplitFollowsTheEdgeBlend) {
    for (std::uint32_t i = 0; i < 200; ++i) {
        const glm::vec3 e(hash01(i, 1), hash01(i, 2), hash01(i, 3)), t(hash01(i, 4), hash01(i, 5), hash01(i, 6));
        const glm::vec3 behind(hash01(i, 7), hash01(i, 8), hash01(i, 9));
        const float c = i % 10 == 0 ? 1.0f : hash01(i, 10);
        const glm::vec3 want = behind + c * (shared::fluidOver(e, t, behind) - behind);
        const glm::vec3 got =
            shared::fluidOver(shared::fluidEdgeEmission(e, c), shared::fluidEdgeTransmittance(t, c), behind);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 1e-6f) << i;
        if (c >= 1.0f) {
            EXPECT_EQ(shared::fluidEdgeTransmittance(t, c), t);
        }
    }
}

// A fluid in front of another: opaque, it hides it exactly (T = 0); clear,
// the one behind shows through (its colour tints the overlap).
TEST(SeveralFluids, TheFrontFluidHidesOrShowsTheOneBehind) {
    Bodies b;
    b.add(ballOfParticles({0.0f, 0.08f, 0.05f}, 0.05f, 2.0f * kR), 0);  // in front
    b.add(block(-0.08f, -0.02f), 1);
    for (const char* front : {"water", "opaque"}) {
        RenderSettings s = settingsFor(b, {0.0f, 0.08f, 0.0f});
        Material m = preset("water");
        if (std::string(front) == "opaque") m.opacity = 1.0f;
        s.fluidMaterials = {m, preset("lava")};
        const Aovs both = render(b.view(), s);
        const Aovs a0 = solo(b, 0, s), a1 = solo(b, 1, s);
        int overlap = 0, same = 0;
        double redShift = 0.0;
        for (std::size_t i = 0; i < both.color.size(); ++i) {
            if (both.fluid.pixels[i] != 0.0f || !(a1.depth.pixels[i] < kInf)) continue;
            ++overlap;
            same += sameBits(both.color.pixels[i], a0.color.pixels[i]);
            redShift += (both.color.pixels[i].r - both.color.pixels[i].b) - (a0.color.pixels[i].r - a0.color.pixels[i].b);
        }
        ASSERT_GT(overlap, 300) << front;
        if (m.opacity == 1.0f) {
            EXPECT_EQ(same, overlap);
        } else {
            EXPECT_LT(same, overlap / 10);
            EXPECT_GT(redShift / overlap, 0.02);  // the lava behind reddens the clear water
        }
    }
}

// The composite follows depth, not the index: swapping the fluid indices
// together with their materials gives the same colour, depth and normals.
TEST(SeveralFluids, SwappingIndicesAndMaterialsTogetherChangesNothing) {
    Bodies b;
    b.add(ballOfParticles({0.0f, 0.08f, 0.05f}, 0.05f, 2.0f * kR), 0);
    b.add(block(-0.08f, -0.02f), 1);
    b.add(block(0.1f, 0.0f), 2);
    RenderSettings s = settingsFor(b, {0.0f, 0.08f, 0.0f});
    s.fluidMaterials = {preset("water"), preset("lava"), preset("milk")};
    const Aovs a = render(b.view(), s);
    Bodies swapped = b;
    for (std::int64_t& k : swapped.fluid) k = 2 - k;
    s.fluidMaterials = {preset("milk"), preset("lava"), preset("water")};
    const Aovs c = render(swapped.view(), s);
    EXPECT_EQ(differingBits(a.color, c.color), 0);
    EXPECT_EQ(differingBits(a.depth, c.depth), 0);
    EXPECT_EQ(differingBits(a.normal, c.normal), 0);
    EXPECT_EQ(differingBits(a.thickness, c.thickness), 0);
    int fluid = 0;
    for (std::size_t i = 0; i < a.fluid.size(); ++i) {
        if (a.fluid.pixels[i] < 0.0f) {
            EXPECT_EQ(c.fluid.pixels[i], -1.0f);
            continue;
        }
        ++fluid;
        EXPECT_EQ(c.fluid.pixels[i], 2.0f - a.fluid.pixels[i]);
    }
    EXPECT_GT(fluid, 1000);
}

// With the surface noise on, several fluids' noise AOV is each pixel's
// nearest fluid's own noise: where one fluid is seen, bit for bit that fluid's
// noise rendered alone (the same particles, ids and surface); the noise view
// shows it.
TEST(SeveralFluids, TheNoiseAovIsTheNearestFluidsOwn) {
    Bodies b;
    b.add(block(-0.2f, 0.0f), 0);
    b.add(block(0.04f, 0.0f), 1);
    std::vector<std::int64_t> ids(b.positions.size());
    for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = std::int64_t(7 * i + 3);
    RenderSettings s = settingsFor(b, {0.0f, 0.08f, 0.0f});
    s.fluidMaterials = {preset("water"), preset("lava")};
    s.noise.enabled = true;
    ParticleView all = b.view();
    all.id = StridedView<std::int64_t>(std::span<const std::int64_t>(ids));
    const Aovs both = render(all, s);
    ASSERT_EQ(both.noise.size(), both.fluid.size());
    ASSERT_EQ(both.foam.size(), both.fluid.size());
    for (int k : {0, 1}) {
        std::vector<glm::vec3> p;
        std::vector<std::int64_t> id;
        for (std::size_t i = 0; i < b.positions.size(); ++i)
            if (b.fluid[i] == k) p.push_back(b.positions[i]), id.push_back(ids[i]);
        ParticleView v{std::span<const glm::vec3>(p)};
        v.id = StridedView<std::int64_t>(std::span<const std::int64_t>(id));
        RenderSettings t = s;
        t.shading.material = s.fluidMaterials[std::size_t(k)];
        t.fluidMaterials.clear();
        const Aovs alone = render(v, t);
        int seen = 0, differ = 0, nonzero = 0;
        for (std::size_t i = 0; i < both.noise.size(); ++i) {
            if (both.fluid.pixels[i] != float(k)) continue;
            ++seen;
            nonzero += both.noise.pixels[i] != 0.0f;
            differ += std::memcmp(&both.noise.pixels[i], &alone.noise.pixels[i], sizeof(float)) != 0;
        }
        EXPECT_GT(seen, 500) << k;
        EXPECT_GT(nonzero, seen / 2) << k;
        EXPECT_EQ(differ, 0) << k;
    }
    for (std::size_t i = 0; i < both.noise.size(); ++i)
        if (both.fluid.pixels[i] < 0.0f) {
            EXPECT_EQ(both.noise.pixels[i], 0.0f);
        }
    s.view = View::Noise;
    s.colorOnly = true;
    EXPECT_FALSE(render(all, s).color.empty());
}

// One fluid index in the whole frame: the single-fluid path with that
// fluid's material, the fluid AOV its index wherever there is fluid; the
// fluid-id view colours each fluid on its own.
TEST(SeveralFluids, OneFluidIndexAndTheFluidIdView) {
    Bodies b;
    b.add(block(-0.08f, 0.0f), 2);
    RenderSettings s = settingsFor(b, {0.0f, 0.08f, 0.0f});
    s.fluidMaterials = {preset("water"), preset("water"), preset("lava")};
    const Aovs a = render(b.view(), s);
    RenderSettings plain = s;
    plain.fluidMaterials.clear();
    plain.shading.material = preset("lava");
    const std::vector<glm::vec3> p = b.only(2);
    const Aovs ref = render(std::span<const glm::vec3>(p), plain);
    EXPECT_EQ(differingBits(a.color, ref.color), 0);
    EXPECT_TRUE(ref.fluid.empty());  // no fluid index, no fluid AOV
    ASSERT_EQ(a.fluid.size(), a.depth.size());
    for (std::size_t i = 0; i < a.fluid.size(); ++i) EXPECT_EQ(a.fluid.pixels[i], a.depth.pixels[i] < kInf ? 2.0f : -1.0f);
    Bodies two = b;
    two.add(block(0.04f, 0.0f), 0);
    s.view = View::FluidId;
    const Aovs v = render(two.view(), s);
    const Aovs id = [&] { RenderSettings t = s; t.view = View::Final; return render(two.view(), t); }();
    glm::vec4 colourOf[3] = {};
    for (std::size_t i = 0; i < v.color.size(); ++i) {
        const int k = int(id.fluid.pixels[i]);
        if (k < 0) {
            EXPECT_EQ(v.color.pixels[i].a, 0.0f);
            continue;
        }
        if (colourOf[k].a == 0.0f) colourOf[k] = v.color.pixels[i];
        EXPECT_EQ(v.color.pixels[i], colourOf[k]);
    }
    EXPECT_NE(colourOf[0], colourOf[2]);
}

TEST(SeveralFluids, Errors) {
    Bodies b;
    b.add(block(-0.08f, 0.0f), 0);
    b.add(block(0.04f, 0.0f), 1);
    RenderSettings s = settingsFor(b, {0.0f, 0.08f, 0.0f});
    auto fails = [&](const Bodies& bodies, const RenderSettings& t, const std::string& words) {
        auto r = renderFrame(bodies.view(), t);
        ASSERT_FALSE(r.ok()) << words;
        EXPECT_NE(r.error().message.find(words), std::string::npos) << r.error().message;
    };
    Bodies bad = b;
    bad.fluid[5] = kMaxFluids;
    fails(bad, s, "particle 5 has fluid index 4: expected 0 to 3");
    bad.fluid[5] = -1;
    fails(bad, s, "particle 5 has fluid index -1");
    RenderSettings id = s;
    id.view = View::FluidId;
    auto r = renderFrame(std::span<const glm::vec3>(b.positions), id);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("fluid-id view needs a fluid index"), std::string::npos);
}

// The two-fluid test frame is the real frame 21 with its `phase` split at
// the middle of the x range (tests/data/splishsplash/two_fluids/README.md).
TEST(SeveralFluids, TheTwoFluidFrameIsFrame21Split) {
    auto a = readParticles(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
    auto b = readParticles(testData("splishsplash/two_fluids/ParticleData_Fluid_21_phase.bgeo"));
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_EQ(a->positions, b->positions);
    const Attribute* phase = b->find("phase");
    ASSERT_NE(phase, nullptr);
    ASSERT_EQ(phase->ints.size(), b->size());
    float lo = kInf, hi = -kInf;
    for (const glm::vec3& p : b->positions) lo = std::min(lo, p.x), hi = std::max(hi, p.x);
    int ones = 0;
    for (std::size_t i = 0; i < b->size(); ++i) {
        EXPECT_EQ(phase->ints[i], b->positions[i].x < 0.5f * (lo + hi) ? 0 : 1);
        ones += int(phase->ints[i]);
    }
    EXPECT_GT(ones, 1000);
    EXPECT_LT(ones, int(b->size()) - 1000);
    for (const char* name : {"id", "velocity", "density"}) {
        const Attribute *x = a->find(name), *y = b->find(name);
        ASSERT_TRUE(x && y) << name;
        EXPECT_EQ(x->floats, y->floats) << name;
        EXPECT_EQ(x->ints, y->ints) << name;
    }
}
}  // namespace fluids_test_local
