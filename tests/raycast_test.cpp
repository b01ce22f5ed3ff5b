// The ray-cast SPH surface (docs/pipeline.md#ray-cast-surface; RaycastParams,
// core/sph_field.h, cpu/raycast.cpp, shared/sph_surface.h): the kernel and its
// gradient, the field grid against a direct sum (outliers included), a flat
// face found where an independent double-precision bisection puts the iso
// level, a lone particle without a surface, the scene depth bounding the rays,
// the same output for any thread count, and the Renderer and CLI around the
// stage.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "core/sph_field.h"
#include "cpu/raycast.h"
#include "cpu/splat.h"
#include "meniscus/io.h"
#include "meniscus/renderer.h"
#include "shared/sph_surface.h"
#include "surface/field.h"
#include "render_threads.h"
#include "test_util.h"

namespace raycast_test_local {

using namespace meniscus;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// The cubic spline written out again in double (Monaghan 1992), for the
// independent reference below.
double splineW(double q) {
    if (q >= 1.0) return 0.0;
    return q <= 0.5 ? 6.0 * q * q * (q - 1.0) + 1.0 : 2.0 * std::pow(1.0 - q, 3);
}

// F(p) / F0 in double over every particle (no grid), F0 summed over the 2r lattice.
double fieldFraction(const std::vector<glm::vec3>& pts, glm::dvec3 p, double r, double supportRadii) {
    const double h = supportRadii * r;
    double f = 0.0;
    for (const glm::vec3& x : pts) f += splineW(glm::length(p - glm::dvec3(x)) / h);
    double rest = 0.0;
    for (int i = -3; i <= 3; ++i)
        for (int j = -3; j <= 3; ++j)
            for (int k = -3; k <= 3; ++k) rest += splineW(2.0 * r * std::sqrt(double(i * i + j * j + k * k)) / h);
    return f / rest;
}

std::vector<glm::vec3> lattice(int nx, int ny, int nz, float spacing, glm::vec3 origin = glm::vec3(0.0f)) {
    std::vector<glm::vec3> p;
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x) p.push_back(origin + spacing * glm::vec3(x, y, z));
    return p;
}

struct Cast {
    Image<float> start;
    cpu::RaycastImages out;
};

Cast castAll(const std::vector<glm::vec3>& pts, const Camera& cam, float r, const RaycastParams& p,
             const Image<float>* scene = nullptr) {
    SphField field;
    EXPECT_TRUE(buildSphField(pts, r, p, field));
    Cast c;
    c.start = cpu::splatDepth(cam, pts, p.coverRadii * r);
    c.out = cpu::raycastSurface(cam, field, p, r, c.start, scene);
    return c;
}

TEST(SphKernel, IntegratesToOneAndItsGradientIsTheDerivative) {
    // The normalised spline 8/(pi h^3) W integrates to 1: int_0^1 W(q) q^2 dq = 1/32.
    const int n = 20000;
    double integral = 0.0;
    for (int i = 0; i <= n; ++i) {
        const double q = double(i) / n, w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        integral += w * shared::sphKernel(float(q)) * q * q;
    }
    integral /= 3.0 * n;
    EXPECT_NEAR(integral, 1.0 / 32.0, 1e-6);
    EXPECT_EQ(shared::sphKernel(0.0f), 1.0f);
    EXPECT_EQ(shared::sphKernel(0.5f), 0.25f);
    EXPECT_EQ(shared::sphKernel(1.0f), 0.0f);
    // G(q) q = W'(q), against central differences on both branches.
    for (float q : {0.05f, 0.2f, 0.45f, 0.55f, 0.8f, 0.95f}) {
        const double e = 1e-3, d = (splineW(q + e) - splineW(q - e)) / (2 * e);
        EXPECT_NEAR(shared::sphKernelGradient(q) * q, d, 1e-5) << q;
    }
}

