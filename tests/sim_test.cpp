// The simulator (src/sim/, include/meniscus/sim.h): kernels, neighbour search,
// boundaries, the three methods, emitters/drains/lifetime, and the physics
// checks that are cheap enough for every CI run.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "meniscus/io.h"
#include "meniscus/sim.h"
#include <cstdio>
#include "shared/sph_kernels.h"
#include "sim/boundary_density_maps.h"
#include "sim/colliders.h"
#include "sim/kernels.h"
#include "sim/neighbour_search.h"
#include "sim/parallel.h"

namespace sim_test_local {

using namespace meniscus;
using namespace meniscus::sim;

namespace {

// Integral over R^3 of a radial function f(r) with support h (midpoint rule in r).
template <class F>
double radialIntegral(F&& f, float h, int steps = 20000) {
    double sum = 0.0;
    const double dr = double(h) / steps;
    for (int k = 0; k < steps; ++k) {
        const double r = (k + 0.5) * dr;
        sum += 4.0 * 3.14159265358979323846 * r * r * double(f(float(r))) * dr;
    }
    return sum;
}

FluidBlock block(const Box& box, const glm::vec3& velocity) {
    FluidBlock f;
    f.box = box;
    f.velocity = velocity;
    return f;
}

Scene tank(float radius, Solver solver = Solver::Dfsph) {
    Scene s;
    s.params.radius = radius;
    s.params.solver = solver;
    return s;
}

std::unique_ptr<Simulator> make(const Scene& scene) {
    auto s = Simulator::create(scene);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().describe());
    return s.ok() ? std::move(s.value()) : nullptr;
}

// Runs f once on each of the loops' compilations this CPU and build have
// (parallel.h), with a trace naming it; the path in use before is restored.
template <class F>
void onEachSimdPath(F&& f) {
    const SimdPath before = simdPath();
    for (SimdPath path : {SimdPath::Baseline, SimdPath::Avx2Fma}) {
        setSimdPath(path);
        if (simdPath() != path) continue;
        SCOPED_TRACE(simdPathName(path));
        f(path);
    }
    setSimdPath(before);
}

}  // namespace

// ---------------------------------------------------------------- kernels

TEST(SimKernels, IntegrateToOne) {
    const float h = 0.04f;
    const CubicSpline cubic(h);
    const MullerKernels mk(h);
    EXPECT_NEAR(radialIntegral([&](float r) { return cubic.W(r); }, h), 1.0, 1e-4);
    EXPECT_NEAR(radialIntegral([&](float r) { return mk.poly6(r * r); }, h), 1.0, 1e-4);
    EXPECT_NEAR(radialIntegral([&](float r) { return mk.spiky(r); }, h), 1.0, 1e-4);
    // The viscosity kernel's 1/r term needs a finer start.
    EXPECT_NEAR(radialIntegral([&](float r) { return mk.viscosity(r); }, h, 200000), 1.0, 1e-3);
}

TEST(SimKernels, GradientsAreTheDerivatives) {
    const float h = 0.04f;
    const CubicSpline cubic(h);
    const MullerKernels mk(h);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.03f, 0.03f);
    for (int k = 0; k < 200; ++k) {
        const glm::vec3 d(u(rng), u(rng), u(rng));
        const float r = glm::length(d);
        if (r < 0.002f || r > 0.038f) continue;
        const float e = 1e-5f;
        for (int a = 0; a < 3; ++a) {
            glm::vec3 p = d, m = d;
            p[a] += e, m[a] -= e;
            const float fdCubic = (cubic.W(glm::length(p)) - cubic.W(glm::length(m))) / (2 * e);
            const float fdPoly = (mk.poly6(glm::dot(p, p)) - mk.poly6(glm::dot(m, m))) / (2 * e);
            const float fdSpiky = (mk.spiky(glm::length(p)) - mk.spiky(glm::length(m))) / (2 * e);
            const float scaleC = 1.0f / std::pow(h, 4.0f);
            EXPECT_NEAR(cubic.gradW(d, r)[a], fdCubic, 2e-3f * scaleC) << "cubic at " << r;
            EXPECT_NEAR(mk.poly6Grad(d, glm::dot(d, d))[a], fdPoly, 2e-3f * scaleC) << "poly6 at " << r;
            EXPECT_NEAR(mk.spikyGrad(d, r)[a], fdSpiky, 2e-3f * scaleC) << "spiky at " << r;
        }
    }
    // The gradient is odd: grad W(-d) = -grad W(d) (what makes the forces pairwise).
    const glm::vec3 d(0.01f, -0.005f, 0.007f);
    EXPECT_EQ(cubic.gradW(-d, glm::length(d)), -cubic.gradW(d, glm::length(d)));
}

// One cubic spline: the simulator's is sigma times shared::sphKernel (and its
// gradient sigma / h^2 times sphKernelGradient), the functions the renderer's
// ray cast, the mesher and the radius estimate evaluate, bit for bit.
TEST(SimKernels, TheCubicSplineIsTheSharedOne) {
    const float h = 0.04f, invH = 1.0f / h;
    const CubicSpline cubic(h);
    const float sigma = shared::sphKernelSigma(h);
    EXPECT_EQ(sigma, 8.0f / (3.14159265358979323846f * h * h * h));
    for (float r : {0.0f, 0.003f, 0.5f * h, std::nextafter(0.5f * h, h), 0.031f, std::nextafter(h, 0.0f)}) {
        EXPECT_EQ(cubic.W(r), sigma * shared::sphKernel(r * invH)) << r;
        if (r > 0.0f) {
            EXPECT_EQ(cubic.gradFactor(r), sigma / (h * h) * shared::sphKernelGradient(r * invH)) << r;
        }
    }
    EXPECT_EQ(cubic.W(h), 0.0f);
    EXPECT_EQ(cubic.gradFactor(h), 0.0f);
    EXPECT_EQ(shared::sphKernel(0.0f), 1.0f);
    EXPECT_EQ(shared::sphKernel(0.5), 0.25);  // the double instance, as the radius estimate uses it
}

