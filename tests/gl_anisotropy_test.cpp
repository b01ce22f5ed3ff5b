// GL anisotropic kernels (docs/pipeline.md#anisotropic-kernels,
// src/gl/anisotropy.cpp) against the CPU reference computeAnisotropy on the
// same particles: the real frame (default parameters; smoothing and the
// particles' own radii), a sheet one particle thick (flat ellipsoids of a
// known shape), far outliers (the CPU's hashed grid), and the default
// pipeline's depth on GL (the ellipsoids made on the GPU) against the CPU's.
//
// Tolerances, and why: both find the same neighbours (the distance test is
// the same float arithmetic, `precise` on the GPU), so the same particles are
// lone spheres, bit for bit. The ellipsoids: the GPU sums in float and runs
// the closed-form eigen-decomposition (src/shared/anisotropy.h) in float, the
// CPU in double. The shape's matrices m and q are smooth functions of the
// covariance even where its eigenvectors are not (nearly equal eigenvalues:
// the bulk), so they differ by float rounding times the decomposition's
// conditioning: measured at most 3.4e-5 of the matrix's largest entry on the
// real frame (llvmpipe); allowed kShapeRel = 1e-3. The centres: at most
// kCentreRadii = 1e-3 r apart (the free surface's shift is r - a3 times a
// ratio of the sums). The pipeline: the GL backend's parity tolerance
// (tests/gl_backend_test.cpp: depth 1e-5 relative, coverage 0.05%) on all
// but kDepthFraction = 0.5% of the covered pixels, none beyond
// kDepthCap = 5e-3: the existing tolerance assumes bit-identical inputs, and
// a ray grazing an ellipsoid that moved by 1e-5 r may meet the one behind
// (measured on frame 21 at 320x180: the raw depth 1 pixel of 11,636 beyond
// 1e-5, at 8.9e-4; the smoothed depth 28, all under 1e-4; the ray cast, whose
// march starts on the splat, 3, at most 3.4e-3).
// Skips only when no headless GL 4.3 context can be created at all.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/anisotropy.h"
#include "gl/anisotropy.h"
#include "gl_test_util.h"
#include "meniscus/renderer.h"
#include "test_util.h"

namespace gl_anisotropy_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

// The GL backend's own ellipsoids (GlTest has it take the host's).
class GlAnisotropy : public GlTest {
protected:
    void SetUp() override {
        GlTest::SetUp();
        setenv("MENISCUS_GL_HOST_ANISOTROPY", "0", 1);
    }
};

constexpr double kShapeRel = 1e-3, kCentreRadii = 1e-3;
constexpr double kDepthRel = 1e-5, kDepthFraction = 5e-3, kDepthCap = 5e-3;

double maxAbs(const glm::mat3& a) {
    double m = 0.0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) m = std::max(m, double(std::abs(a[c][r])));
    return m;
}

bool isLone(const EllipsoidShape& e, float r) {
    const glm::mat3 q = glm::mat3(r * r);
    return e.q == q;
}

struct Diff {
    double shapeRel = 0.0;    // max over particles of max |m_gpu - m_cpu| / max |m_cpu| (and q)
    double centreRadii = 0.0; // max |c_gpu - c_cpu| / r
    int loneDiffer = 0;       // a lone sphere on one side only
};

Diff compare(const Ellipsoids& cpu, const Ellipsoids& gpu, float r, float kn, std::span<const float> radii = {}) {
    Diff d;
    EXPECT_EQ(cpu.shapes.size(), gpu.shapes.size());
    EXPECT_EQ(cpu.centres.size(), gpu.centres.size());
    for (std::size_t i = 0; i < cpu.shapes.size() && i < gpu.shapes.size(); ++i) {
        const float ri = radii.empty() ? r : radii[i];
        const EllipsoidShape &a = cpu.shapes[i], &b = gpu.shapes[i];
        d.loneDiffer += isLone(a, kn * ri) != isLone(b, kn * ri);
        d.shapeRel = std::max(d.shapeRel, maxAbs(b.m - a.m) / maxAbs(a.m));
        d.shapeRel = std::max(d.shapeRel, maxAbs(b.q - a.q) / maxAbs(a.q));
        d.centreRadii = std::max(d.centreRadii, double(glm::length(gpu.centres[i] - cpu.centres[i])) / ri);
    }
    std::printf("  shapes rel %.3g, centres %.3g r, lone spheres differing %d\n", d.shapeRel, d.centreRadii,
                d.loneDiffer);
    return d;
}

void expectSame(const Diff& d) {
    EXPECT_EQ(d.loneDiffer, 0);
    EXPECT_LE(d.shapeRel, kShapeRel);
    EXPECT_LE(d.centreRadii, kCentreRadii);
}

}  // namespace