TEST(SphKernel, RestValueAndKernelAreTheMesher) {
    // The raycast and the isosurface path agree on F0 (so --surface raycast
    // and --surface mesh find the same level).
    MeshParams mp;
    mp.radiusM = 1.0f;
    mp.field = SurfaceField::Sph;
    const surface::Field mesher = surface::makeField(mp);
    EXPECT_NEAR(shared::sphRestField(defaults::kSphSupportRadii), mesher.rest, 1e-5);
    // The mesher keeps its own copy of the spline (the isosurface path uses
    // nothing of src/shared): the two give the same bits.
    for (int i = 0; i < 1000; ++i) {
        const float d = 4.0f * float(i) / 1000.0f;
        EXPECT_EQ(mesher.sphKernel(d * d), shared::sphKernel(std::sqrt(d * d) * mesher.invSupport)) << d;
    }
}

TEST(SphField, GridSumMatchesTheDirectSumOutliersIncluded) {
    const float r = 0.01f;
    std::vector<glm::vec3> pts = test::jitteredBlock({12, 10, 12}, 2.0f * r, 0.3f, glm::vec3(0.0f));
    // Far outliers: the dense grid would need billions of cells of h.
    pts.push_back({500.0f, 3.0f, -700.0f});
    pts.push_back({-900.0f, 0.0f, 0.0f});
    pts.push_back({-900.0f, 0.01f, 0.02f});
    RaycastParams p;
    SphField field;
    ASSERT_TRUE(buildSphField(pts, r, p, field));
    EXPECT_LE(field.grid.cellCount(), std::size_t(1) << 16);
    const double rest = shared::sphRestField(p.supportRadii);
    for (glm::vec3 q : {glm::vec3(0.1f, 0.1f, 0.1f), glm::vec3(0.05f, 0.19f, 0.11f), glm::vec3(0.23f, 0.0f, 0.0f),
                        glm::vec3(-900.0f, 0.005f, 0.01f), glm::vec3(500.0f, 3.0f, -700.02f)}) {
        float f = 0.0f;
        glm::vec3 g(0.0f);
        evaluateSphField(field, q, f, g);
        EXPECT_NEAR(f / rest, fieldFraction(pts, q, r, p.supportRadii), 1e-5) << q.x << " " << q.y << " " << q.z;
    }
    EXPECT_NEAR(field.isoRaw, 0.5 * rest, 1e-5);
}

TEST(Raycast, AFlatFaceLiesWhereTheIsoLevelIsAndFacesTheEye) {
    // A lattice slab seen face on: the surface is the plane where F = iso F0,
    // found here by bisection in double over all particles; every pixel over
    // the face's inner part sees it at that eye depth (planes stay planes:
    // the camera looks along the face's normal) with the normal (0, 0, 1).
    const float r = 0.01f, s = 2.0f * r;
    const std::vector<glm::vec3> pts = lattice(24, 24, 6, s);
    const glm::vec3 mid(11.5f * s, 11.5f * s, 5.0f * s);
    const Camera cam = test::faceOnCamera(mid, 0.6f, 96, 96);
    RaycastParams p;
    const Cast c = castAll(pts, cam, r, p);
    double lo = mid.z, hi = mid.z + 3.0 * r;  // inside .. outside
    for (int i = 0; i < 60; ++i) {
        const double m = 0.5 * (lo + hi);
        (fieldFraction(pts, {mid.x, mid.y, m}, r, p.supportRadii) >= p.iso ? lo : hi) = m;
    }
    const double planeDepth = double(cam.eye.z) - lo;
    EXPECT_GT(lo - mid.z, 0.5 * r);  // the iso level lies beyond the outer centres
    int checked = 0;
    for (int y = 36; y < 60; ++y)
        for (int x = 36; x < 60; ++x) {
            const float t = c.out.depth.at(x, y);
            ASSERT_TRUE(std::isfinite(t)) << x << "," << y;
            // The face of a lattice is a plane up to bumps far below 0.01 r.
            EXPECT_NEAR(t, planeDepth, 0.01 * r) << x << "," << y;
            const glm::vec3 n = c.out.normal.at(x, y);
            // (The iso-surface of a lattice ripples: its normals lean by up to ~0.5 degrees.)
            EXPECT_GT(n.z, std::cos(glm::radians(1.0f))) << x << "," << y;
            EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
            ++checked;
        }
    EXPECT_EQ(checked, 24 * 24);
    // The centre pixel's ray is the bisection's line: there to 1e-3 r.
    EXPECT_NEAR(c.out.depth.at(48, 48), planeDepth, 1e-3 * r);
    // Every ray started at the splat's front, in front of the surface.
    EXPECT_LT(c.start.at(48, 48), c.out.depth.at(48, 48));
}