// The neighbour build evaluates the kernels four distances at once; the
// lanes must be the scalar kernels bit for bit (the same lists and frames on
// any path), across both branches, the support's edge and r = 0.
TEST(SimKernels, FourAtOnceEqualsTheScalarKernels) {
    const float h = 0.04f;
    const CubicSpline cubic(h);
    const MullerKernels mk(h);
    std::vector<float> rs = {0.0f, 1e-12f, 0.5f * h, std::nextafter(0.5f * h, h), std::nextafter(h, 0.0f), h, 1.5f * h};
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.1f * h);
    while (rs.size() < 4000) rs.push_back(u(rng));
    for (std::size_t k = 0; k + 4 <= rs.size(); k += 4) {
        F4 w, g, sw, sg;
        cubic.evaluate4(load4(&rs[k]), w, g);
        mk.spiky4(load4(&rs[k]), sw, sg);
        alignas(16) float W[4], G[4], SW[4], SG[4];
        store4(W, w), store4(G, g), store4(SW, sw), store4(SG, sg);
        for (int l = 0; l < 4; ++l) {
            const float r = rs[k + std::size_t(l)];
            EXPECT_EQ(W[l], cubic.W(r)) << "cubic W at r = " << r;
            EXPECT_EQ(G[l], cubic.gradFactor(r)) << "cubic gradient at r = " << r;
            EXPECT_EQ(SW[l], mk.spiky(r)) << "spiky W at r = " << r;
            EXPECT_EQ(SG[l], mk.spikyGradFactor(r)) << "spiky gradient at r = " << r;
        }
    }
    // And the factor is the gradient: grad W(d) = gradFactor(|d|) d, with a
    // gradient that is not zero inside the support.
    EXPECT_LT(cubic.gradFactor(0.3f * h), 0.0f);
    EXPECT_LT(cubic.gradFactor(0.7f * h), 0.0f);
    EXPECT_LT(mk.spikyGradFactor(0.5f * h), 0.0f);
}

TEST(SimKernels, LaplaciansMatchFiniteDifferences) {
    const float h = 0.04f;
    const MullerKernels mk(h);
    // Radial Laplacian f'' + 2 f' / r.
    for (float r : {0.008f, 0.015f, 0.025f, 0.033f}) {
        const float e = 1e-4f;
        auto lap = [&](auto&& f) { return (f(r + e) - 2 * f(r) + f(r - e)) / (e * e) + (f(r + e) - f(r - e)) / (e * r); };
        const float p6 = lap([&](float x) { return mk.poly6(x * x); });
        const float visc = lap([&](float x) { return mk.viscosity(x); });
        EXPECT_NEAR(mk.poly6Lap(r * r), p6, 2e-2f * std::abs(p6) + 1.0f) << r;
        EXPECT_NEAR(mk.viscosityLap(r), visc, 2e-2f * std::abs(visc) + 1.0f) << r;
    }
}

// ---------------------------------------------------------------- neighbour search

// Each of the loops' compilations (parallel.h): the baseline one exactly as the
// scalar kernel; the AVX2+FMA one (where this CPU has it) within rounding, and
// with the same lists but for pairs within rounding of the support.
class SimNeighboursOnEachPath : public ::testing::TestWithParam<SimdPath> {
protected:
    void SetUp() override {
        before_ = simdPath();
        setSimdPath(GetParam());
        if (simdPath() != GetParam()) GTEST_SKIP() << "this CPU or build has no " << simdPathName(GetParam()) << " path";
    }
    void TearDown() override { setSimdPath(before_); }
    SimdPath before_ = SimdPath::Baseline;
};

TEST_P(SimNeighboursOnEachPath, SameAsBruteForceAndInCellOrder) {
    const bool exact = GetParam() == SimdPath::Baseline;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<glm::vec3> pts(3000);
    for (auto& p : pts) p = {u(rng), u(rng) * 0.5f, u(rng) * 0.3f};
    pts.push_back({-5.0f, 0.2f, 0.1f});  // outside the grid: clamped into a border cell
    const float h = 0.06f;
    CellGrid grid;
    grid.configure(Box{{0, 0, 0}, {1, 0.5f, 0.3f}}, h);
    grid.build(pts);
    NeighbourLists lists;
    const CubicSpline K(h);
    std::vector<float> wSum(pts.size());
    buildNeighbourLists(pts, grid, h, true, [&](F4 r, F4& w, F4& g) { K.evaluate4(r, w, g); }, lists, wSum);
    // The gradient's largest magnitude: FMA's rounding is relative to the
    // terms of the spline's polynomial, not to a small result near the support.
    float peak = 0.0f;
    for (int k = 1; k < 1000; ++k) peak = std::max(peak, std::abs(K.gradFactor(h * float(k) / 1000.0f)) * h * float(k) / 1000.0f);
    std::size_t compared = 0;
    for (std::size_t i = 0; i < pts.size(); i += 7) {
        std::vector<std::uint32_t> brute, found;
        auto borderline = [&](std::uint32_t j) {
            const float d2 = glm::dot(pts[i] - pts[j], pts[i] - pts[j]);
            return !exact && std::abs(d2 - h * h) < 1e-5f * h * h;
        };
        for (std::size_t j = 0; j < pts.size(); ++j)
            if (j != i && glm::dot(pts[i] - pts[j], pts[i] - pts[j]) < h * h && !borderline(std::uint32_t(j)))
                brute.push_back(std::uint32_t(j));
        double sum = 0.0;
        for (const Neighbour& nb : lists.of(i)) {
            if (!borderline(nb.j)) found.push_back(nb.j);
            const glm::vec3 want = K.gradW(pts[i] - pts[nb.j], glm::length(pts[i] - pts[nb.j]));
            if (exact) EXPECT_EQ(nb.g * (pts[i] - pts[nb.j]), want);
            else EXPECT_LE(glm::length(nb.g * (pts[i] - pts[nb.j]) - want), 1e-6f * peak);
            sum += double(K.W(glm::length(pts[i] - pts[nb.j])));
            ++compared;
        }
        EXPECT_NEAR(wSum[i], sum, 1e-4 * sum + 1e-3);
        std::sort(found.begin(), found.end());
        EXPECT_EQ(found, brute) << "particle " << i;
    }
    EXPECT_GT(compared, 5000u);
}

INSTANTIATE_TEST_SUITE_P(Paths, SimNeighboursOnEachPath, ::testing::Values(SimdPath::Baseline, SimdPath::Avx2Fma),
                         [](const auto& info) { return info.param == SimdPath::Baseline ? "Baseline" : "Avx2Fma"; });

TEST(SimNeighbours, ZOrderIsAPermutationThatGroupsCells) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<glm::vec3> pts(2000);
    for (auto& p : pts) p = {u(rng), u(rng), u(rng)};
    CellGrid grid;
    grid.configure(Box{{0, 0, 0}, {1, 1, 1}}, 0.1f);
    const auto order = zOrder(grid, pts);
    std::vector<std::uint32_t> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (std::uint32_t k = 0; k < sorted.size(); ++k) ASSERT_EQ(sorted[k], k);
    for (std::size_t k = 1; k < order.size(); ++k)
        EXPECT_LE(grid.mortonKey(pts[order[k - 1]]), grid.mortonKey(pts[order[k]]));
}

// ---------------------------------------------------------------- boundaries (density maps)

