// Radius estimate (half the median nearest-neighbour distance), bounds,
// attribute statistics and NaN removal.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "meniscus/particles.h"

using namespace meniscus;

namespace {

std::vector<glm::vec3> jitteredLattice(int nx, int ny, int nz, float spacing, float jitter, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-jitter, jitter);
    std::vector<glm::vec3> pts;
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x)
                pts.push_back(spacing * glm::vec3(x, y, z) + glm::vec3(u(rng), u(rng), u(rng)));
    return pts;
}

// Brute-force O(N²) reference: the (N-1)/2-th smallest nearest-neighbour distance.
float bruteMedianNN(const std::vector<glm::vec3>& pts) {
    std::vector<float> nn(pts.size(), std::numeric_limits<float>::infinity());
    for (std::size_t i = 0; i < pts.size(); ++i)
        for (std::size_t j = 0; j < pts.size(); ++j)
            if (i != j) {
                const float d = glm::length(pts[i] - pts[j]);
                if (d > 0.0f) nn[i] = std::min(nn[i], d);
            }
    std::sort(nn.begin(), nn.end());
    return nn[(nn.size() - 1) / 2];
}

}  // namespace

TEST(Particles, RadiusIsHalfTheLatticeSpacing) {
    const auto pts = jitteredLattice(30, 20, 25, 0.02f, 0.0f, 1);
    const RadiusEstimate est = estimateRadius(pts);
    EXPECT_FALSE(est.fallback);
    EXPECT_NEAR(est.radius, 0.01f, 1e-6f);
}

TEST(Particles, RadiusMatchesBruteForceOnRandomSets) {
    for (unsigned seed : {1u, 2u, 3u}) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        std::vector<glm::vec3> pts(1500);
        for (auto& p : pts) p = {u(rng) * 3.0f, u(rng), u(rng) * 0.5f};
        const RadiusEstimate est = estimateRadius(pts);
        EXPECT_FLOAT_EQ(est.medianNeighbourDistance, bruteMedianNN(pts)) << "seed " << seed;
        EXPECT_FLOAT_EQ(est.radius, 0.5f * est.medianNeighbourDistance);
    }
}

TEST(Particles, RadiusOfAFlatSheetAndASparseSpray) {
    // A single layer (zero thickness in y): the grid must cope with a flat box.
    const auto sheet = jitteredLattice(60, 1, 60, 0.05f, 0.0f, 0);
    EXPECT_NEAR(estimateRadius(sheet).radius, 0.025f, 1e-6f);
    // A dense block plus far-away spray: the median still reflects the block.
    auto pts = jitteredLattice(20, 20, 20, 0.01f, 0.001f, 4);
    for (int i = 0; i < 50; ++i) pts.push_back({5.0f + float(i), 3.0f, -2.0f});
    const float r = estimateRadius(pts).radius;
    EXPECT_GT(r, 0.004f);
    EXPECT_LT(r, 0.0055f);
}

TEST(Particles, RadiusIsScaleInvariant) {
    auto pts = jitteredLattice(15, 15, 15, 0.02f, 0.004f, 9);
    const float r1 = estimateRadius(pts).radius;
    for (auto& p : pts) p *= 10.0f;
    EXPECT_NEAR(estimateRadius(pts).radius, 10.0f * r1, 1e-5f * 10.0f);
}

TEST(Particles, RadiusIgnoresCoincidentPointsAndFallsBackWhenAlone) {
    std::vector<glm::vec3> pts{{0, 0, 0}, {0, 0, 0}, {0.1f, 0, 0}, {0.1f, 0, 0}};
    EXPECT_NEAR(estimateRadius(pts).radius, 0.05f, 1e-7f);
    const std::vector<glm::vec3> one{{1, 2, 3}};
    const RadiusEstimate est = estimateRadius(one);
    EXPECT_TRUE(est.fallback);
    EXPECT_GT(est.radius, 0.0f);
}

TEST(Particles, BoundsOfPositions) {
    const std::vector<glm::vec3> pts{{1, -2, 3}, {-1, 5, 0}, {0, 0, 7}};
    const Bounds b = computeBounds(pts);
    EXPECT_EQ(b.min, glm::vec3(-1, -2, 0));
    EXPECT_EQ(b.max, glm::vec3(1, 5, 7));
    EXPECT_TRUE(computeBounds({}).empty());
}

TEST(Particles, AttributeStatsMinMedianMax) {
    ParticleSet s;
    s.positions.resize(5);
    s.attributes.push_back({"density", AttributeType::Float, 1, {3, 1, 4, 1, 5}, {}});
    s.attributes.push_back({"id", AttributeType::Int, 1, {}, {4, 3, 2, 1, 0}});
    auto d = attributeStats(s, "density");
    ASSERT_TRUE(d);
    EXPECT_EQ(d->min, 1);
    EXPECT_EQ(d->median, 3);
    EXPECT_EQ(d->max, 5);
    s.positions.resize(4);
    s.attributes[0].floats = {1, 2, 3, 10};
    EXPECT_EQ(attributeStats(s, "density")->median, 2.5);  // even count: mean of the middle two
    EXPECT_FALSE(attributeStats(s, "velocity"));
}

TEST(Particles, DropNonFiniteKeepsAttributesAligned) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    ParticleSet s;
    s.positions = {{0, 0, 0}, {nan, 0, 0}, {1, 1, 1}, {0, inf, 0}, {2, 2, 2}};
    s.attributes.push_back({"velocity", AttributeType::Float, 3, {0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4}, {}});
    s.attributes.push_back({"id", AttributeType::Int, 1, {}, {10, 11, 12, 13, 14}});
    EXPECT_EQ(dropNonFinite(s), 2u);
    ASSERT_EQ(s.size(), 3u);
    EXPECT_EQ(s.positions[1], glm::vec3(1, 1, 1));
    EXPECT_EQ(s.find("id")->ints, (std::vector<std::int64_t>{10, 12, 14}));
    EXPECT_EQ(s.find("velocity")->floats, (std::vector<float>{0, 0, 0, 2, 2, 2, 4, 4, 4}));
}
