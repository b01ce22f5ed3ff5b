// Anisotropic kernels (Yu & Turk 2013; core/anisotropy.h) and the ellipsoid
// splat (shared/ellipsoid.h, cpu/splat.cpp): the eigen-solver, the shapes of
// known neighbourhoods (bulk: the sphere; free surface and sheet: flat;
// alone: small), invariances, the exact ray-ellipsoid depth and bounds, and
// the splat's coverage of a one-particle sheet.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include "core/anisotropy.h"
#include "cpu/splat.h"
#include "cpu/thickness.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "render_threads.h"
#include "test_util.h"

namespace anisotropy_test_local {

using namespace meniscus;

namespace {

// A simple cubic lattice of n x n x n particles of spacing s, corner at the origin.
std::vector<glm::vec3> block(int nx, int ny, int nz, float s) {
    std::vector<glm::vec3> p;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) p.push_back(glm::vec3(float(i), float(j), float(k)) * s);
    return p;
}

// The half-axes of a shape: sqrt of q's eigenvalues, descending, and its axes.
glm::dvec3 halfAxes(const EllipsoidShape& e, glm::dmat3* axes = nullptr) {
    glm::dvec3 v;
    glm::dmat3 r;
    symmetricEigen(glm::dmat3(e.q), v, r);
    if (axes) *axes = r;
    return glm::sqrt(glm::max(v, glm::dvec3(0.0)));
}

std::size_t indexOf(const std::vector<glm::vec3>& p, glm::vec3 x) {
    for (std::size_t i = 0; i < p.size(); ++i)
        if (glm::length(p[i] - x) < 1e-6f) return i;
    return p.size();
}

using test::lookAt;

}  // namespace

TEST(Anisotropy, EigenDecompositionReconstructsTheMatrix) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int t = 0; t < 2000; ++t) {
        // Random rotation and eigenvalues, some repeated (the degenerate cases the bulk gives).
        const glm::dvec3 axis = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)) + glm::dvec3(1e-3));
        const glm::dmat3 rot = glm::dmat3(glm::rotate(glm::dmat4(1.0), 3.0 * u(rng), axis));
        glm::dvec3 lam(u(rng), u(rng), u(rng));
        if (t % 4 == 1) lam.y = lam.x;
        if (t % 4 == 2) lam.z = lam.y;
        if (t % 8 == 3) lam = glm::dvec3(lam.x);
        glm::dmat3 a(0.0);
        for (int k = 0; k < 3; ++k) a += lam[k] * glm::outerProduct(rot[k], rot[k]);
        glm::dvec3 v;
        glm::dmat3 r;
        symmetricEigen(a, v, r);
        EXPECT_GE(v[0], v[1]);
        EXPECT_GE(v[1], v[2]);
        glm::dmat3 back(0.0);
        for (int k = 0; k < 3; ++k) back += v[k] * glm::outerProduct(r[k], r[k]);
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) ASSERT_NEAR(back[c][k], a[c][k], 1e-9) << t;
        EXPECT_NEAR(glm::determinant(r), 1.0, 1e-9);  // orthonormal, right-handed
    }
}