TEST(SimBoundary, WallTableIsTheHalfSpaceIntegral) {
    const float h = 0.04f;
    const CubicSpline K(h);
    const WallTable t(h, [&](double d) { return double(K.W(float(d))); });
    EXPECT_NEAR(t.phi(0.0f), 0.5f, 1e-4f);  // on the surface: half the kernel's mass
    EXPECT_NEAR(t.phi(-h), 1.0f, 1e-4f);    // deep inside: all of it
    EXPECT_NEAR(t.phi(h), 0.0f, 1e-6f);
    // Against a brute-force sum of W over a fine grid of the half-space y < 0.
    const float cell = h / 40.0f;
    for (float d : {0.005f, 0.01f, 0.02f, 0.03f}) {
        double sum = 0.0;
        for (int iy = 0; iy < 40; ++iy)
            for (int ix = -40; ix < 40; ++ix)
                for (int iz = -40; iz < 40; ++iz) {
                    const glm::vec3 y((ix + 0.5f) * cell, -(iy + 0.5f) * cell, (iz + 0.5f) * cell);
                    sum += double(K.W(glm::length(glm::vec3(0, d, 0) - y)));
                }
        EXPECT_NEAR(t.phi(d), sum * double(cell) * cell * cell, 2e-3) << d;
        // A = -dPhi/dd.
        const float e = 1e-4f;
        EXPECT_NEAR(t.slab(d), -(t.phi(d + e) - t.phi(d - e)) / (2 * e), 0.01f * t.slab(d) + 1e-3f) << d;
    }
}

TEST(SimBoundary, TheRestLatticeHasRestDensityAtWallsEdgesAndCorners) {
    // A box filled with fluid (its cube faces on the walls): every particle,
    // in the bulk, on a face, along an edge or in a corner, must have rho0
    // within a stated bound; this is what the wall offset and the exact
    // domain table are for (half-space walls alone give 4 % at a face, 8 %
    // along an edge).
    for (Solver solver : {Solver::Dfsph, Solver::Sph}) {
        Scene s = tank(0.01f, solver);
        s.domain = Box{{0, 0, 0}, {0.2f, 0.2f, 0.2f}};
        s.fluid.push_back(block(Box{{0, 0, 0}, {0.2f, 0.2f, 0.2f}}, glm::vec3(0.0f)));
        s.params.gravity = glm::vec3(0.0f);
        auto sim = make(s);
        ASSERT_TRUE(sim);
        ASSERT_EQ(sim->size(), 1000u);  // 10^3: the first particle r from each wall
        ASSERT_TRUE(sim->step().ok());
        float lo = 1e9f, hi = 0.0f;
        for (float d : sim->densities()) lo = std::min(lo, d), hi = std::max(hi, d);
        EXPECT_GT(lo, 1000.0f * 0.985f) << solverName(solver);
        EXPECT_LT(hi, 1000.0f * 1.015f) << solverName(solver);
    }
}

TEST(SimBoundary, DomainTableIsTheKernelMassInside) {
    const float h = 0.04f;
    const CubicSpline K(h);
    const DomainTable t(h, [&](double d) { return double(K.W(float(d))); });
    const WallTable half(h, [&](double d) { return double(K.W(float(d))); });
    EXPECT_NEAR(t.inside(glm::vec3(h)), 1.0f, 1e-4f);                 // far from every wall
    EXPECT_NEAR(t.inside({0.0f, h, h}), 0.5f, 2e-3f);                 // on a face
    EXPECT_NEAR(t.inside({0.0f, 0.0f, h}), 0.25f, 2e-3f);             // on an edge
    EXPECT_NEAR(t.inside({0.0f, 0.0f, 0.0f}), 0.125f, 2e-3f);         // in a corner
    for (float d : {0.005f, 0.015f, 0.03f}) EXPECT_NEAR(1.0f - t.inside({d, h, h}), half.phi(d), 2e-3f) << d;
    // Against a brute-force sum over the quadrant behind an edge.
    const float c = h / 50.0f;
    const glm::vec3 p(13 * c, 26 * c, h);  // the walls on cell faces of the brute-force grid
    double outside = 0.0, total = 0.0;
    for (int i = -50; i < 50; ++i)
        for (int j = -50; j < 50; ++j)
            for (int k = -50; k < 50; ++k) {
                const glm::vec3 u((i + 0.5f) * c, (j + 0.5f) * c, (k + 0.5f) * c);
                const double w = double(K.W(glm::length(u)));
                total += w;
                if (u.x < -p.x || u.y < -p.y) outside += w;
            }
    EXPECT_NEAR(1.0f - t.inside(p), outside / total, 3e-3);
    // The gradient is the derivative.
    const glm::vec3 g = t.gradient(p);
    const float e = 1e-4f;
    EXPECT_NEAR(g.x, (t.inside(p + glm::vec3(e, 0, 0)) - t.inside(p - glm::vec3(e, 0, 0))) / (2 * e), 0.05f * std::abs(g.x) + 0.5f);
    EXPECT_GT(g.x, 0.0f);  // further from the wall: more mass inside
}

TEST(SimColliders, DistancesAndTheGuard) {
    Collider box;
    box.kind = Collider::Kind::Box;
    box.box = Box{{0, 0, 0}, {1, 1, 1}};
    EXPECT_NEAR(colliderDistance(box, nullptr, {0.5f, 0.9f, 0.5f}).distance, -0.1f, 1e-6f);
    EXPECT_EQ(colliderDistance(box, nullptr, {0.5f, 0.9f, 0.5f}).normal, glm::vec3(0, 1, 0));
    EXPECT_NEAR(colliderDistance(box, nullptr, {2.0f, 0.5f, 0.5f}).distance, 1.0f, 1e-6f);
    Collider sphere;
    sphere.kind = Collider::Kind::Sphere;
    sphere.center = {0, 0, 0}, sphere.radius = 0.5f;
    EXPECT_NEAR(colliderDistance(sphere, nullptr, {0, 0.2f, 0}).distance, -0.3f, 1e-6f);
    // A closed mesh (the unit cube's 12 triangles): inside is negative.
    ColliderMesh cube;
    cube.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    cube.mesh.indices = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 0, 4, 7, 0, 7, 3};
    Collider mesh;
    mesh.kind = Collider::Kind::Mesh;
    EXPECT_NEAR(colliderDistance(mesh, &cube.mesh, {0.5f, 0.8f, 0.5f}).distance, -0.2f, 1e-5f);
    EXPECT_NEAR(colliderDistance(mesh, &cube.mesh, {0.5f, 1.3f, 0.5f}).distance, 0.3f, 1e-5f);
    // The guard puts a particle inside back out and stops it moving in.
    Scene scene;
    scene.domain = Box{{-2, -2, -2}, {2, 2, 2}};
    scene.colliders = {sphere};
    glm::vec3 x(0, 0.4f, 0), v(0, -1, 0.5f);
    EXPECT_TRUE(keepOutside(scene, {}, 0.01f, x, v, glm::vec3(0, 0.6f, 0)));
    EXPECT_GE(glm::length(x), 0.5f);
    EXPECT_EQ(v.y, 0.0f);
    EXPECT_EQ(v.z, 0.5f);
    glm::vec3 far(0, 3.0f, 0), vf(0, 1, 0);
    EXPECT_TRUE(keepOutside(scene, {}, 0.01f, far, vf, glm::vec3(0, 1.9f, 0)));
    EXPECT_LE(far.y, 2.0f);
    // A ball sunk into the floor: just inside it, by the floor, its nearest
    // surface point is below the floor. Pushed there, put back by the tank,
    // it would be inside again: it goes back to where its step began, at rest.
    Collider sunk = sphere;
    sunk.center = {0, -1.8f, 0};  // radius 0.5: 0.3 below the floor at y = -2
    scene.colliders = {sunk};
    const glm::vec3 start(0.47f, -1.99f, 0.0f);  // 7 mm outside the ball
    glm::vec3 pinched(0.36f, -1.995f, 0.0f), vp(-1.0f, -0.5f, 0.0f);
    ASSERT_LT(colliderDistance(sunk, nullptr, pinched).distance, 0.0f);
    ASSERT_GT(colliderDistance(sunk, nullptr, start).distance, 0.0f);
    EXPECT_TRUE(keepOutside(scene, {}, 0.01f, pinched, vp, start));
    EXPECT_GE(colliderDistance(sunk, nullptr, pinched).distance, 0.0f);
    EXPECT_GE(pinched.y, -2.0f);
    EXPECT_EQ(pinched, start);
    EXPECT_EQ(vp, glm::vec3(0.0f));
}

