// Radius estimate (volume-equivalent radius of the bulk number density; half
// the median nearest-neighbour distance where there is no bulk), its range
// checks, bounds, attribute statistics and NaN removal.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/particle_view.h"
#include "test_util.h"

namespace particles_test_local {

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
    EXPECT_EQ(est.method, RadiusMethod::BulkDensity);
    EXPECT_NEAR(est.radius, 0.01f, 0.01f * 0.01f);  // 1%: the kernel sum over a lattice
    EXPECT_EQ(est.isolated, 0u);
}

TEST(Particles, RadiusMatchesBruteForceOnRandomSets) {
    for (unsigned seed : {1u, 2u, 3u}) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        std::vector<glm::vec3> pts(1500);
        for (auto& p : pts) p = {u(rng) * 3.0f, u(rng), u(rng) * 0.5f};
        const RadiusEstimate est = estimateRadius(pts);
        EXPECT_FLOAT_EQ(est.medianNeighbourDistance, bruteMedianNN(pts)) << "seed " << seed;
    }
}

TEST(Particles, RadiusOfAFlatSheetAndASparseSpray) {
    // A single layer (zero thickness in y): the grid must cope with a flat box.
    // No bulk to take a density of: half the nearest-neighbour distance.
    const auto sheet = jitteredLattice(60, 1, 60, 0.05f, 0.0f, 0);
    const RadiusEstimate s = estimateRadius(sheet);
    EXPECT_EQ(s.method, RadiusMethod::NearestNeighbour);
    EXPECT_NEAR(s.radius, 0.025f, 1e-6f);
    // A dense block plus far-away spray: the bulk is the block; the spray is isolated.
    auto pts = jitteredLattice(20, 20, 20, 0.01f, 0.001f, 4);
    for (int i = 0; i < 50; ++i) pts.push_back({5.0f + float(i), 3.0f, -2.0f});
    const RadiusEstimate est = estimateRadius(pts);
    EXPECT_EQ(est.method, RadiusMethod::BulkDensity);
    EXPECT_NEAR(est.radius, 0.005f, 0.03f * 0.005f);
    EXPECT_EQ(est.isolated, 50u);
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

// Regression: two points 1e-15 m apart made the grid's cell size underflow to 0
// and `cell *= 1.25` never ended.
TEST(Particles, RadiusOfATinySetEnds) {
    const std::vector<glm::vec3> pts{{0, 0, 0}, {1e-15f, 0, 0}};
    const RadiusEstimate est = estimateRadius(pts);
    EXPECT_EQ(est.method, RadiusMethod::NearestNeighbour);
    EXPECT_FLOAT_EQ(est.radius, 0.5e-15f);
    EXPECT_FALSE(checkRadius(est.radius).ok());  // and the pipeline refuses to render it
}

// Regression: one particle at x = 1e6 beside a 49^3 block at 0.01 m sized the
// grid to the whole bounds and turned the estimate into 0.05 m.
TEST(Particles, RadiusIgnoresAFarOutlier) {
    auto pts = jitteredLattice(49, 49, 49, 0.01f, 0.0f, 0);
    const float alone = estimateRadius(pts).radius;
    pts.push_back({1e6f, 0.0f, 0.0f});
    const RadiusEstimate est = estimateRadius(pts);
    EXPECT_EQ(est.method, RadiusMethod::BulkDensity);
    EXPECT_FLOAT_EQ(est.radius, alone);
    EXPECT_NEAR(est.radius, 0.005f, 0.01f * 0.005f);
    EXPECT_EQ(est.isolated, 1u);
    EXPECT_NE(est.describe().find("1 isolated particles ignored"), std::string::npos) << est.describe();
}

TEST(Particles, RadiusIsTheSameForAnyThreadCount) {
    const auto pts = jitteredLattice(40, 30, 30, 0.02f, 0.006f, 5);
    RadiusEstimate one, two;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = estimateRadius(pts);
    }
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
        two = estimateRadius(pts);
    }
    EXPECT_EQ(one.radius, two.radius);
    EXPECT_EQ(one.bulkNumberDensity, two.bulkNumberDensity);
}