TEST(Anisotropy, BulkIsTheSphereFreeSurfaceFlattensAloneShrinks) {
    const float r = 0.01f, s = 2.0f * r;
    std::vector<glm::vec3> p = block(12, 12, 12, s);
    const glm::vec3 lone(-1.0f, -1.0f, -1.0f);
    p.push_back(lone);
    AnisotropyParams params;
    params.smoothing = 0.0f;
    params.keepSurface = false;
    Ellipsoids e;
    computeAnisotropy(p, r, params, e);
    // Isolated: the lone particle, and the block's 8 corners (7 neighbours
    // closer than 2 spacings, under N_eps = 8); edges and faces are not.
    EXPECT_EQ(e.isolated, 9u);
    // Bulk: a sphere of radius r (the lattice's covariance is isotropic).
    const glm::dvec3 bulk = halfAxes(e.shapes[indexOf(p, glm::vec3(6, 6, 6) * s)]);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(bulk[k], r, 1e-4 * r);
    // Middle of the top face (y = 11 s): flat along y, wide along x and z,
    // the volume of the sphere, the ratio at most kr.
    glm::dmat3 axes;
    const glm::dvec3 top = halfAxes(e.shapes[indexOf(p, glm::vec3(6, 11, 6) * s)], &axes);
    EXPECT_NEAR(std::abs(axes[2].y), 1.0, 1e-6);  // the shortest axis is the normal
    EXPECT_LT(top[2], 0.7 * r);
    EXPECT_GT(top[0], 1.2 * r);
    EXPECT_NEAR(top[0] * top[1] * top[2], double(r) * r * r, 1e-6 * r * r * r);
    EXPECT_LE(top[0] / top[2], params.kr * (1.0 + 1e-6));
    // The lone particle: a sphere of kn r.
    const glm::dvec3 alone = halfAxes(e.shapes.back());
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(alone[k], params.kn * r, 1e-6 * r);
    // Without smoothing (and keepSurface) the centres stay put.
    for (std::size_t i = 0; i < p.size(); ++i) ASSERT_EQ(e.centres[i], p[i]);
}

TEST(Anisotropy, KeepSurfaceMovesAFaceOutwardAndNotTheBulkOrASheet) {
    const float r = 0.01f, s = 2.0f * r;
    const std::vector<glm::vec3> p = block(12, 12, 12, s);
    AnisotropyParams params;  // keepSurface on by default
    Ellipsoids e;
    computeAnisotropy(p, r, params, e);
    const std::size_t bulk = indexOf(p, glm::vec3(6, 6, 6) * s), top = indexOf(p, glm::vec3(6, 11, 6) * s);
    EXPECT_LT(glm::length(e.centres[bulk] - p[bulk]), 1e-6f);
    // The top face: moved straight up, its outer side (centre + the short
    // half-axis) back near where the sphere's was (p + r), never beyond.
    const double a3 = halfAxes(e.shapes[top])[2];
    EXPECT_GT(e.centres[top].y, p[top].y + 0.1f * r);
    EXPECT_NEAR(e.centres[top].x, p[top].x, 1e-6f);
    EXPECT_NEAR(e.centres[top].z, p[top].z, 1e-6f);
    const double outer = double(e.centres[top].y) + a3 - double(p[top].y);
    EXPECT_GT(outer, 0.8 * r);
    EXPECT_LE(outer, 1.0001 * r);
    // A sheet's neighbourhood is symmetric: its middle stays put.
    const std::vector<glm::vec3> sheet = block(15, 1, 15, s);
    Ellipsoids f;
    computeAnisotropy(sheet, r, params, f);
    const std::size_t mid = indexOf(sheet, glm::vec3(7, 0, 7) * s);
    EXPECT_LT(glm::length(f.centres[mid] - sheet[mid]), 1e-3f * r);
}

TEST(Anisotropy, SmoothingMovesSurfaceCentresInwardAndLeavesTheBulk) {
    const float r = 0.01f, s = 2.0f * r;
    const std::vector<glm::vec3> p = block(12, 12, 12, s);
    AnisotropyParams params;
    params.smoothing = 1.0f;
    params.keepSurface = false;
    Ellipsoids e;
    computeAnisotropy(p, r, params, e);
    const std::size_t bulk = indexOf(p, glm::vec3(6, 6, 6) * s), top = indexOf(p, glm::vec3(6, 11, 6) * s);
    EXPECT_LT(glm::length(e.centres[bulk] - p[bulk]), 1e-6f);
    // The top face's weighted mean lies below it: smoothing moves it down, not sideways.
    EXPECT_LT(e.centres[top].y, p[top].y - 0.1f * r);
    EXPECT_NEAR(e.centres[top].x, p[top].x, 1e-6f);
    EXPECT_NEAR(e.centres[top].z, p[top].z, 1e-6f);
}