TEST(SimColliders, PbfCollisionResponseProjectsAGapOutOfEverySurface) {
    // projectOutside (Macklin & Muller 2013's collision response): a point
    // inside the ball, or closer than the gap, goes to the gap along the
    // normal; one beyond a tank wall to the gap inside it; one far from all
    // stays where it is, bit for bit.
    Collider ball;
    ball.kind = Collider::Kind::Sphere;
    ball.center = {0, 0, 0}, ball.radius = 0.5f;
    Scene scene;
    scene.domain = Box{{-2, -2, -2}, {2, 2, 2}};
    scene.colliders = {ball};
    const float gap = 0.01f;
    for (const glm::vec3 start : {glm::vec3(0, 0.3f, 0), glm::vec3(0.3f, 0.4f, 0.0f), glm::vec3(0, 0.505f, 0)}) {
        glm::vec3 x = start;
        EXPECT_TRUE(projectOutside(scene, {}, gap, x));
        EXPECT_NEAR(colliderDistance(ball, nullptr, x).distance, gap, 1e-6f);
        EXPECT_NEAR(glm::dot(glm::normalize(x), glm::normalize(start)), 1.0f, 1e-6f) << "along the normal";
    }
    glm::vec3 out(2.5f, -2.0f, 0.7f);
    EXPECT_TRUE(projectOutside(scene, {}, gap, out));
    EXPECT_EQ(out, glm::vec3(2.0f - gap, -2.0f + gap, 0.7f));
    glm::vec3 free(1.0f, 1.0f, 1.0f);
    EXPECT_FALSE(projectOutside(scene, {}, gap, free));
    EXPECT_EQ(free, glm::vec3(1.0f));
}

// ---------------------------------------------------------------- physics

namespace {

// A column 0.2 m x 0.3 m x 0.2 m of water filling the bottom of a tank.
Scene column(Solver solver = Solver::Dfsph) {
    Scene s = tank(0.01f, solver);
    s.domain = Box{{0, 0, 0}, {0.2f, 0.5f, 0.2f}};
    s.fluid.push_back(block(Box{{0, 0, 0}, {0.2f, 0.3f, 0.2f}}, glm::vec3(0.0f)));
    s.params.viscosity = 0.01f;  // m^2/s, SPlisHSPlasH's dam-break damping
    if (solver == Solver::Sph) {
        s.params.viscosity = 0.5f;     // mu, Pa s: damps the start (the column is not at rest on the lattice)
        s.params.stiffness = 1000.0f;  // c = 31.6 m/s, ~10x the largest flow speed
    }
    return s;
}

struct ColumnResult {
    double maxSpeed = 0, meanDrift = 0, maxDrift = 0, densityError = 0, slope = 0, surfaceY = 0;
    double comDrift = 0;  // |centre of mass after - before| over the measured span, m
    std::size_t guardCorrections = 0;  // over the whole run
};

// Settles the column for `settle` seconds (the lattice is not the rest
// state: its walls are a gap of r away), then measures over `measure` more.
ColumnResult runColumn(Solver solver, double settle, double measure) {
    ColumnResult out;
    auto sim = make(column(solver));
    if (!sim) return out;
    EXPECT_TRUE(sim->advanceTo(settle).ok());
    std::vector<glm::vec3> byId(sim->size());
    for (std::size_t i = 0; i < sim->size(); ++i) byId[std::size_t(sim->ids()[i])] = sim->positions()[i];
    glm::dvec3 comBefore(0.0), comAfter(0.0);
    for (const glm::vec3& p : sim->positions()) comBefore += glm::dvec3(p) / double(sim->size());
    EXPECT_TRUE(sim->advanceTo(settle + measure).ok());
    for (const glm::vec3& p : sim->positions()) comAfter += glm::dvec3(p) / double(sim->size());
    out.comDrift = glm::length(comAfter - comBefore);
    out.guardCorrections = sim->totals().guardCorrections;
    const auto x = sim->positions();
    const auto v = sim->velocities();
    const auto ids = sim->ids();
    float top = 0.0f;
    for (const glm::vec3& p : x) top = std::max(top, p.y);
    out.surfaceY = top;
    double sumRho = 0, sy = 0, sp = 0, syy = 0, syp = 0;
    std::size_t interior = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        out.maxSpeed = std::max(out.maxSpeed, double(glm::length(v[i])));
        const double drift = glm::length(x[i] - byId[std::size_t(ids[i])]);
        out.meanDrift += drift / double(x.size());
        out.maxDrift = std::max(out.maxDrift, drift);
        // Interior: 4r from the free surface and the walls.
        const glm::vec3 p = x[i];
        if (p.y < top - 0.04f && p.y > 0.04f && p.x > 0.04f && p.x < 0.16f && p.z > 0.04f && p.z < 0.16f) {
            sumRho += std::abs(sim->densities()[i] - 1000.0f) / 1000.0f;
            const double y = p.y, pr = sim->pressures()[i];
            sy += y, sp += pr, syy += y * y, syp += y * pr;
            ++interior;
        }
    }
    out.densityError = interior ? sumRho / double(interior) : 1.0;
    // Least squares p = a - slope * y (the free surface's height need not be known).
    const double m = double(interior);
    out.slope = interior > 1 ? -(m * syp - sy * sp) / (m * syy - sy * sy) : 0.0;
    return out;
}

}  // namespace