TEST(Raycast, ALoneParticleHasNoSurfaceAPairIsOne) {
    // One particle's own density is 1/F0 ~ 0.32 of the rest value, below the
    // 0.5 iso level: its splat is covered, its ray finds nothing. Eight
    // particles at rest spacing reach it: a surface, and a closed one.
    const float r = 0.01f;
    RaycastParams p;
    const Camera cam = test::faceOnCamera(glm::vec3(0.0f), 0.3f, 64, 64);
    const Cast one = castAll({glm::vec3(0.0f)}, cam, r, p);
    EXPECT_TRUE(std::isfinite(one.start.at(32, 32)));
    for (float t : one.out.depth.pixels) EXPECT_FALSE(std::isfinite(t));
    for (const glm::vec3& n : one.out.normal.pixels) EXPECT_EQ(n, glm::vec3(0.0f));
    const Cast cube = castAll(lattice(2, 2, 2, 2.0f * r, glm::vec3(-r)), cam, r, p);
    EXPECT_TRUE(std::isfinite(cube.out.depth.at(32, 32)));
    EXPECT_GT(cube.out.normal.at(32, 32).z, 0.99f);
}

TEST(Raycast, TheSceneDepthEndsTheRays) {
    // A wall just behind the splat's front and in front of the surface: no
    // ray may look past it, so no fluid where it stands; and a ray that would
    // start behind it (a wall in front of the splat) sees nothing either.
    const float r = 0.01f, s = 2.0f * r;
    const std::vector<glm::vec3> pts = lattice(16, 16, 4, s);
    const glm::vec3 mid(7.5f * s, 7.5f * s, 3.0f * s);
    const Camera cam = test::faceOnCamera(mid, 0.5f, 64, 64);
    RaycastParams p;
    const Cast free = castAll(pts, cam, r, p);
    ASSERT_LT(free.start.at(32, 32), free.out.depth.at(32, 32));
    Image<float> wall(64, 64, kInf);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 32; ++x) wall.at(x, y) = 0.5f * (free.start.at(32, 32) + free.out.depth.at(32, 32));
    SphField field;
    ASSERT_TRUE(buildSphField(pts, r, p, field));
    const auto walled = cpu::raycastSurface(cam, field, p, r, free.start, &wall);
    EXPECT_FALSE(std::isfinite(walled.depth.at(20, 32)));
    EXPECT_EQ(walled.depth.at(44, 32), free.out.depth.at(44, 32));
    for (float& z : wall.pixels) z = 0.5f * free.start.at(32, 32);
    const auto hidden = cpu::raycastSurface(cam, field, p, r, free.start, &wall);
    for (float t : hidden.depth.pixels) EXPECT_FALSE(std::isfinite(t));
}