TEST(Anisotropy, ASheetIsFlatAlongItsNormalWhateverItsOrientation) {
    const float r = 0.01f, s = 2.0f * r;
    const std::vector<glm::vec3> flat = block(15, 1, 15, s);  // in the xz plane
    const glm::mat3 rot = glm::mat3(glm::rotate(glm::mat4(1.0f), 0.7f, glm::normalize(glm::vec3(1, 2, 3))));
    std::vector<glm::vec3> turned;
    for (const glm::vec3& x : flat) turned.push_back(rot * x);
    AnisotropyParams params;
    Ellipsoids a, b;
    computeAnisotropy(flat, r, params, a);
    computeAnisotropy(turned, r, params, b);
    const std::size_t mid = indexOf(flat, glm::vec3(7, 0, 7) * s);
    glm::dmat3 axesA, axesB;
    const glm::dvec3 ha = halfAxes(a.shapes[mid], &axesA), hb = halfAxes(b.shapes[mid], &axesB);
    EXPECT_NEAR(ha[0] / ha[2], params.kr, 1e-3);  // clamped at kr
    EXPECT_NEAR(std::abs(axesA[2].y), 1.0, 1e-6);
    // Rotation equivariance: the same axes, turned.
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(hb[k], ha[k], 1e-4 * r);
    EXPECT_NEAR(std::abs(glm::dot(glm::dvec3(rot * glm::vec3(axesA[2])), axesB[2])), 1.0, 1e-4);
}

TEST(Anisotropy, ScaleInvariantAndTheSameForAnyThreadCount) {
    auto set = readParticles(test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo").string());
    ASSERT_TRUE(set) << set.error().describe();
    const std::vector<glm::vec3>& p = set->positions;
    const float r = 0.025f;
    AnisotropyParams params;
    Ellipsoids one, scaled;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        computeAnisotropy(p, r, params, one);
    }
    for (int threads : {2, 3}) {
        Ellipsoids more;
        {
            // An arena of that many slots: 3 threads even on a 2-core machine.
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
            tbb::task_arena arena(threads);
            arena.execute([&] { computeAnisotropy(p, r, params, more); });
        }
        EXPECT_EQ(more.isolated, one.isolated);
        for (std::size_t i = 0; i < p.size(); ++i) {
            ASSERT_EQ(std::memcmp(&one.centres[i], &more.centres[i], sizeof(glm::vec3)), 0) << i << " " << threads;
            ASSERT_EQ(std::memcmp(&one.shapes[i], &more.shapes[i], sizeof(EllipsoidShape)), 0) << i << " " << threads;
        }
    }
    // Scaling positions and radius by 4 (a power of two: exact) scales m by 1/4 and q by 16.
    std::vector<glm::vec3> big;
    for (const glm::vec3& x : p) big.push_back(4.0f * x);
    computeAnisotropy(big, 4.0f * r, params, scaled);
    EXPECT_EQ(scaled.isolated, one.isolated);
    for (std::size_t i = 0; i < p.size(); ++i)
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) {
                ASSERT_NEAR(scaled.shapes[i].m[c][k], one.shapes[i].m[c][k] / 4.0f, 1e-3f / r) << i;
                ASSERT_NEAR(scaled.shapes[i].q[c][k], one.shapes[i].q[c][k] * 16.0f, 1e-5f * 16.0f * r * r) << i;
            }
}