TEST(SimPhysics, DfsphColumnStaysAtRest) {
    const ColumnResult c = runColumn(Solver::Dfsph, 1.5, 0.5);
    // The lattice settles onto the floor by about its gap (2r -> r): bounds in r = 0.01 m.
    std::printf("DFSPH column: max speed %.4f m/s, mean drift %.5f m, max drift %.5f m, density error %.5f, slope %.0f Pa/m\n",
                c.maxSpeed, c.meanDrift, c.maxDrift, c.densityError, c.slope);
    // Bounds as the solver stands: a settled column keeps moving at a few cm/s
    // (mean), never like a flow (free fall from its height would be 2.4 m/s);
    // its density stays within 0.3 % of rho0; the pressure grows downward at
    // the hydrostatic rate within a factor of 2.
    EXPECT_LT(c.maxSpeed, 0.6) << "m/s";
    EXPECT_LT(c.meanDrift, 0.005) << "m over 0.5 s";
    EXPECT_LT(c.densityError, 0.003) << "mean |rho - rho0| / rho0 in the interior";
    EXPECT_GT(c.slope, 0.5 * 1000.0 * 9.81) << "Pa/m";
    EXPECT_LT(c.slope, 2.0 * 1000.0 * 9.81) << "Pa/m";
}

TEST(SimPhysics, SphColumnStaysAtRest) {
    // Muller SPH, k = 1000 m^2/s^2, mu = 0.5 Pa s (column()). With the paper's
    // symmetrised pressure force and poly6 density this column gained energy
    // and boiled (6 m/s by 0.3 s, particles through the walls);
    // sph_muller2003.cpp says why and what replaced it.
    const ColumnResult c = runColumn(Solver::Sph, 1.0, 0.5);
    std::printf("SPH column: max speed %.4f m/s, mean drift %.5f m, max drift %.5f m, centre-of-mass drift %.5f m, "
                "density error %.5f, slope %.0f Pa/m, guard corrections %zu\n",
                c.maxSpeed, c.meanDrift, c.maxDrift, c.comDrift, c.densityError, c.slope, c.guardCorrections);
    // Bounds in r = 0.01 m: at rest means slower than 0.3 m/s anywhere (free
    // fall from the column's height would be 2.4 m/s), the particles moving
    // less than r on average (an acoustic jitter of ~5 cm/s that the
    // viscosity damps slowly) and the centre of mass less than 1 mm in 0.5 s;
    // the interior within 1 % of rho0 (k = 1000 allows ~0.3 % of
    // hydrostatic compression at the floor); the pressure growing downward
    // between rho0 g and 1.75 rho0 g: the SPH gradient of the spiky kernel on
    // this lattice (2r spacing, h = 4r) is 0.77 of the true gradient
    // (sum_j V (x_j - x_i) (x) grad W_ij = 0.77 I), so holding the fluid
    // takes a pressure 1.3 times steeper than rho0 g.
    EXPECT_LT(c.maxSpeed, 0.3) << "m/s";
    EXPECT_LT(c.meanDrift, 0.01) << "m over 0.5 s";
    EXPECT_LT(c.comDrift, 0.001) << "m over 0.5 s";
    EXPECT_LT(c.densityError, 0.01) << "mean |rho - rho0| / rho0 in the interior";
    EXPECT_GT(c.slope, 1.0 * 1000.0 * 9.81) << "Pa/m";
    EXPECT_LT(c.slope, 1.75 * 1000.0 * 9.81) << "Pa/m";
}

TEST(SimPhysics, PbfColumnStaysAtRest) {
    // Position-based fluids (Macklin & Muller 2013, pbf_macklin2013.cpp) at
    // the DFSPH column's tolerance: a column at rest stays at rest, its
    // density within 0.5 % of rho0 (the projection stops at a mean error of
    // 0.05 %), the particles drifting less than r/2 on average in 0.5 s and
    // the centre of mass less than 1 mm.
    const ColumnResult c = runColumn(Solver::Pbf, 1.0, 0.5);
    std::printf("PBF column: max speed %.4f m/s, mean drift %.5f m, max drift %.5f m, centre-of-mass drift %.5f m, "
                "density error %.5f, guard corrections %zu\n",
                c.maxSpeed, c.meanDrift, c.maxDrift, c.comDrift, c.densityError, c.guardCorrections);
    EXPECT_LT(c.maxSpeed, 0.3) << "m/s";
    EXPECT_LT(c.meanDrift, 0.005) << "m over 0.5 s";
    EXPECT_LT(c.comDrift, 0.001) << "m over 0.5 s";
    EXPECT_LT(c.densityError, 0.005) << "mean |rho - rho0| / rho0 in the interior";
}

namespace {

// Kinetic + gravitational energy, J, plus for SPH the internal energy of
// p = k (rho - rho0) clamped at 0: m k (ln(rho / rho0) + rho0 / rho - 1)
// per particle above rho0 (the integral of p / rho^2 d rho). PBF stores none
// (its constraint is a projection, not a spring).
double totalEnergy(const Simulator& sim) {
    const SimParams& p = sim.scene().params;
    const double m = sim.particleMass(), k = p.stiffness, rho0 = p.restDensity;
    const bool elastic = p.solver == Solver::Sph;
    double e = 0.0;
    for (std::size_t i = 0; i < sim.size(); ++i) {
        const glm::dvec3 v(sim.velocities()[i]), x(sim.positions()[i]);
        const double rho = sim.densities()[i];
        e += m * (0.5 * glm::dot(v, v) - glm::dot(glm::dvec3(p.gravity), x));
        if (elastic && rho > rho0) e += m * k * (std::log(rho / rho0) + rho0 / rho - 1.0);
    }
    return e;
}

// The dam break scene at a coarse radius (729 particles) with `solver`:
// 1 s, every particle finite and in the tank, the front at the far wall, and
// the energy never above its start (a closed tank has no source).
void damBreakGainsNoEnergy(Solver solver, const char* name) {
    auto read = readScene(MENISCUS_SOURCE_DIR "/scenes/dam_break.json");
    ASSERT_TRUE(read.ok()) << read.error().describe();
    Scene s = read.value();
    s.params.solver = solver;
    s.params.radius = 0.05f;
    s.params.particleVolume = 0.0f;  // the rest lattice (the solver's test, not SPlisHSPlasH's mass)
    auto sim = make(s);
    ASSERT_TRUE(sim);
    const double e0 = totalEnergy(*sim);
    double highest = e0;
    for (int k = 1; k <= 20; ++k) {
        const Status st = sim->advanceTo(0.05 * k);
        ASSERT_TRUE(st.ok()) << st.error().describe();
        for (const glm::vec3& p : sim->positions())
            ASSERT_TRUE(glm::all(glm::greaterThanEqual(p, s.domain.min)) && glm::all(glm::lessThanEqual(p, s.domain.max)))
                << "t = " << sim->time();
        highest = std::max(highest, totalEnergy(*sim));
    }
    float front = -1e9f;
    for (const glm::vec3& p : sim->positions()) front = std::max(front, p.x);
    std::printf("%s dam break: energy %.1f J at the start, at most %.1f J, %.1f J at 1 s; front x = %.2f m\n", name, e0,
                highest, totalEnergy(*sim), double(front));
    EXPECT_LT(highest, e0 * 1.005) << "J";
    EXPECT_GT(front, 1.5f) << "the front crossed the tank (x from -0.95 m to the wall at 2 m)";
}

}  // namespace