TEST_F(GlAnisotropy, TheRealFrameMatchesTheCpu) {
    const RealFrame& f = realFrame();
    ASSERT_FALSE(f.positions.empty());
    std::vector<float> radii(f.positions.size());
    for (std::size_t i = 0; i < radii.size(); ++i) radii[i] = f.radius * (0.8f + 0.4f * float(i % 7) / 6.0f);
    // 0: the defaults; 1: smoothed centres, no surface shift; 2: the own radii, more neighbours needed.
    for (int variant = 0; variant < 3; ++variant) {
        SCOPED_TRACE(variant);
        AnisotropyParams p;
        if (variant == 1) p.smoothing = 0.9f, p.keepSurface = false;
        if (variant == 2) p.minNeighbours = 20, p.kr = 2.0f;
        const std::span<const float> own = variant == 2 ? std::span<const float>(radii) : std::span<const float>();
        Ellipsoids cpu;
        computeAnisotropy(f.positions, f.radius, p, cpu, own);
        auto gpu = gl::anisotropyOnGpu(f.positions, f.radius, p, own);
        ASSERT_TRUE(gpu) << gpu.error().describe();
        const Diff d = compare(cpu, *gpu, f.radius, p.kn, own);
        expectSame(d);
        // Some of each kind: the comparison covers lone spheres and ellipsoids.
        int lone = 0;
        for (std::size_t i = 0; i < cpu.shapes.size(); ++i) lone += isLone(cpu.shapes[i], p.kn * (own.empty() ? f.radius : own[i]));
        EXPECT_GT(lone, 0);
        EXPECT_LT(lone, int(cpu.shapes.size()) / 2);
    }
}

// The GPU's result does not depend on the order its atomics ran in: the
// same bits twice.
TEST_F(GlAnisotropy, TheSameBitsEveryRun) {
    const RealFrame& f = realFrame();
    ASSERT_FALSE(f.positions.empty());
    auto a = gl::anisotropyOnGpu(f.positions, f.radius, AnisotropyParams{});
    auto b = gl::anisotropyOnGpu(f.positions, f.radius, AnisotropyParams{});
    ASSERT_TRUE(a && b);
    ASSERT_EQ(a->shapes.size(), b->shapes.size());
    EXPECT_EQ(std::memcmp(a->shapes.data(), b->shapes.data(), a->shapes.size() * sizeof(EllipsoidShape)), 0);
    EXPECT_EQ(std::memcmp(a->centres.data(), b->centres.data(), a->centres.size() * sizeof(glm::vec3)), 0);
}

// A sheet one particle thick (a square lattice of spacing 2r in a tilted
// plane): away from its edges every neighbourhood is flat, the covariance's
// third eigenvalue 0, floored to 1/kr of the others: half-axes
// r (1, 1, 1/kr) (kr)^(1/3), the shortest along the plane's normal, the
// centres where they were (the neighbourhood is symmetric).
TEST_F(GlAnisotropy, ASheetGivesFlatEllipsoids) {
    const float r = 0.01f;
    const glm::vec3 u = glm::normalize(glm::vec3(1.0f, 0.2f, 0.1f));
    const glm::vec3 normal = glm::normalize(glm::cross(u, glm::vec3(0.0f, 0.3f, 1.0f)));
    const glm::vec3 v = glm::cross(normal, u);
    const int n = 24;
    std::vector<glm::vec3> p;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) p.push_back(glm::vec3(0.3f, -0.2f, 0.5f) + 2.0f * r * (float(i) * u + float(j) * v));
    const AnisotropyParams params;
    auto gpu = gl::anisotropyOnGpu(p, r, params);
    ASSERT_TRUE(gpu) << gpu.error().describe();
    Ellipsoids cpu;
    computeAnisotropy(p, r, params, cpu);
    expectSame(compare(cpu, *gpu, r, params.kn));
    const double k = std::cbrt(double(params.kr));
    const double along = r * k, across = r * k / double(params.kr);
    // q = a1^2 (I - n n^T) + a3^2 n n^T.
    const glm::dmat3 nn = glm::outerProduct(glm::dvec3(normal), glm::dvec3(normal));
    const glm::dmat3 expected = along * along * (glm::dmat3(1.0) - nn) + across * across * nn;
    const int margin = int(std::ceil(params.neighbourRadii / 2.0f));  // R = 4 r = 2 spacings
    int checked = 0;
    for (int j = margin; j < n - margin; ++j)
        for (int i = margin; i < n - margin; ++i) {
            const std::size_t k2 = std::size_t(j * n + i);
            const glm::dmat3 q(gpu->shapes[k2].q);
            for (int c = 0; c < 3; ++c)
                for (int rr = 0; rr < 3; ++rr) EXPECT_NEAR(q[c][rr], expected[c][rr], 1e-4 * along * along);
            EXPECT_LE(glm::length(gpu->centres[k2] - p[k2]), 1e-5f * r);
            ++checked;
        }
    EXPECT_GT(checked, 300);
}