// The default radius is within 10% of the radius each real data set was
// simulated with (SPlisHSPlasH's particleRadius; docs/radius.md).
TEST(Particles, DefaultRadiusOfEveryRealDataSetIsWithinTenPercent) {
    const std::pair<std::filesystem::path, float> sets[] = {
        {test::repoData("demo/ParticleData_Fluid_19.bgeo"), 0.025f},
        {test::repoData("demo/ParticleData_Fluid_20.bgeo"), 0.025f},
        {test::repoData("demo/ParticleData_Fluid_21.bgeo"), 0.025f},
        {test::repoData("demo/ParticleData_Fluid_22.bgeo"), 0.025f},
        {test::repoData("demo/ParticleData_Fluid_23.bgeo"), 0.025f},
        {test::repoData("dambreak_r0.01/ParticleData_Fluid_21.bgeo"), 0.01f},
        {test::testData("splishsplash/partio/ParticleData_Fluid_1.bgeo"), 0.025f},
        {test::testData("splishsplash/partio/ParticleData_Fluid_9.bgeo"), 0.025f},
        {test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"), 0.025f},
        {test::testData("splishsplash/partio/ParticleData_Fluid_61.bgeo"), 0.025f},
        {test::testData("splishsplash/vtk/ParticleData_Fluid_1.vtk"), 0.025f},
        {test::testData("splishsplash/vtk/ParticleData_Fluid_9.vtk"), 0.025f},
        {test::testData("splishsplash/vtk/ParticleData_Fluid_21.vtk"), 0.025f},
        {test::testData("splishsplash/vtk/ParticleData_Fluid_61.vtk"), 0.025f},
        {test::testData("vtu/fluid21_binary.vtu"), 0.025f},
        {test::testData("vtu/fluid21_ascii_first500.vtu"), 0.025f},
    };
    for (const auto& [path, trueRadius] : sets) {
        auto set = readParticles(path);
        ASSERT_TRUE(set.ok()) << set.error().describe();
        const RadiusEstimate est = defaultRadius(*set);
        EXPECT_EQ(est.method, RadiusMethod::BulkDensity) << path;
        EXPECT_NEAR(est.radius, trueRadius, 0.1f * trueRadius) << path << ": " << est.describe();
    }
}

TEST(Particles, DefaultRadiusReadsTheFilesOwnRadius) {
    ParticleSet s;
    s.positions = jitteredLattice(10, 10, 10, 0.02f, 0.0f, 0);
    EXPECT_EQ(defaultRadius(s).method, RadiusMethod::BulkDensity);
    s.attributes.push_back({"pscale", AttributeType::Float, 1, std::vector<float>(1000, 0.013f), {}});
    const RadiusEstimate est = defaultRadius(s);
    EXPECT_EQ(est.method, RadiusMethod::FileAttribute);
    EXPECT_FLOAT_EQ(est.radius, 0.013f);
    EXPECT_NE(est.describe().find("'pscale'"), std::string::npos) << est.describe();
    // An unusable value (0) is not taken.
    s.attributes[0].floats.assign(1000, 0.0f);
    EXPECT_EQ(defaultRadius(s).method, RadiusMethod::BulkDensity);
}

// A smoothing length h becomes each particle's radius h / (2 k); a file's own
// radius wins; floats only; k must be positive.
TEST(Particles, RadiusFromTheSmoothingLength) {
    ParticleSet s;
    s.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    auto none = addRadiusFromSmoothingLength(s, 1.2f);
    ASSERT_TRUE(none);
    EXPECT_EQ(*none, "");
    EXPECT_TRUE(s.attributes.empty());
    s.attributes.push_back({"hsml", AttributeType::Float, 1, {0.024f, 0.048f, 0.012f}, {}});
    auto h = addRadiusFromSmoothingLength(s, 1.2f);
    ASSERT_TRUE(h);
    EXPECT_EQ(*h, "hsml");
    const Attribute* r = s.find("radius");
    ASSERT_NE(r, nullptr);
    ASSERT_EQ(r->floats.size(), 3u);
    EXPECT_FLOAT_EQ(r->floats[0], 0.01f);
    EXPECT_FLOAT_EQ(r->floats[1], 0.02f);
    EXPECT_FLOAT_EQ(r->floats[2], 0.005f);
    EXPECT_EQ(ParticleView::of(s).radius[1], r->floats[1]);  // what the renderer draws
    const RadiusEstimate est = defaultRadius(s);
    EXPECT_EQ(est.method, RadiusMethod::FileAttribute);
    EXPECT_FLOAT_EQ(est.radius, 0.01f);  // the median
    // Again: the set has a radius now, nothing changes.
    auto again = addRadiusFromSmoothingLength(s, 2.0f);
    ASSERT_TRUE(again);
    EXPECT_EQ(*again, "");
    EXPECT_FLOAT_EQ(s.find("radius")->floats[1], 0.02f);
    EXPECT_EQ(s.attributes.size(), 2u);
    // A file's pscale wins over its h.
    ParticleSet p;
    p.positions = {{0, 0, 0}};
    p.attributes.push_back({"h", AttributeType::Float, 1, {0.5f}, {}});
    p.attributes.push_back({"pscale", AttributeType::Float, 1, {0.1f}, {}});
    ASSERT_TRUE(addRadiusFromSmoothingLength(p, 1.2f));
    EXPECT_EQ(p.find("radius"), nullptr);
    // An integer h is not a length; a bad k is an error.
    ParticleSet q;
    q.positions = {{0, 0, 0}};
    q.attributes.push_back({"h", AttributeType::Int, 1, {}, {3}});
    ASSERT_TRUE(addRadiusFromSmoothingLength(q, 1.2f));
    EXPECT_EQ(q.find("radius"), nullptr);
    for (float bad : {0.0f, -1.0f, NAN, INFINITY}) {
        auto err = addRadiusFromSmoothingLength(q, bad);
        ASSERT_FALSE(err) << bad;
        EXPECT_NE(err.error().message.find("smoothing length per particle spacing"), std::string::npos);
    }
}

// Regression: 1,000 points in [0, 1e30]^3 gave "too few particles" and a camera
// error naming no file; now the data is named as the problem.
TEST(Particles, CoordinatesBeyondTheRangeAreNamed) {
    std::vector<glm::vec3> pts{{0, 0, 0}, {1e30f, 5e29f, 0}};
    const Status st = checkCoordinates(pts, "big.xyz");
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().file, "big.xyz");
    EXPECT_NE(st.error().message.find("1e+30 m"), std::string::npos) << st.error().message;
    pts[1] = {1e17f, 0, 0};
    EXPECT_TRUE(checkCoordinates(pts, "ok.xyz").ok());
}

// Regression: --radius 1e30 failed as "up vector is parallel to the view direction".
TEST(Particles, RadiusRangeCheck) {
    for (float bad : {1e30f, 0.0f, -1.0f, 1e-20f, std::numeric_limits<float>::quiet_NaN(),
                      std::numeric_limits<float>::infinity()}) {
        const Status st = checkRadius(bad);
        ASSERT_FALSE(st.ok()) << bad;
        EXPECT_NE(st.error().message.find("out of range"), std::string::npos) << st.error().message;
    }
    EXPECT_TRUE(checkRadius(0.025f).ok());
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
}  // namespace particles_test_local