TEST(Raycast, PassingOverQuietCellsChangesNothingButTheCost) {
    // Every covered pixel of the real frame marched again with a field that
    // has no quiet cells: the same depth and normal bits, with fewer field
    // sums when passing over them. And the quiet bits are right: at random
    // points of quiet cells the field is below the iso level.
    auto set = readParticles(test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo").string());
    ASSERT_TRUE(set) << set.error().describe();
    const float r = 0.025f;
    const Camera cam = test::lookAt({2.5f, 2.1f, 2.9f}, {0.43f, 0.45f, 0.0f}, 160, 90);
    RaycastParams p;
    SphField field;
    ASSERT_TRUE(buildSphField(set->positions, r, p, field));
    const Image<float> start = cpu::splatDepth(cam, set->positions, p.coverRadii * r);
    const cpu::RaycastImages ref = cpu::raycastSurface(cam, field, p, r, start, nullptr);
    struct Counting {
        const SphField& field;
        bool skip;
        long* sums;
        void operator()(const glm::vec3& q, float& f, glm::vec3& g) const {
            ++*sums;
            evaluateSphField(field, q, f, g);
        }
        bool quiet(const glm::vec3& q) const { return skip && sphFieldQuiet(field, q); }
        float lastInCell(const glm::vec3& o, const glm::vec3& d, float t) const {
            return skip ? sphFieldLastInCell(field, o, d, t) : t;
        }
    };
    long withSkip = 0, without = 0;
    const float f = cam.focalPx(), invH2 = 1.0f / (field.support * field.support);
    int differ = 0, covered = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            const float t0 = start.at(x, y);
            if (!std::isfinite(t0)) continue;
            const float rx = ((float(x) + 0.5f) - 0.5f * float(cam.width)) / f;
            const float ry = -((float(y) + 0.5f) - 0.5f * float(cam.height)) / f;
            const glm::vec3 dir = shared::sphRayDir(rx, ry, cam.right(), cam.trueUp(), cam.back());
            glm::vec3 g1(0.0f), g2(0.0f);
            const float t1 = shared::sphRaycast(cam.eye, dir, t0, cam.nearM, cam.farM, p.stepRadii * r, p.maxSteps,
                                                p.newtonSteps, field.isoRaw, invH2, g1, Counting{field, true, &withSkip});
            const float t2 = shared::sphRaycast(cam.eye, dir, t0, cam.nearM, cam.farM, p.stepRadii * r, p.maxSteps,
                                                p.newtonSteps, field.isoRaw, invH2, g2, Counting{field, false, &without});
            ++covered;
            differ += std::memcmp(&t1, &t2, sizeof t1) != 0 || g1 != g2;
            differ += std::memcmp(&t1, &ref.depth.at(x, y), sizeof t1) != 0 && std::isfinite(t1);
        }
    EXPECT_GT(covered, 1000);
    EXPECT_EQ(differ, 0);
    EXPECT_LT(withSkip, without * 3 / 4);
    const glm::vec3 lo = field.grid.lo();
    const glm::vec3 extent = glm::vec3(field.grid.dims()) / field.grid.invCell();
    int quiet = 0, loud = 0;
    for (std::uint32_t i = 0; i < 200000; ++i) {
        const glm::vec3 q = lo + extent * glm::vec3(test::hash01(i, 1), test::hash01(i, 2), test::hash01(i, 3));
        float fq = 0.0f;
        glm::vec3 gq(0.0f);
        evaluateSphField(field, q, fq, gq);
        if (sphFieldQuiet(field, q)) {
            ++quiet;
            EXPECT_LT(fq, field.isoRaw) << q.x << " " << q.y << " " << q.z;
        } else {
            ++loud;
        }
    }
    EXPECT_GT(quiet, 1000);
    EXPECT_GT(loud, 1000);
}