// The AVX2 code (where this CPU has it) and the baseline code give the same
// bits: the same IEEE operations in the same lanes. (On a CPU without AVX2
// both runs take the baseline and the test compares it with itself.)
TEST(Anisotropy, BaselineAndAvx2CodeGiveTheSameBits) {
    auto set = readParticles(test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo").string());
    ASSERT_TRUE(set) << set.error().describe();
    const std::vector<glm::vec3>& p = set->positions;
    AnisotropyParams params;
    params.smoothing = 0.5f;  // the centres too
    Ellipsoids fast, base;
    computeAnisotropy(p, 0.025f, params, fast);
    const bool before = detail::allowAnisotropyAvx2(false);
    computeAnisotropy(p, 0.025f, params, base);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<glm::dmat3> matrices;
    for (int t = 0; t < 200; ++t) {
        glm::dmat3 a;
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k <= c; ++k) a[c][k] = a[k][c] = u(rng);
        if (t % 3 == 1) a[1][1] = a[0][0], a[0][1] = a[1][0] = a[0][2] = a[2][0] = 0.0;  // a double eigenvalue
        matrices.push_back(a);
    }
    std::vector<glm::dvec3> baseValues(matrices.size());
    std::vector<glm::dmat3> baseVectors(matrices.size());
    for (std::size_t t = 0; t < matrices.size(); ++t) symmetricEigen(matrices[t], baseValues[t], baseVectors[t]);
    detail::allowAnisotropyAvx2(before);
    ASSERT_EQ(fast.isolated, base.isolated);
    ASSERT_EQ(std::memcmp(fast.centres.data(), base.centres.data(), p.size() * sizeof(glm::vec3)), 0);
    ASSERT_EQ(std::memcmp(fast.shapes.data(), base.shapes.data(), p.size() * sizeof(EllipsoidShape)), 0);
    for (std::size_t t = 0; t < matrices.size(); ++t) {
        glm::dvec3 values;
        glm::dmat3 vectors;
        symmetricEigen(matrices[t], values, vectors);
        ASSERT_EQ(std::memcmp(&values, &baseValues[t], sizeof values), 0) << t;
        ASSERT_EQ(std::memcmp(&vectors, &baseVectors[t], sizeof vectors), 0) << t;
    }
}

// ---- The ellipsoid splat ------------------------------------------------------

namespace {

// The nearest hit of the pixel ray through (i, j) with the world ellipsoid
// (centre c, half-axes a along the columns of rot), in double, as eye depth;
// NaN for a miss; *grazing when the ray nearly touches it.
double analyticEllipsoidDepth(const Camera& cam, int i, int j, const glm::dvec3& c, const glm::dmat3& rot,
                              const glm::dvec3& a, bool* grazing) {
    const double f = 0.5 * cam.height / std::tan(0.5 * glm::radians(double(cam.fovYDegrees)));
    const glm::dvec3 dv{(i + 0.5 - 0.5 * cam.width) / f, -(j + 0.5 - 0.5 * cam.height) / f, -1.0};
    const glm::dvec3 right(cam.right()), up(cam.trueUp()), back(cam.back());
    const glm::dvec3 dir = dv.x * right + dv.y * up + dv.z * back;  // world, eye depth 1 per unit parameter
    const glm::dvec3 o = glm::dvec3(cam.eye) - c;
    // In the ellipsoid's frame scaled to the unit sphere.
    glm::dvec3 od, dd;
    for (int k = 0; k < 3; ++k) od[k] = glm::dot(rot[k], o) / a[k], dd[k] = glm::dot(rot[k], dir) / a[k];
    const double A = glm::dot(dd, dd), B = glm::dot(dd, od), C = glm::dot(od, od) - 1.0;
    const double disc = B * B - A * C;
    *grazing = std::abs(disc) < 2e-3 * A;  // disc = A (1 - squared miss distance in the unit sphere's space)
    if (disc < 0) return std::nan("");
    return (-B - std::sqrt(disc)) / A;
}

}  // namespace