TEST(SimPhysics, SphDamBreakStaysInTheTankAndGainsNoEnergy) {
    // The paper's symmetrised pressure force gained 19 % by 0.7 s (sph_muller2003.cpp).
    damBreakGainsNoEnergy(Solver::Sph, "SPH");
}

TEST(SimPhysics, PbfDamBreakStaysInTheTankAndGainsNoEnergy) {
    // XSPH and the projection take energy out; the lattice settling in the
    // first steps lifts it by 0.24 %, inside the 0.5 % bound.
    damBreakGainsNoEnergy(Solver::Pbf, "PBF");
}

namespace {

// A blob far from every wall, without gravity, with random velocities.
Scene freeBlob(Solver solver) {
    Scene s = tank(0.01f, solver);
    s.params.gravity = glm::vec3(0.0f);
    s.domain = Box{{-1, -1, -1}, {1, 1, 1}};
    s.fluid.push_back(block(Box{{-0.06f, -0.06f, -0.06f}, {0.06f, 0.06f, 0.06f}}, glm::vec3(0.0f)));
    return s;
}

glm::dvec3 momentum(const Simulator& sim) {
    glm::dvec3 p(0.0);
    for (const glm::vec3& v : sim.velocities()) p += glm::dvec3(v) * double(sim.particleMass());
    return p;
}

}  // namespace

TEST(SimPhysics, MomentumIsConservedWithoutBoundaries) {
    for (Solver solver : {Solver::Dfsph, Solver::Sph, Solver::Pbf}) {
        auto sim = make(freeBlob(solver));
        ASSERT_TRUE(sim);
        // Random velocities, then compress the blob a little so pressure acts.
        ParticleSet set = sim->particles();
        std::mt19937 rng(11);
        std::normal_distribution<float> n(0.0f, 0.3f);
        Attribute* vel = set.find(kAttrVelocity);
        for (float& f : vel->floats) f = n(rng);
        for (glm::vec3& p : set.positions) p *= 0.93f;
        ASSERT_TRUE(sim->restore(set, 0.0).ok());
        const glm::dvec3 before = momentum(*sim);
        double scale = 0.0;
        for (const glm::vec3& v : sim->velocities()) scale += glm::length(glm::dvec3(v)) * double(sim->particleMass());
        ASSERT_TRUE(sim->advanceTo(0.05).ok());
        const glm::dvec3 after = momentum(*sim);
        EXPECT_LT(glm::length(after - before), 1e-4 * scale) << solverName(solver);
        EXPECT_EQ(sim->totals().guardCorrections, 0u);
    }
}

TEST(SimPhysics, ParticleVolumeSetsTheMassAndTheStartingDensity) {
    // particle_volume 0 (the default): the lattice's own volume, so the
    // block's interior starts at rho0; 0.8 (SPlisHSPlasH's): m = 0.8 (2r)^3
    // rho0, and the same lattice reads 0.8 rho0 within the kernel's lattice sum.
    auto interiorDensity = [](float volume, double* mass) {
        Scene s = column();
        s.params.particleVolume = volume;
        auto sim = make(s);
        EXPECT_TRUE(sim && sim->advanceTo(1e-4).ok());
        *mass = sim->particleMass();
        double sum = 0.0;
        int count = 0;
        for (std::size_t i = 0; i < sim->size(); ++i) {
            const glm::vec3 p = sim->positions()[i];
            if (p.x > 0.06f && p.x < 0.14f && p.z > 0.06f && p.z < 0.14f && p.y > 0.06f && p.y < 0.22f)
                sum += sim->densities()[i], ++count;
        }
        return count ? sum / count : 0.0;
    };
    double own = 0, splish = 0;
    const double rhoOwn = interiorDensity(0.0f, &own), rhoSplish = interiorDensity(0.8f, &splish);
    const double r = 0.01;
    EXPECT_NEAR(splish, 1000.0 * 0.8 * std::pow(2 * r, 3), 1e-9) << "kg";
    EXPECT_NEAR(rhoOwn, 1000.0, 2.0) << "kg/m^3";
    EXPECT_NEAR(rhoSplish / rhoOwn, splish / own, 1e-3);
}

TEST(SimPhysics, BallisticMassPointsFallAsTheyShould) {
    Scene s = tank(0.01f, Solver::Ballistic);
    s.domain = Box{{-1, 0, -1}, {1, 20, 1}};
    s.fluid.push_back(block(Box{{-0.05f, 10.0f, -0.05f}, {0.05f, 10.1f, 0.05f}}, glm::vec3(1.0f, 2.0f, 0.0f)));
    auto sim = make(s);
    ASSERT_TRUE(sim);
    const float y0 = sim->positions()[0].y, x0 = sim->positions()[0].x;
    const std::int64_t id0 = sim->ids()[0];
    const double t = 1.0;
    ASSERT_TRUE(sim->advanceTo(t).ok());
    std::size_t k = 0;
    while (sim->ids()[k] != id0) ++k;
    const double dt = s.params.maxDt;
    // Symplectic Euler (velocity first) lands below the exact parabola by
    // g sum(dt_k^2) / 2, at most g max_dt t / 2.
    const double exact = y0 + 2.0 * t - 0.5 * 9.81 * t * t;
    EXPECT_LT(sim->positions()[k].y, exact);
    EXPECT_GT(sim->positions()[k].y, exact - 0.5 * 9.81 * dt * t - 1e-4);
    EXPECT_NEAR(sim->positions()[k].x, x0 + 1.0 * t, 1e-4);
    EXPECT_NEAR(sim->velocities()[k].y, 2.0 - 9.81 * t, 1e-3);
    EXPECT_DOUBLE_EQ(sim->time(), t);
}

TEST(SimPhysics, NoParticleLeavesTheDomainOrEntersACollider) {
    // A small dam break with a box and a sphere in the way, for the solvers
    // whose walls are density maps (DFSPH) or projections (PBF).
    for (Solver solver : {Solver::Dfsph, Solver::Pbf}) {
        SCOPED_TRACE(solverName(solver));
        Scene s = tank(0.02f, solver);
        s.domain = Box{{0, 0, 0}, {0.8f, 0.5f, 0.2f}};
        s.fluid.push_back(block(Box{{0, 0, 0}, {0.2f, 0.4f, 0.2f}}, glm::vec3(0.0f)));
        Collider box;
        box.kind = Collider::Kind::Box;
        box.box = Box{{0.4f, 0.0f, 0.05f}, {0.45f, 0.1f, 0.15f}};
        Collider ball;
        ball.kind = Collider::Kind::Sphere;
        ball.center = {0.6f, 0.05f, 0.1f}, ball.radius = 0.06f;
        s.colliders = {box, ball};
        auto sim = make(s);
        ASSERT_TRUE(sim);
        for (double t = 0.05; t <= 1.0 + 1e-9; t += 0.05) {
            const Status st = sim->advanceTo(t);
            ASSERT_TRUE(st.ok()) << st.error().describe();
            for (const glm::vec3& p : sim->positions()) {
                ASSERT_TRUE(glm::all(glm::greaterThanEqual(p, s.domain.min)) &&
                            glm::all(glm::lessThanEqual(p, s.domain.max)))
                    << "t = " << t;
                ASSERT_GE(colliderDistance(box, nullptr, p).distance, -1e-6f) << "t = " << t;
                ASSERT_GE(colliderDistance(ball, nullptr, p).distance, -1e-6f) << "t = " << t;
            }
        }
        // The front reached the obstacles (the flow did move).
        float front = 0.0f;
        for (const glm::vec3& p : sim->positions()) front = std::max(front, p.x);
        EXPECT_GT(front, 0.5f);
    }
}

