// TurbulenceTracker (src/core/turbulence.h): the noise amplitude factor of
// particles whose velocity jumps between frames, matched by id.
#include <algorithm>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "core/turbulence.h"

namespace turbulence_test_local {

using namespace meniscus;

namespace {
TurbulenceParams params() {
    TurbulenceParams p;
    p.tauMps = 1.0f;
    p.boost = 3.0f;
    p.holdFrames = 4;
    return p;
}
}  // namespace

TEST(Turbulence, AJumpBoostsThenFadesOverTheHold) {
    TurbulenceTracker t(params());
    const std::vector<std::int64_t> ids{10, 20};
    // Frame 0: nothing known. Frame 1: particle 20 jumps by 2 m/s (> tau = 1);
    // 10 moves steadily. Then both steady.
    std::vector<std::vector<glm::vec3>> v{{{0, 0, 0}, {0, 0, 0}}, {{0, 0, 0}, {2, 0, 0}}};
    for (int k = 0; k < 6; ++k) v.push_back({{0, 0, 0}, {2, 0, 0}});
    const std::vector<float> want20{1.0f, 3.0f, 2.5f, 2.0f, 1.5f, 1.0f, 1.0f, 1.0f};
    for (std::size_t f = 0; f < v.size(); ++f) {
        const std::vector<float> a = t.update(ids, v[f]);
        ASSERT_EQ(a.size(), 2u);
        EXPECT_EQ(a[0], 1.0f) << "frame " << f;
        EXPECT_FLOAT_EQ(a[1], want20[f]) << "frame " << f;
    }
    EXPECT_EQ(t.tracked(), 2u);
}

TEST(Turbulence, TheThresholdIsStrictAndAnotherJumpRestartsTheFade) {
    TurbulenceTracker t(params());
    const std::vector<std::int64_t> id{7};
    t.update(id, std::vector<glm::vec3>{{0, 0, 0}});
    EXPECT_EQ(t.update(id, std::vector<glm::vec3>{{1, 0, 0}})[0], 1.0f);  // |dv| = tau: not more than tau
    EXPECT_EQ(t.update(id, std::vector<glm::vec3>{{1, 0, 1.5f}})[0], 3.0f);
    EXPECT_EQ(t.update(id, std::vector<glm::vec3>{{1, 0, 1.5f}})[0], 2.5f);
    EXPECT_EQ(t.update(id, std::vector<glm::vec3>{{1, 1.2f, 1.5f}})[0], 3.0f);  // again: the fade restarts
}

// The particles' order in a frame does not matter, only their ids.
TEST(Turbulence, MatchedByIdWhateverTheOrder) {
    std::mt19937 rng(3);
    std::normal_distribution<float> g(0.0f, 1.0f);
    const std::size_t n = 500;
    std::vector<std::int64_t> ids(n);
    std::iota(ids.begin(), ids.end(), 1000);
    std::vector<std::vector<glm::vec3>> frames(5, std::vector<glm::vec3>(n));
    for (auto& f : frames)
        for (auto& v : f) v = {g(rng), g(rng), g(rng)};
    TurbulenceTracker inOrder(params()), shuffled(params());
    std::vector<std::size_t> perm(n);
    std::iota(perm.begin(), perm.end(), 0);
    int boosted = 0;
    for (const auto& f : frames) {
        std::shuffle(perm.begin(), perm.end(), rng);
        std::vector<std::int64_t> pid(n);
        std::vector<glm::vec3> pv(n);
        for (std::size_t k = 0; k < n; ++k) pid[k] = ids[perm[k]], pv[k] = f[perm[k]];
        const std::vector<float> a = inOrder.update(ids, f), b = shuffled.update(pid, pv);
        for (std::size_t k = 0; k < n; ++k) {
            ASSERT_EQ(b[k], a[perm[k]]);
            boosted += a[k] > 1.0f;
        }
    }
    EXPECT_GT(boosted, 500);  // random velocities of sd 1 m/s jump by more than 1 m/s most frames
}

// A particle that leaves the frame is forgotten: back, it is new (no boost
// from the jump between its last and its new velocity), and the tracker holds
// one frame's particles only.
TEST(Turbulence, AbsentParticlesAreForgotten) {
    TurbulenceTracker t(params());
    t.update(std::vector<std::int64_t>{1, 2, 3}, std::vector<glm::vec3>{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}});
    EXPECT_EQ(t.tracked(), 3u);
    t.update(std::vector<std::int64_t>{1}, std::vector<glm::vec3>{{0, 0, 0}});
    EXPECT_EQ(t.tracked(), 1u);
    const std::vector<float> a =
        t.update(std::vector<std::int64_t>{1, 2}, std::vector<glm::vec3>{{5, 0, 0}, {5, 0, 0}});
    EXPECT_EQ(a[0], 3.0f);
    EXPECT_EQ(a[1], 1.0f);
    t.reset();
    EXPECT_EQ(t.tracked(), 0u);
    EXPECT_EQ(t.update(std::vector<std::int64_t>{1}, std::vector<glm::vec3>{{0, 0, 0}})[0], 1.0f);
}
}  // namespace turbulence_test_local