TEST(EllipsoidSplat, MatchesTheAnalyticEllipsoidAndItsBounds) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int t = 0; t < 12; ++t) {
        const Camera cam = lookAt({0.3f * u(rng), 0.4f + 0.2f * u(rng), 2.0f}, {0.0f, 0.0f, 0.0f});
        const glm::vec3 c(0.3f * u(rng), 0.3f * u(rng), 0.3f * u(rng));
        const glm::vec3 axis = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
        const glm::mat3 rot = glm::mat3(glm::rotate(glm::mat4(1.0f), 3.0f * u(rng), axis));
        const glm::vec3 a(0.2f + 0.1f * u(rng), 0.1f + 0.05f * u(rng), 0.04f + 0.02f * u(rng));
        const EllipsoidShape shape = ellipsoidShape(rot, a);
        const Image<float> depth = cpu::splatDepth(cam, std::span(&c, 1), 1.0f, nullptr, std::span(&shape, 1));
        const cpu::SplatBins bins = cpu::binParticles(cam, std::span(&c, 1), 1.0f, std::span(&shape, 1));
        const cpu::PixelRect rect = bins.rects[0];
        int covered = 0, rectMinX = cam.width, rectMaxX = -1, rectMinY = cam.height, rectMaxY = -1;
        for (int j = 0; j < cam.height; ++j)
            for (int i = 0; i < cam.width; ++i) {
                bool grazing = false;
                const double z = analyticEllipsoidDepth(cam, i, j, glm::dvec3(c), glm::dmat3(rot), glm::dvec3(a), &grazing);
                if (!std::isnan(z)) {  // the rectangle is the hit pixels' bounding box, give or take grazing rays
                    rectMinX = std::min(rectMinX, i), rectMaxX = std::max(rectMaxX, i);
                    rectMinY = std::min(rectMinY, j), rectMaxY = std::max(rectMaxY, j);
                    EXPECT_TRUE(i >= rect.x0 && i < rect.x1 && j >= rect.y0 && j < rect.y1) << t << ": " << i << "," << j;
                }
                if (grazing) continue;
                const float got = depth.at(i, j);
                if (std::isnan(z)) {
                    EXPECT_TRUE(std::isinf(got)) << t << ": " << i << "," << j;
                } else {
                    ++covered;
                    EXPECT_LE(std::abs(got - z) / z, 2e-5) << t << ": " << i << "," << j;
                }
            }
        EXPECT_GT(covered, 50) << t;
        // Tight: no more than a pixel of slack on any side.
        EXPECT_GE(rectMinX, rect.x0 - 1);
        EXPECT_LE(rect.x0, rectMinX);
        EXPECT_LE(rect.x1 - 1 - rectMaxX, 1);
        EXPECT_LE(rect.y0, rectMinY);
        EXPECT_LE(rect.y1 - 1 - rectMaxY, 1);
        EXPECT_GE(rectMinY - rect.y0, 0);
        EXPECT_LE(rectMinX - rect.x0, 1);
        EXPECT_LE(rectMinY - rect.y0, 1);
    }
}