TEST(SimPhysics, SameFramesForAnyThreadCount) {
    onEachSimdPath([](SimdPath) {
    for (Solver solver : {Solver::Dfsph, Solver::Pbf}) {
        SCOPED_TRACE(solverName(solver));
        Scene s = tank(0.02f, solver);
        s.domain = Box{{0, 0, 0}, {0.6f, 0.4f, 0.2f}};
        s.fluid.push_back(block(Box{{0, 0, 0}, {0.2f, 0.3f, 0.2f}}, glm::vec3(0.0f)));
        s.params.resortEvery = 7;
        auto run = [&](int threads) {
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
            auto sim = make(s);
            EXPECT_TRUE(sim->advanceTo(0.3).ok());
            return sim->particles();
        };
        const ParticleSet a = run(1), b = run(2), c = run(4);
        ASSERT_EQ(a.positions.size(), b.positions.size());
        EXPECT_EQ(0, std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(glm::vec3)));
        EXPECT_EQ(0, std::memcmp(a.positions.data(), c.positions.data(), a.positions.size() * sizeof(glm::vec3)));
        EXPECT_EQ(a.find(kAttrVelocity)->floats, c.find(kAttrVelocity)->floats);
        EXPECT_EQ(a.find(kAttrId)->ints, c.find(kAttrId)->ints);
    }
    });
}

// FMA changes the rounding and nothing else: the two paths' dam breaks agree
// to far below a particle radius over the first steps (later they part, as
// any two roundings of a splashing flow do).
TEST(SimPhysics, BothVectorPathsGiveTheSameFlowUpToRounding) {
    Scene s = tank(0.02f);
    s.domain = Box{{0, 0, 0}, {0.6f, 0.4f, 0.2f}};
    s.fluid.push_back(block(Box{{0, 0, 0}, {0.2f, 0.3f, 0.2f}}, glm::vec3(0.0f)));
    std::vector<ParticleSet> runs;
    onEachSimdPath([&](SimdPath) {
        auto sim = make(s);
        ASSERT_TRUE(sim->advanceTo(0.1).ok());
        runs.push_back(sim->particles());
    });
    if (runs.size() < 2) GTEST_SKIP() << "one vector path only on this CPU or build";
    ASSERT_EQ(runs[0].positions.size(), runs[1].positions.size());
    float worst = 0.0f;
    for (std::size_t i = 0; i < runs[0].positions.size(); ++i)
        worst = std::max(worst, glm::length(runs[0].positions[i] - runs[1].positions[i]));
    std::printf("baseline and AVX2+FMA paths after 0.1 s: largest position difference %.3g m\n", worst);
    // (Bits may be identical: GCC fuses multiply-adds only from -O2 on, so
    // the sanitizer build's -O1 paths differ in their instructions alone.)
    EXPECT_LT(worst, 0.01f * 0.02f) << "m, a hundredth of the radius";
}

TEST(SimSources, EmitterRateDrainAndLifetime) {
    Scene s = tank(0.01f);
    s.domain = Box{{0, 0, 0}, {0.4f, 0.6f, 0.4f}};
    Emitter e;
    e.position = {0.2f, 0.5f, 0.2f};
    e.direction = {0, -1, 0};
    e.speed = 1.0f;
    e.rate = 2000.0f;  // particles per second
    e.end = 0.5f;
    s.emitters = {e};
    s.drains = {Drain{Box{{0, 0, 0}, {0.4f, 0.05f, 0.4f}}}};
    auto sim = make(s);
    ASSERT_TRUE(sim);
    EXPECT_EQ(sim->size(), 0u);
    ASSERT_TRUE(sim->advanceTo(0.5).ok());
    // One layer of round(rate * 2r / speed) = 40 particles every 2r / speed = 0.02 s.
    EXPECT_NEAR(double(sim->totals().emitted), 2000.0 * 0.5, 2000.0 * 0.02 + 1);
    ASSERT_TRUE(sim->advanceTo(1.2).ok());
    EXPECT_GT(sim->totals().drained, 0u);
    for (const glm::vec3& p : sim->positions()) EXPECT_GT(p.y, 0.05f - 1e-6f);
    // Ids are unique and new ones continue after the last.
    std::vector<std::int64_t> ids(sim->ids().begin(), sim->ids().end());
    std::sort(ids.begin(), ids.end());
    EXPECT_EQ(std::adjacent_find(ids.begin(), ids.end()), ids.end());

    Scene life = freeBlob(Solver::Ballistic);
    life.params.lifetime = 0.1f;
    auto dying = make(life);
    const std::size_t n = dying->size();
    ASSERT_TRUE(dying->advanceTo(0.09).ok());
    EXPECT_EQ(dying->size(), n);
    ASSERT_TRUE(dying->advanceTo(0.2).ok());
    EXPECT_EQ(dying->size(), 0u);
    EXPECT_EQ(dying->totals().expired, n);
}

TEST(SimScene, BadScenesAreErrorsNamingTheProblem) {
    Scene s = tank(0.01f);
    s.file = "bad.json";
    s.domain = Box{{0, 0, 0}, {1, 1, 1}};
    s.fluid.push_back(block(Box{{0.5f, 0.5f, 0.5f}, {1.5f, 0.9f, 0.9f}}, glm::vec3(0.0f)));
    auto r = Simulator::create(s);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().describe().find("bad.json"), std::string::npos);
    EXPECT_NE(r.error().describe().find("fluid[0]"), std::string::npos);
    s.fluid.clear();
    s.params.radius = -1.0f;
    EXPECT_FALSE(Simulator::create(s).ok());
    // Too many particles (8 m^3 at r = 1 mm: 10^9), and a domain far too large
    // for its radius (the grid's memory): refused up front, not a crash.
    s.params.radius = 1e-3f;
    s.domain = Box{{0, 0, 0}, {2.0f, 2.0f, 2.0f}};
    s.fluid.push_back(block(Box{{0, 0, 0}, {2.0f, 2.0f, 2.0f}}, glm::vec3(0.0f)));
    auto many = Simulator::create(s);
    ASSERT_FALSE(many.ok());
    EXPECT_NE(many.error().describe().find("particles"), std::string::npos) << many.error().describe();
    {
        Scene flood = tank(0.01f);
        flood.domain = Box{{0, 0, 0}, {1, 1, 1}};
        Emitter e;
        e.position = {0.5f, 0.5f, 0.5f};
        e.rate = 1e30f;  // particles per second
        flood.emitters = {e};
        auto r = Simulator::create(flood);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().describe().find("emitters[0]"), std::string::npos) << r.error().describe();
    }
    for (float side : {1e6f}) {
        s.domain = Box{{0, 0, 0}, {side, side, side}};
        auto big = Simulator::create(s);
        ASSERT_FALSE(big.ok());
        EXPECT_NE(big.error().describe().find("grid cells"), std::string::npos) << big.error().describe();
    }
}