TEST(Raycast, SameBitsForAnyThreadCount) {
    auto set = readParticles(test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo").string());
    ASSERT_TRUE(set) << set.error().describe();
    RenderSettings s;
    s.radiusM = 0.025f;
    s.camera = test::lookAt({2.5f, 2.1f, 2.9f}, {0.43f, 0.45f, 0.0f}, 160, 90);
    s.raycast.enabled = true;
    std::vector<StageTime> times;
    const Aovs one = test::renderOnThreads(set->positions, s, 1, &times);
    const Aovs two = test::renderOnThreads(set->positions, s, 2);
    ASSERT_FALSE(one.depth.empty());
    for (const char* stage : {"sph-field", "raycast"})
        EXPECT_TRUE(std::any_of(times.begin(), times.end(), [&](const StageTime& t) { return t.stage == stage; }))
            << stage;
    EXPECT_FALSE(std::any_of(times.begin(), times.end(), [](const StageTime& t) { return t.stage == "smooth"; }));
    EXPECT_EQ(test::differingBits(one.depth, two.depth), 0);
    EXPECT_EQ(test::differingBits(one.normal, two.normal), 0);
    EXPECT_EQ(test::differingBits(one.color, two.color), 0);
}

TEST(RaycastPipeline, TheFilterIsNotUsedAndTheThicknessKeepsItsCalibration) {
    // The ray cast takes the smoothing's place: any filter, the same image.
    // Its splat draws spheres 1.5 r wide, calibrated as such: a slab's
    // thickness stays its true depth, as with the spheres of r.
    const float r = 0.01f, s = 2.0f * r;
    const std::vector<glm::vec3> pts = lattice(20, 20, 10, s);
    const glm::vec3 mid(9.5f * s, 9.5f * s, 9.0f * s);
    RenderSettings rs;
    rs.radiusM = r;
    rs.camera = test::faceOnCamera(mid, 0.6f, 80, 80);
    rs.scene.background = false;
    rs.raycast.enabled = true;
    auto a = Renderer().render(pts, rs);
    ASSERT_TRUE(a) << a.error().describe();
    rs.filter = GaussianParams{};
    auto b = Renderer().render(pts, rs);
    ASSERT_TRUE(b);
    EXPECT_EQ(test::differingBits(a->depth, b->depth), 0);
    EXPECT_EQ(test::differingBits(a->color, b->color), 0);
    rs.raycast.enabled = false;
    auto spheres = Renderer().render(pts, rs);
    ASSERT_TRUE(spheres);
    const float slab = 10.0f * s;
    EXPECT_NEAR(a->thickness.at(40, 40), slab, 0.1f * slab);
    EXPECT_NEAR(spheres->thickness.at(40, 40), slab, 0.1f * slab);
}

TEST(RaycastPipeline, BadParametersAndTheMeshPathAreErrors) {
    RenderSettings rs;
    rs.radiusM = 0.01f;
    rs.camera = test::faceOnCamera(glm::vec3(0.0f), 0.3f, 16, 16);
    rs.raycast.enabled = true;
    rs.raycast.coverRadii = 0.5f;
    auto bad = Renderer().render(std::vector<glm::vec3>{glm::vec3(0.0f)}, rs);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("raycast.coverRadii"), std::string::npos) << bad.error().message;
    rs.raycast.coverRadii = 1.2f;
    rs.raycast.maxSteps = 0;
    EXPECT_FALSE(Renderer().render(std::vector<glm::vec3>{glm::vec3(0.0f)}, rs));
    EXPECT_EQ(checkRaycastParams(RaycastParams{}), "");
    EXPECT_NE(checkRaycastParams(RaycastParams{.iso = 1.5f}), "");
}

TEST(RaycastCli, SurfaceRaycastRendersAndSaysWhatIsWrong) {
    const auto dir = test::tempDir();
    const std::string in = test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo").string();
    const std::string out = (dir / "rc.png").string();
    std::string log;
    ASSERT_EQ(test::runCommand(test::cliPath() + " render " + in + " -o " + out +
                                   " --surface raycast --width 96 --height 54 --backend cpu",
                               &log),
              0)
        << log;
    EXPECT_EQ(test::readPng(out).width, 96);
    EXPECT_NE(test::runCommand(test::cliPath() + " render " + in + " -o " + out + " --surface raycast --field thesis",
                               &log),
              0);
    EXPECT_NE(log.find("--field thesis"), std::string::npos) << log;
    EXPECT_NE(test::runCommand(test::cliPath() + " render " + in + " -o " + out +
                                   " --surface raycast --raycast-cover 0.5",
                               &log),
              0);
    EXPECT_NE(log.find("coverRadii"), std::string::npos) << log;
}

}  // namespace
}  // namespace raycast_test_local
