// Whitewater (Ihmsen et al. 2012; src/sim/whitewater_ihmsen2012.cpp): each
// potential against a configuration whose answer is known (rest, rigid
// motion, approach and separation, an expanding and a shrinking ball), the
// classification against lattice neighbour counts, each type's motion against
// its equation, the expected number made, the cap, the frame-interval
// estimate and the whole generator on the real SPlisHSPlasH sequence
// (data/demo, small dam break frames 19-23, 15 fps): the same particles for
// any thread count, and spray above the bubbles.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "meniscus/io.h"
#include "meniscus/whitewater.h"
#include "test_util.h"

namespace whitewater_test_local {

using namespace meniscus;
using namespace meniscus::sim;

namespace {

constexpr float kR = 0.025f;  // particle radius; the lattice spacing is 2 r, h = 4 r

// A cubic lattice of n^3 particles of spacing 2 r from `origin`.
std::vector<glm::vec3> lattice(glm::ivec3 n, glm::vec3 origin = glm::vec3(0.0f)) {
    return test::jitteredBlock(n, 2.0f * kR, 0.0f, origin);
}

struct Fluid {
    std::vector<glm::vec3> x, v;
    ParticleView view() const {
        ParticleView pv{std::span<const glm::vec3>(x)};
        pv.velocity = StridedView<glm::vec3>(std::span<const glm::vec3>(v));
        return pv;
    }
};

Fluid block(glm::ivec3 n, glm::vec3 velocity, glm::vec3 origin = glm::vec3(0.0f)) {
    Fluid f;
    f.x = lattice(n, origin);
    f.v.assign(f.x.size(), velocity);
    return f;
}

std::size_t indexNear(const std::vector<glm::vec3>& x, glm::vec3 p) {
    std::size_t best = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
        if (glm::length(x[i] - p) < glm::length(x[best] - p)) best = i;
    return best;
}

float maxOf(const std::vector<float>& v) { return v.empty() ? 0.0f : *std::max_element(v.begin(), v.end()); }

TEST(WhitewaterPotentials, AtRestEverythingIsZero) {
    const Fluid f = block({8, 8, 8}, glm::vec3(0.0f));
    WhitewaterParams p;
    p.supportRadii = 3.9f;  // no lattice pair at exactly h, where rounding decides
    auto pot = computePotentials(f.view(), kR, p);
    ASSERT_TRUE(pot.ok()) << pot.error().describe();
    EXPECT_EQ(maxOf(pot->trappedAir), 0.0f);
    EXPECT_EQ(maxOf(pot->waveCrest), 0.0f);
    EXPECT_EQ(maxOf(pot->energy), 0.0f);
    // Lattice counts within h = 1.95 spacings: 26 inside, 17 on a face, 7 at a corner.
    EXPECT_EQ(pot->neighbours[indexNear(f.x, glm::vec3(0.175f))], 26u);
    EXPECT_EQ(pot->neighbours[indexNear(f.x, glm::vec3(0.175f, 0.175f, 0.0f))], 17u);
    EXPECT_EQ(pot->neighbours[0], 7u);
}

TEST(WhitewaterPotentials, RigidMotionTrapsNoAirAndCarriesItsEnergy) {
    const glm::vec3 u(1.5f, -0.5f, 2.0f);
    const Fluid f = block({6, 6, 6}, u);
    auto pot = computePotentials(f.view(), kR, WhitewaterParams{});
    ASSERT_TRUE(pot.ok());
    EXPECT_EQ(maxOf(pot->trappedAir), 0.0f);
    for (float e : pot->energy) EXPECT_FLOAT_EQ(e, 0.5f * glm::dot(u, u));
}

// Two blocks 1 spacing apart moving toward each other trap air at their
// faces (eq. 2's 1 - v^_ij . x^_ij is 2 for a pair head-on); moving apart,
// only the pairs off the axis count (1 - cos of their angle), far less.
TEST(WhitewaterPotentials, TrappedAirWhereBlocksApproachNotWhereTheySeparate) {
    float faceValue[2] = {0.0f, 0.0f};
    for (float sign : {1.0f, -1.0f}) {
        Fluid a = block({4, 6, 6}, glm::vec3(sign * 2.0f, 0, 0));
        const Fluid b = block({4, 6, 6}, glm::vec3(-sign * 2.0f, 0, 0), glm::vec3(8.0f * kR, 0, 0));
        a.x.insert(a.x.end(), b.x.begin(), b.x.end());
        a.v.insert(a.v.end(), b.v.begin(), b.v.end());
        auto pot = computePotentials(a.view(), kR, WhitewaterParams{});
        ASSERT_TRUE(pot.ok());
        const std::size_t face = indexNear(a.x, glm::vec3(6.0f * kR, 0.125f, 0.125f));
        faceValue[sign > 0 ? 0 : 1] = pot->trappedAir[face];
        EXPECT_EQ(pot->trappedAir[indexNear(a.x, glm::vec3(0.0f, 0.125f, 0.125f))], 0.0f);  // far from the other block
    }
    // Approaching, each cross pair adds |v_ij| (1 + cos) W~ with |v_ij| = 4 m/s.
    EXPECT_GT(faceValue[0], 4.0f);
    EXPECT_GT(faceValue[0], 4.0f * faceValue[1]);
}

// A ball of lattice particles: its surface is curved. Expanding (every
// particle moving along its outward normal) it is a crest everywhere; the same
// ball shrinking moves against its normals: no crest (eq. 7's delta).
TEST(WhitewaterPotentials, WaveCrestOnAnExpandingBallNotAShrinkingOne) {
    Fluid f;
    const glm::vec3 c(0.25f);
    for (const glm::vec3& p : lattice({11, 11, 11}))
        if (glm::length(p - c) <= 0.25f) f.x.push_back(p);
    for (float sign : {1.0f, -1.0f}) {
        f.v.clear();
        for (const glm::vec3& p : f.x) {
            const glm::vec3 d = p - c;
            f.v.push_back(glm::length(d) > 0.0f ? sign * 2.0f * glm::normalize(d) : glm::vec3(0.0f));
        }
        auto pot = computePotentials(f.view(), kR, WhitewaterParams{});
        ASSERT_TRUE(pot.ok());
        std::size_t crests = 0;
        for (float k : pot->waveCrest) crests += k > 0.1f;
        if (sign > 0) EXPECT_GT(crests, f.x.size() / 4) << "of " << f.x.size();
        else EXPECT_EQ(crests, 0u);
    }
    // A flat face moving up along its normal has (almost) no curvature.
    const Fluid slab = block({10, 3, 10}, glm::vec3(0, 2, 0));
    WhitewaterParams p;
    p.supportRadii = 3.9f;
    auto flat = computePotentials(slab.view(), kR, p);
    ASSERT_TRUE(flat.ok());
    EXPECT_LT(flat->waveCrest[indexNear(slab.x, glm::vec3(0.225f, 0.1f, 0.225f))], 0.05f);
}

TEST(WhitewaterClassification, ByFluidNeighbourCount) {
    const WhitewaterParams p;
    EXPECT_EQ(classifyDiffuse(0, p), DiffuseType::Spray);
    EXPECT_EQ(classifyDiffuse(5, p), DiffuseType::Spray);
    EXPECT_EQ(classifyDiffuse(6, p), DiffuseType::Foam);
    EXPECT_EQ(classifyDiffuse(20, p), DiffuseType::Foam);
    EXPECT_EQ(classifyDiffuse(21, p), DiffuseType::Bubble);
}

DiffuseParticles one(glm::vec3 x, glm::vec3 v, float life) {
    DiffuseParticles d;
    d.positions = {x};
    d.velocities = {v};
    d.type = {DiffuseType::Foam};
    d.lifetime = {life};
    d.id = {7};
    return d;
}

// Over a block moving at u: a particle inside is a bubble (26 neighbours),
// one a spacing above the top face is foam (9), one far above is spray (0);
// each moves by its own equation.
TEST(WhitewaterAdvection, EachTypeMovesByItsEquation) {
    const glm::vec3 u(0.5f, 0.0f, -0.25f);
    const Fluid f = block({10, 10, 10}, u);
    WhitewaterParams p;
    const float dt = 0.02f;
    Bounds box;
    box.extend(glm::vec3(-10.0f)), box.extend(glm::vec3(10.0f));

    const glm::vec3 v0(0.1f, 0.3f, 0.0f);
    DiffuseParticles spray = one({0.2f, 1.5f, 0.2f}, v0, 3.0f);
    ASSERT_TRUE(advectDiffuse(spray, f.view(), kR, p, dt, box).ok());
    ASSERT_EQ(spray.size(), 1u);
    EXPECT_EQ(spray.type[0], DiffuseType::Spray);
    const glm::vec3 vs = v0 + dt * p.gravity;
    EXPECT_NEAR(glm::length(spray.velocities[0] - vs), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(spray.positions[0] - (glm::vec3(0.2f, 1.5f, 0.2f) + dt * vs)), 0.0f, 1e-6f);
    EXPECT_EQ(spray.lifetime[0], 3.0f);  // spray does not age

    const glm::vec3 top(0.2f, 0.45f + 2.0f * kR, 0.2f);  // one spacing above the top layer (y = 0.45)
    DiffuseParticles foam = one(top, glm::vec3(0.0f), 3.0f);
    ASSERT_TRUE(advectDiffuse(foam, f.view(), kR, p, dt, box).ok());
    EXPECT_EQ(foam.type[0], DiffuseType::Foam);
    EXPECT_NEAR(glm::length(foam.velocities[0] - u), 0.0f, 1e-5f);  // the fluid's (uniform) velocity
    EXPECT_NEAR(glm::length(foam.positions[0] - (top + dt * u)), 0.0f, 1e-6f);
    EXPECT_FLOAT_EQ(foam.lifetime[0], 3.0f - dt);

    const glm::vec3 inside(0.2f, 0.2f, 0.2f);
    DiffuseParticles bubble = one(inside, v0, 3.0f);
    ASSERT_TRUE(advectDiffuse(bubble, f.view(), kR, p, dt, box).ok());
    EXPECT_EQ(bubble.type[0], DiffuseType::Bubble);
    const glm::vec3 vb = v0 - dt * p.buoyancy * p.gravity + p.drag * (u - v0);
    EXPECT_NEAR(glm::length(bubble.velocities[0] - vb), 0.0f, 1e-5f);
    EXPECT_GT(bubble.velocities[0].y, v0.y);  // buoyancy lifts it

    // Foam at the end of its life, and anything leaving the box, dissolve.
    DiffuseParticles dying = one(top, glm::vec3(0.0f), 0.5f * dt);
    ASSERT_TRUE(advectDiffuse(dying, f.view(), kR, p, dt, box).ok());
    EXPECT_EQ(dying.size(), 0u);
    Bounds small;
    small.extend(glm::vec3(-0.1f)), small.extend(glm::vec3(1.0f));
    DiffuseParticles leaving = one({0.2f, 1.5f, 0.2f}, v0, 3.0f);
    ASSERT_TRUE(advectDiffuse(leaving, f.view(), kR, p, dt, small).ok());
    EXPECT_EQ(leaving.size(), 0u);
}

// Saturated potentials (limits far below the values) make exactly
// scale (k_ta + k_wc) dt particles per fluid particle with at least 15
// neighbours; a fractional expectation is met on average (stochastic rounding).
TEST(WhitewaterGeneration, MakesTheExpectedNumber) {
    Fluid f = block({12, 12, 12}, glm::vec3(0.0f));
    for (std::size_t i = 0; i < f.x.size(); ++i)  // scrambled velocities: relative motion everywhere
        f.v[i] = glm::vec3(float((i * 7919u) % 17u) - 8.0f, float((i * 104729u) % 13u) - 6.0f, 3.0f);
    auto pot = computePotentials(f.view(), kR, WhitewaterParams{});
    ASSERT_TRUE(pot.ok());
    std::size_t generating = 0;
    for (std::size_t i = 0; i < f.x.size(); ++i) generating += pot->neighbours[i] >= 15 && pot->trappedAir[i] > 1e-3f;
    ASSERT_GT(generating, 1000u);

    WhitewaterParams p;
    p.trappedAirMin = 0.0f, p.trappedAirMax = 1e-3f;
    p.waveCrestMin = 0.0f, p.waveCrestMax = 1e9f;  // never reached: I_wc ~ 0
    p.energyMin = 0.0f, p.energyMax = 1e-3f;
    p.waveCrestRate = 0.0f;
    for (float perParticle : {3.0f, 0.25f}) {
        p.scale = perParticle / 0.1f;
        auto gen = WhitewaterGenerator::create(p, kR);
        ASSERT_TRUE(gen.ok()) << gen.error().describe();
        auto s = gen->step(f.view(), 0.1);
        ASSERT_TRUE(s.ok()) << s.error().describe();
        if (perParticle == 3.0f) {
            EXPECT_EQ(s->generated, 3 * generating);
        } else {
            const double mean = 0.25 * double(generating), sd = std::sqrt(double(generating) * 0.25 * 0.75);
            EXPECT_NEAR(double(s->generated), mean, 4.0 * sd);
        }
    }
    // The cap holds: never more alive or waiting than maxParticles.
    p.scale = 30.0f;
    p.maxParticles = 500;
    auto gen = WhitewaterGenerator::create(p, kR);
    ASSERT_TRUE(gen.ok());
    for (int k = 0; k < 3; ++k) {
        auto s = gen->step(f.view(), 0.1);
        ASSERT_TRUE(s.ok());
        EXPECT_LE(gen->particles().size() + s->generated, 500u);
    }
}

TEST(WhitewaterGeneration, AColumnAtRestMakesNothing) {
    const Fluid f = block({10, 10, 10}, glm::vec3(0.0f));
    std::vector<PotentialMaxima> maxima{maximaOf(*computePotentials(f.view(), kR, WhitewaterParams{}))};
    const WhitewaterParams p = withAutomaticLimits(WhitewaterParams{}, maxima);
    auto gen = WhitewaterGenerator::create(p, kR);
    ASSERT_TRUE(gen.ok()) << gen.error().describe();
    for (int k = 0; k < 5; ++k) {
        auto s = gen->step(f.view(), 1.0 / 30.0);
        ASSERT_TRUE(s.ok());
        EXPECT_EQ(s->generated, 0u);
    }
    EXPECT_EQ(gen->particles().size(), 0u);
}

TEST(WhitewaterLimits, AutomaticFromTheMeanOfTheMaxima) {
    WhitewaterParams p;
    p.energyMin = 1.0f, p.energyMax = 9.0f;  // given: kept
    const WhitewaterParams a = withAutomaticLimits(p, {{2.0, 4.0, 100.0}, {4.0, 8.0, 300.0}});
    EXPECT_FLOAT_EQ(a.trappedAirMax, 3.0f);
    EXPECT_FLOAT_EQ(a.trappedAirMin, 0.3f);
    EXPECT_FLOAT_EQ(a.waveCrestMax, 6.0f);
    EXPECT_FLOAT_EQ(a.waveCrestMin, 0.6f);
    EXPECT_EQ(a.energyMin, 1.0f);
    EXPECT_EQ(a.energyMax, 9.0f);
    EXPECT_FALSE(WhitewaterGenerator::create(p, kR).ok());  // automatic limits not resolved yet
}

TEST(WhitewaterErrors, BadInputIsAnErrorNotACrash) {
    Fluid f = block({4, 4, 4}, glm::vec3(1.0f));
    ParticleView noVelocity{std::span<const glm::vec3>(f.x)};
    EXPECT_FALSE(computePotentials(noVelocity, kR, WhitewaterParams{}).ok());
    EXPECT_FALSE(computePotentials(f.view(), 0.0f, WhitewaterParams{}).ok());
    WhitewaterParams bad;
    bad.drag = 2.0f;
    EXPECT_NE(checkWhitewaterParams(bad).find("drag"), std::string::npos);
    WhitewaterParams p = withAutomaticLimits(WhitewaterParams{}, {{1.0, 1.0, 1.0}});
    auto gen = WhitewaterGenerator::create(p, kR);
    ASSERT_TRUE(gen.ok());
    EXPECT_FALSE(gen->step(noVelocity, 0.1).ok());
    EXPECT_FALSE(gen->step(f.view(), 0.0).ok());
}

// ---- The real sequence ----------------------------------------------------

std::vector<ParticleSet> realFrames() {
    std::vector<ParticleSet> frames;
    for (int k = 19; k <= 23; ++k) {
        auto set = readParticles(test::repoData("demo/ParticleData_Fluid_" + std::to_string(k) + ".bgeo"));
        EXPECT_TRUE(set.ok()) << set.error().describe();
        if (set) frames.push_back(std::move(*set));
    }
    return frames;
}

// SPlisHSPlasH wrote these at 15 frames per second.
TEST(WhitewaterReal, FrameIntervalFromTheParticlesMotion) {
    const auto frames = realFrames();
    ASSERT_EQ(frames.size(), 5u);
    for (std::size_t k = 0; k + 1 < frames.size(); ++k) {
        auto dt = estimateFrameInterval(ParticleView::of(frames[k]), ParticleView::of(frames[k + 1]));
        ASSERT_TRUE(dt.ok()) << dt.error().describe();
        EXPECT_NEAR(*dt, 1.0 / 15.0, 0.05 / 15.0) << "frames " << 19 + k << " to " << 20 + k;
    }
}

DiffuseParticles runReal(const std::vector<ParticleSet>& frames, int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    std::vector<PotentialMaxima> maxima;
    for (const ParticleSet& f : frames) maxima.push_back(maximaOf(*computePotentials(ParticleView::of(f), kR, {})));
    auto gen = WhitewaterGenerator::create(withAutomaticLimits(WhitewaterParams{}, maxima), kR);
    EXPECT_TRUE(gen.ok());
    for (const ParticleSet& f : frames) EXPECT_TRUE(gen->step(ParticleView::of(f), 1.0 / 15.0).ok());
    return gen->particles();
}

TEST(WhitewaterReal, SameParticlesForAnyThreadCountEachTypeInItsPlace) {
    const auto frames = realFrames();
    ASSERT_EQ(frames.size(), 5u);
    const DiffuseParticles one = runReal(frames, 1), two = runReal(frames, 2);
    ASSERT_GT(one.size(), 500u);
    ASSERT_EQ(one.size(), two.size());
    EXPECT_EQ(std::memcmp(one.positions.data(), two.positions.data(), one.size() * sizeof(glm::vec3)), 0);
    EXPECT_EQ(one.id, two.id);
    EXPECT_EQ(one.type, two.type);
    // Every type is there, each where its class says: spray away from the
    // fluid of the last frame, foam at its surface, bubbles inside.
    const std::vector<glm::vec3>& fluid = frames.back().positions;
    double near[3] = {0.0, 0.0, 0.0};
    std::size_t count[3] = {0, 0, 0};
    for (std::size_t i = 0; i < one.size(); ++i) {
        std::size_t within = 0;
        for (const glm::vec3& q : fluid) within += glm::length(q - one.positions[i]) < 4.0f * kR;
        near[int(one.type[i])] += double(within);
        ++count[int(one.type[i])];
    }
    for (int t = 0; t < 3; ++t) {
        ASSERT_GT(count[t], 10u) << "type " << t;
        near[t] /= double(count[t]);
    }
    const int foam = int(DiffuseType::Foam), spray = int(DiffuseType::Spray), bubble = int(DiffuseType::Bubble);
    EXPECT_LT(near[spray], near[foam]);
    EXPECT_LT(near[foam], near[bubble]);
    // Ids are unique.
    std::vector<std::int64_t> ids = one.id;
    std::sort(ids.begin(), ids.end());
    EXPECT_EQ(std::adjacent_find(ids.begin(), ids.end()), ids.end());
}

TEST(WhitewaterReal, WrittenAndReadBack) {
    const auto frames = realFrames();
    const DiffuseParticles d = runReal(frames, 2);
    const auto path = test::tempDir() / "diffuse.bgeo";
    ASSERT_TRUE(writeParticles(path, toParticleSet(d)).ok());
    auto back = readParticles(path);
    ASSERT_TRUE(back.ok()) << back.error().describe();
    ASSERT_EQ(back->size(), d.size());
    const Attribute* type = back->find(kAttrDiffuseType);
    ASSERT_NE(type, nullptr);
    ASSERT_EQ(type->count(), d.size());
    for (std::size_t i = 0; i < d.size(); ++i) ASSERT_EQ(type->ints[i], std::int64_t(d.type[i]));
    EXPECT_NE(back->find(kAttrLifetime), nullptr);
    EXPECT_NE(back->find(kAttrVelocity), nullptr);
}

}  // namespace
}  // namespace whitewater_test_local