TEST(SimApi, RestoreRoundTripsAndParticlesCarryTheAttributes) {
    auto sim = make(column());
    ASSERT_TRUE(sim->advanceTo(0.05).ok());
    const ParticleSet set = sim->particles();
    ASSERT_NE(set.find(kAttrId), nullptr);
    ASSERT_NE(set.find(kAttrVelocity), nullptr);
    ASSERT_NE(set.find(kAttrDensity), nullptr);
    EXPECT_EQ(set.find(kAttrVelocity)->count(), set.size());
    auto other = make(column());
    ASSERT_TRUE(other->restore(set, 0.05).ok());
    EXPECT_EQ(other->time(), 0.05);
    ParticleSet back = other->particles();
    // Same particles (the restore re-sorts them in z order): compare by id.
    std::vector<glm::vec3> a(set.size()), b(set.size());
    for (std::size_t i = 0; i < set.size(); ++i) a[std::size_t(set.find(kAttrId)->ints[i])] = set.positions[i];
    for (std::size_t i = 0; i < back.size(); ++i) b[std::size_t(back.find(kAttrId)->ints[i])] = back.positions[i];
    EXPECT_EQ(a, b);
    // Outside the domain: refused.
    ParticleSet bad = set;
    bad.positions[0].y = 5.0f;
    EXPECT_FALSE(other->restore(bad, 0.0).ok());
}

// ---------------------------------------------------------------- validation

namespace {

struct FrontPoint {
    double T, xOverA;
};

// The Martin & Moyce (1952) n^2 = 2 front, table 2 rows (tests/data/martin_moyce_1952.csv).
std::vector<FrontPoint> martinMoyceTable() {
    std::vector<FrontPoint> out;
    std::FILE* f = std::fopen(MENISCUS_TEST_DATA "/martin_moyce_1952.csv", "r");
    if (!f) return out;
    char line[256];
    while (std::fgets(line, sizeof line, f)) {
        double T, x, a;
        char source[64];
        if (line[0] == '#' || std::sscanf(line, "%lf,%lf,%lf,%63s", &T, &x, &a, source) != 4) continue;
        if (std::string(source) == "table2") out.push_back({T, x});
    }
    std::fclose(f);
    return out;
}

// The surge front: the 99.5th percentile of x (a lone droplet ahead is not the front).
double frontX(const Simulator& sim) {
    std::vector<float> x;
    for (const glm::vec3& p : sim.positions()) x.push_back(p.x);
    const std::size_t k = std::size_t(0.995 * double(x.size() - 1));
    std::nth_element(x.begin(), x.begin() + std::ptrdiff_t(k), x.end());
    return double(x[k]);
}

}  // namespace

TEST(SimValidation, MartinMoyceSurgeFront) {
    onEachSimdPath([](SimdPath) {
    auto scene = readScene(MENISCUS_SOURCE_DIR "/scenes/martin_moyce.json");
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    const double a = 0.05715, g = 9.81, timeUnit = std::sqrt(a / (2.0 * g));  // T = t sqrt(2g/a)
    const float r = float(a / 20.0);  // coarser than the scene's a/40, for CI: 10 x 20 x 4 particles
    scene->params.radius = r;
    // The column's free faces r beyond a and 2a, as the scene does for its own r.
    scene->fluid[0].box.max.x = float(a) + r;
    scene->fluid[0].box.max.y = float(2.0 * a) + r;
    auto sim = make(*scene);
    ASSERT_TRUE(sim);
    ASSERT_EQ(sim->size(), 10u * 20u * 4u);
    const auto table = martinMoyceTable();
    ASSERT_GE(table.size(), 10u);
    int compared = 0;
    for (const FrontPoint& p : table) {
        if (p.T < 1.0 || p.T > 3.0) continue;
        ASSERT_TRUE(sim->advanceTo(p.T * timeUnit).ok());
        const double z = frontX(*sim) / a;
        std::printf("Martin & Moyce: T = %.2f  measured x/a = %.2f  simulated %.2f  (%+.1f %%)\n", p.T, p.xOverA, z,
                    100.0 * (z - p.xOverA) / p.xOverA);
        EXPECT_NEAR(z, p.xOverA, 0.12 * p.xOverA) << "T = " << p.T;
        ++compared;
    }
    EXPECT_GE(compared, 8);
    });
}

// The shipped glass (a triangle-mesh collider, scenes/glass.obj) under its
// nozzle: no particle ever enters the glass's walls, and what is poured
// collects inside the cup (inner radius 0.065 m, rim at 0.2 m) instead of
// leaking through the mesh onto the floor (drops that splash over the rim aside).
TEST(SimPhysics, TheMeshGlassHoldsWhatTheNozzlePours) {
    auto scene = readScene(MENISCUS_SOURCE_DIR "/scenes/glass.json");
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    auto sim = make(*scene);
    ASSERT_TRUE(sim);
    auto mesh = readMesh(scene->colliders[0].mesh);
    ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
    const Collider& glass = scene->colliders[0];
    for (glm::vec3& p : mesh->positions) p = p * glass.scale + glass.translate;
    for (double t = 0.1; t <= 1.2 + 1e-9; t += 0.1) {
        const Status st = sim->advanceTo(t);
        ASSERT_TRUE(st.ok()) << st.error().describe();
        for (const glm::vec3& p : sim->positions())
            ASSERT_GE(colliderDistance(glass, &*mesh, p).distance, -1e-5f) << "t = " << t << " at " << p.x << ","
                                                                             << p.y << "," << p.z;
    }
    std::size_t inCup = 0, below = 0;
    for (const glm::vec3& p : sim->positions()) {
        const bool inside = std::hypot(p.x, p.z) < 0.065f && p.y < 0.2f;
        inCup += inside;
        below += !inside && p.y < 0.2f;
    }
    EXPECT_GT(sim->size(), 300u) << "the nozzle poured";
    // The jet splashes off the bottom and a few drops go over the rim (at
    // t = 1.2 s: 19 of 720 outside, on the floor or running down the glass);
    // a leaking mesh would let through far more.
    EXPECT_LT(below, sim->size() / 20) << "outside the glass below its rim";
    EXPECT_GT(inCup, sim->size() * 85 / 100) << "most of it is in the cup (the rest still falling)";
}
}  // namespace sim_test_local