// Far outliers (a drop a kilometre away, a lone one at 1e7 m): the CPU takes
// its hashed grid, the GPU hashes cells always; the same neighbourhoods.
TEST_F(GlAnisotropy, FarOutliersMatchTheCpu) {
    const RealFrame& f = realFrame();
    ASSERT_FALSE(f.positions.empty());
    std::vector<glm::vec3> p(f.positions.begin(), f.positions.begin() + std::min<std::size_t>(20000, f.positions.size()));
    const std::size_t body = p.size();
    for (int k = 0; k < 27; ++k)  // a small cluster 1 km away
        p.push_back(glm::vec3(1000.0f, 0.0f, 0.0f) + 1.5f * f.radius * glm::vec3(float(k % 3), float(k / 3 % 3), float(k / 9)));
    p.push_back(glm::vec3(-1e7f, 3e6f, 1e7f));
    const AnisotropyParams params;
    Ellipsoids cpu;
    computeAnisotropy(p, f.radius, params, cpu);
    auto gpu = gl::anisotropyOnGpu(p, f.radius, params);
    ASSERT_TRUE(gpu) << gpu.error().describe();
    expectSame(compare(cpu, *gpu, f.radius, params.kn));
    EXPECT_TRUE(isLone(gpu->shapes.back(), params.kn * f.radius));
    EXPECT_FALSE(isLone(gpu->shapes[body + 13], params.kn * f.radius));  // the cluster's centre: 26 neighbours
}

// The default pipeline (anisotropy on) with the ellipsoids made on the GPU:
// the depth within the GL backend's parity tolerance of the CPU's, with the
// ray cast's larger shapes too; timed, the GL anisotropy line is the GPU's
// passes and the host's part of it is its own line.
TEST_F(GlAnisotropy, TheDefaultPipelineMatchesTheCpu) {
    const RealFrame& f = realFrame();
    ASSERT_FALSE(f.positions.empty());
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    RenderSettings s;
    s.radiusM = f.radius;
    s.camera = realFrameCamera(320, 180);
    ASSERT_TRUE(s.anisotropy.enabled);
    for (int variant = 0; variant < 2; ++variant) {
        SCOPED_TRACE(variant);
        s.raycast.enabled = variant == 1;
        std::vector<StageTime> times;
        auto a = cpu.render(f.positions, s);
        auto b = gl->render(f.positions, s, &times);
        ASSERT_TRUE(a.ok()) << a.error().describe();
        ASSERT_TRUE(b.ok()) << b.error().describe();
        const DepthDiff raw = compareDepth(a->rawDepth, b->rawDepth), z = compareDepth(a->depth, b->depth);
        EXPECT_LE(raw.coverageDiffer, int(5e-4 * raw.coveredCpu) + 2);
        EXPECT_LE(z.coverageDiffer, int(5e-4 * z.coveredCpu) + 2);
        expectDepthNearlySame(a->rawDepth, b->rawDepth, kDepthRel, kDepthFraction, kDepthCap);
        expectDepthNearlySame(a->depth, b->depth, kDepthRel, kDepthFraction, kDepthCap);
        int host = 0, device = 0;
        for (const StageTime& t : times) {
            host += t.stage == "host: anisotropy";
            device += t.stage == "anisotropy";
        }
        EXPECT_EQ(host, 1);
        EXPECT_EQ(device, 1);
    }
}

// Unset, the choice is the driver's: the host's ellipsoids on llvmpipe
// (faster there, docs/performance.md), the GPU's on a hardware GPU.
TEST_F(GlAnisotropy, TheDriverChoosesWhereByDefault) {
    const RealFrame& f = realFrame();
    ASSERT_FALSE(f.positions.empty());
    unsetenv("MENISCUS_GL_HOST_ANISOTROPY");
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    RenderSettings s;
    s.radiusM = f.radius;
    s.camera = realFrameCamera(160, 90);
    std::vector<StageTime> times;
    ASSERT_TRUE(gl->render(f.positions, s, &times).ok());
    const bool onGpu = std::any_of(times.begin(), times.end(), [](const StageTime& t) { return t.stage == "host: anisotropy"; });
    EXPECT_EQ(onGpu, gl->backendName().find("llvmpipe") == std::string::npos) << gl->backendName();
}
}  // namespace gl_anisotropy_test_local