TEST(EllipsoidSplat, TheSphereShapeGivesTheSphereSplat) {
    auto set = readParticles(test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo").string());
    ASSERT_TRUE(set) << set.error().describe();
    const float r = 0.025f;
    const Camera cam = lookAt({2.5f, 2.1f, 2.9f}, {0.43f, 0.45f, 0.0f}, 320, 180);
    const std::vector<EllipsoidShape> spheres(set->positions.size(), sphereShape(r));
    ThicknessParams tp;
    const auto a = cpu::splatDepthAndThickness(cam, set->positions, r, tp);
    const auto b = cpu::splatDepthAndThickness(cam, set->positions, r, tp, nullptr, spheres);
    int fluid = 0;
    for (std::size_t k = 0; k < a.depth.pixels.size(); ++k) {
        ASSERT_EQ(std::isinf(a.depth.pixels[k]), std::isinf(b.depth.pixels[k])) << k;
        if (std::isinf(a.depth.pixels[k])) continue;
        ++fluid;
        EXPECT_NEAR(b.depth.pixels[k], a.depth.pixels[k], 2e-5f * a.depth.pixels[k]) << k;
        EXPECT_NEAR(b.thickness.pixels[k], a.thickness.pixels[k], 1e-4f * r + 1e-4f * a.thickness.pixels[k]) << k;
    }
    EXPECT_GT(fluid, 1000);
}

TEST(EllipsoidSplat, OneParticleSheetAtRestSpacingIsClosed) {
    // A sheet one particle thick at the rest spacing 2r, seen face on: the
    // spheres leave a hole at every corner of four; the flattened ellipsoids
    // (wider than r along the sheet) cover it all, at a depth within r/2 of
    // the sheet's plane.
    const float r = 0.01f, s = 2.0f * r;
    std::vector<glm::vec3> p = block(30, 30, 1, s);
    const glm::vec3 mid = glm::vec3(14.5f, 14.5f, 0.0f) * s;
    const Camera cam = lookAt(mid + glm::vec3(0.0f, 0.0f, 0.5f), mid, 200, 200);
    AnisotropyParams params;
    params.smoothing = 0.0f;
    Ellipsoids e;
    computeAnisotropy(p, r, params, e);
    const Image<float> spheres = cpu::splatDepth(cam, p, r);
    const Image<float> ellipsoids = cpu::splatDepth(cam, e.centres, r, nullptr, e.shapes);
    // The inner part of the sheet (the outermost two rows of particles see half a neighbourhood).
    const float f = cam.focalPx(), halfPx = 12.0f * s * f / 0.5f;
    int holesSpheres = 0, holesEllipsoids = 0, inner = 0;
    for (int j = 0; j < cam.height; ++j)
        for (int i = 0; i < cam.width; ++i) {
            if (std::abs(i + 0.5f - 100.0f) > halfPx || std::abs(j + 0.5f - 100.0f) > halfPx) continue;
            ++inner;
            holesSpheres += std::isinf(spheres.at(i, j));
            const float z = ellipsoids.at(i, j);
            holesEllipsoids += std::isinf(z);
            if (!std::isinf(z)) {
                EXPECT_NEAR(z, 0.5f, 0.5f * r) << i << "," << j;
            }
        }
    EXPECT_GT(inner, 10000);
    EXPECT_GT(holesSpheres, inner / 20);  // the spheres' gaps: 1 - pi/4 of the area between centres
    EXPECT_EQ(holesEllipsoids, 0);
}

// ---- Through the Renderer -----------------------------------------------------

TEST(AnisotropyPipeline, RendersWithItsTimingLineTheSameForAnyThreadCount) {
    auto set = readParticles(test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo").string());
    ASSERT_TRUE(set) << set.error().describe();
    RenderSettings s;
    s.radiusM = 0.025f;
    s.camera = lookAt({2.5f, 2.1f, 2.9f}, {0.43f, 0.45f, 0.0f}, 192, 108);
    s.anisotropy.enabled = true;
    std::vector<StageTime> times;
    const Aovs one = test::renderOnThreads(set->positions, s, 1, &times);
    const Aovs two = test::renderOnThreads(set->positions, s, 2);
    ASSERT_FALSE(one.depth.empty());
    EXPECT_TRUE(std::any_of(times.begin(), times.end(), [](const StageTime& t) { return t.stage == "anisotropy"; }));
    EXPECT_EQ(std::memcmp(one.color.pixels.data(), two.color.pixels.data(), one.color.pixels.size() * sizeof(glm::vec4)), 0);
    EXPECT_EQ(std::memcmp(one.depth.pixels.data(), two.depth.pixels.data(), one.depth.pixels.size() * sizeof(float)), 0);
    // The raw depth is the ellipsoids' splat, not the spheres'.
    s.anisotropy.enabled = false;
    auto spheres = Renderer().render(set->positions, s);
    ASSERT_TRUE(spheres);
    EXPECT_NE(std::memcmp(one.rawDepth.pixels.data(), spheres->rawDepth.pixels.data(),
                          one.rawDepth.pixels.size() * sizeof(float)),
              0);
    // Parameters out of range are an error naming the field.
    s.anisotropy.enabled = true;
    s.anisotropy.kr = 0.5f;
    auto bad = Renderer().render(set->positions, s);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().describe().find("anisotropy.kr"), std::string::npos) << bad.error().describe();
}

// ---- The particles' own radii -------------------------------------------------

TEST(ParticleRadii, TheViewTakesRadiusOrPscale) {
    ParticleSet set;
    set.positions = {{0, 0, 0}, {1, 0, 0}};
    set.attributes.push_back({"pscale", AttributeType::Float, 1, {0.5f, 0.25f}, {}});
    ParticleView v = ParticleView::of(set);
    ASSERT_TRUE(v.radius.present());
    EXPECT_EQ(v.radius[1], 0.25f);
    set.attributes.push_back({"radius", AttributeType::Float, 1, {0.1f, 0.2f}, {}});
    v = ParticleView::of(set);
    EXPECT_EQ(v.radius[0], 0.1f);  // "radius" first
    set.attributes.clear();
    EXPECT_FALSE(ParticleView::of(set).radius.present());
}

TEST(ParticleRadii, EachParticleIsDrawnAtItsOwnRadius) {
    // Two particles side by side, the right one twice the radius in its
    // attribute: the raw depth at each centre pixel is its own sphere's front.
    const float r = 0.05f;
    std::vector<glm::vec3> p = {{-0.3f, 0.0f, 0.0f}, {0.3f, 0.0f, 0.0f}};
    const std::vector<float> radii = {r, 2.0f * r};
    RenderSettings s;
    s.radiusM = r;
    s.camera = lookAt({0.0f, 0.0f, 2.0f}, {0.0f, 0.0f, 0.0f}, 480, 240);
    s.scene.background = false;
    s.anisotropy.enabled = false;  // two lone particles: spheres of their radii (the kernels would shrink them)
    ParticleView view(p);
    view.radius = StridedView<float>(std::span<const float>(radii));
    auto own = Renderer().render(view, s);
    ASSERT_TRUE(own) << own.error().describe();
    auto pixelOf = [&](glm::vec3 x) {
        const glm::vec3 v = s.camera.toView(x);
        const float f = s.camera.focalPx();
        return glm::ivec2(int(240.0f + f * v.x / -v.z), int(120.0f - f * v.y / -v.z));
    };
    const glm::ivec2 a = pixelOf(p[0]), b = pixelOf(p[1]);
    // The nearest eye depth of a sphere is its centre's, 2, less its radius:
    // the least raw depth around its centre pixel (flat there to second order).
    auto front = [](const Image<float>& z, glm::ivec2 c) {
        float m = std::numeric_limits<float>::infinity();
        for (int y = c.y - 3; y <= c.y + 3; ++y)
            for (int x = c.x - 3; x <= c.x + 3; ++x) m = std::min(m, z.at(x, y));
        return m;
    };
    EXPECT_NEAR(front(own->rawDepth, a), 2.0f - r, 0.01f * r);
    EXPECT_NEAR(front(own->rawDepth, b), 2.0f - 2.0f * r, 0.01f * r);
    // Without them (an explicit --radius): both at the radius.
    s.particleRadii = false;
    auto uniform = Renderer().render(view, s);
    ASSERT_TRUE(uniform);
    EXPECT_NEAR(front(uniform->rawDepth, b), 2.0f - r, 0.01f * r);
    // The anisotropy keeps each lone particle's own size: kn times its radius.
    s.particleRadii = true;
    s.anisotropy.enabled = true;
    auto lone = Renderer().render(view, s);
    ASSERT_TRUE(lone);
    EXPECT_NEAR(front(lone->rawDepth, b), 2.0f - s.anisotropy.kn * 2.0f * r, 0.01f * r);
    // A radius that is not a positive number of metres is an error naming the particle.
    const std::vector<float> bad = {r, -1.0f};
    view.radius = StridedView<float>(std::span<const float>(bad));
    auto err = Renderer().render(view, s);
    ASSERT_FALSE(err);
    EXPECT_NE(err.error().describe().find("particle 1 has radius"), std::string::npos) << err.error().describe();
}

TEST(ParticleRadii, AUniformRadiusAttributeRendersLikeTheRadius) {
    auto set = readParticles(test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo").string());
    ASSERT_TRUE(set) << set.error().describe();
    RenderSettings s;
    s.radiusM = 0.025f;
    s.camera = lookAt({2.5f, 2.1f, 2.9f}, {0.43f, 0.45f, 0.0f}, 192, 108);
    auto plain = Renderer().render(set->positions, s);
    set->attributes.push_back({"radius", AttributeType::Float, 1, std::vector<float>(set->size(), 0.025f), {}});
    auto own = Renderer().render(ParticleView::of(*set), s);
    ASSERT_TRUE(plain && own);
    for (std::size_t k = 0; k < plain->rawDepth.pixels.size(); ++k) {
        const float a = plain->rawDepth.pixels[k], b = own->rawDepth.pixels[k];
        ASSERT_EQ(std::isinf(a), std::isinf(b)) << k;
        if (!std::isinf(a)) {
            ASSERT_NEAR(b, a, 2e-5f * a) << k;
        }
    }
}

TEST(ParticleRadii, AnisotropyKeepsEachParticlesOwnVolume) {
    const float r = 0.01f, s = 2.0f * r;
    const std::vector<glm::vec3> p = block(12, 12, 12, s);
    const std::vector<float> radii(p.size(), 1.5f * r);
    Ellipsoids e;
    computeAnisotropy(p, r, AnisotropyParams{}, e, radii);
    const glm::dvec3 bulk = halfAxes(e.shapes[indexOf(p, glm::vec3(6, 6, 6) * s)]);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(bulk[k], 1.5 * r, 1e-4 * r);
    const glm::dvec3 top = halfAxes(e.shapes[indexOf(p, glm::vec3(6, 11, 6) * s)]);
    EXPECT_NEAR(top[0] * top[1] * top[2], std::pow(1.5 * r, 3.0), 1e-6 * std::pow(1.5 * r, 3.0));
}

TEST(AnisotropyPipeline, AOneParticleSheetShadesEvenlyWithoutHoles) {
    // A sheet one particle thick at rest spacing, seen from above at an angle,
    // rendered whole: with the ellipsoids every pixel over its inner part is
    // liquid, and no pixel is darker or greyer than the median of its 5x5
    // neighbourhood by more than 0.06 in luminance or 0.04 in chroma (linear
    // RGB; the sheet's own shading varies smoothly).
    const float r = 0.01f, s = 2.0f * r;
    const std::vector<glm::vec3> p = block(40, 1, 40, s);
    const glm::vec3 mid = glm::vec3(19.5f, 0.0f, 19.5f) * s;
    RenderSettings rs;
    rs.radiusM = r;
    rs.camera = lookAt(mid + glm::vec3(0.0f, 0.6f, 0.45f), mid, 240, 180);
    rs.scene.background = false;
    rs.anisotropy.enabled = true;
    setFilterIterations(rs.filter, 1);
    auto img = Renderer().render(p, rs);
    ASSERT_TRUE(img) << img.error().describe();
    auto lum = [](glm::vec4 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; };
    auto chroma = [](glm::vec4 c) { return std::max({c.r, c.g, c.b}) - std::min({c.r, c.g, c.b}); };
    struct Count {
        int inner = 0, holes = 0, dark = 0, grey = 0;
    };
    auto count = [&](const Aovs& a) {
        Count n;
        for (int y = 40; y < 140; ++y)
            for (int x = 60; x < 180; ++x) {
                ++n.inner;
                n.holes += std::isinf(a.rawDepth.at(x, y));
                std::vector<float> l, c;
                for (int j = -2; j <= 2; ++j)
                    for (int i = -2; i <= 2; ++i) {
                        l.push_back(lum(a.color.at(x + i, y + j)));
                        c.push_back(chroma(a.color.at(x + i, y + j)));
                    }
                std::nth_element(l.begin(), l.begin() + 12, l.end());
                std::nth_element(c.begin(), c.begin() + 12, c.end());
                n.dark += lum(a.color.at(x, y)) < l[12] - 0.06f;
                n.grey += chroma(a.color.at(x, y)) < c[12] - 0.04f;
            }
        return n;
    };
    const Count e = count(*img);
    EXPECT_GT(e.inner, 10000);
    EXPECT_EQ(e.holes, 0);
    EXPECT_EQ(e.dark, 0);
    EXPECT_EQ(e.grey, 0);
    // The spheres leave holes there, darker and greyer than the liquid around
    // them (the transparent background shows through) unless the hole
    // filling closes them (on by default): the bounds see them.
    rs.anisotropy.enabled = false;
    auto filled = Renderer().render(p, rs);
    ASSERT_TRUE(filled);
    EXPECT_EQ(count(*filled).holes, 0);
    rs.holeFill.enabled = false;
    rs.thickness.minRadii = 0.0f;
    auto spheres = Renderer().render(p, rs);
    ASSERT_TRUE(spheres);
    const Count sp = count(*spheres);
    EXPECT_GT(sp.holes, 100);
    EXPECT_GT(sp.dark + sp.grey, 100);
}
}  // namespace anisotropy_test_local
