// The CPU mesh rasteriser (src/cpu/raster_mesh.cpp) and the Renderer's mesh
// path: an icosphere against the analytic sphere (depth, normals, coverage),
// the fill rule (shared edges cover each pixel centre once), near-plane
// clipping against the analytic plane, thread-count invariance, occlusion by
// the scene, and the Renderer's checks of the mesh.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "cpu/raster_mesh.h"
#include "cpu/scene.h"
#include "cpu/splat.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "mesh_test_util.h"
#include "shared/studio.h"
#include "test_util.h"

namespace raster_mesh_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

double angleDeg(glm::dvec3 a, glm::dvec3 b) {
    const double c = glm::dot(a, b) / (glm::length(a) * glm::length(b));
    return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI;
}

// View-space ray of pixel (x, y) in double (docs/conventions.md#conventions).
glm::dvec3 rayOf(const Camera& cam, int x, int y) {
    const double f = cam.focalPx();
    return {(x + 0.5 - 0.5 * cam.width) / f, -(y + 0.5 - 0.5 * cam.height) / f, -1.0};
}

// Eye depths where the ray (ray.z = -1) enters and leaves the sphere
// (view-space centre c, radius r); false when it misses.
bool raySphere(glm::dvec3 ray, glm::dvec3 c, double r, double* zIn, double* zOut) {
    const double a = glm::dot(ray, ray), b = glm::dot(ray, c), disc = b * b - a * (glm::dot(c, c) - r * r);
    if (disc < 0.0) return false;
    *zIn = (b - std::sqrt(disc)) / a;
    *zOut = (b + std::sqrt(disc)) / a;
    return true;
}

}  // namespace

TEST(RasterMesh, IcosphereIsClosedAndCounterClockwise) {
    const TriangleMesh m = icosphere({0.0f, 0.0f, 0.0f}, 1.0f, 2);
    EXPECT_EQ(m.triangleCount(), 320u);
    for (std::size_t k = 0; k < m.indices.size(); k += 3) {
        const glm::dvec3 a = m.positions[m.indices[k]], b = m.positions[m.indices[k + 1]], c = m.positions[m.indices[k + 2]];
        EXPECT_GT(glm::dot(glm::cross(b - a, c - a), a + b + c), 0.0) << k / 3;
    }
}

// Depth between the analytic sphere and the inner sphere the chord error
// allows, normals equal to the radial direction of the mesh point (the
// perspective-correct interpolation of radial vertex normals over a flat
// triangle is exactly that), coverage between the inner and outer discs.
TEST(RasterMesh, SphereMatchesTheAnalyticSphere) {
    const glm::vec3 centre{0.1f, -0.05f, 0.0f};
    const float R = 0.5f;
    const TriangleMesh mesh = icosphere(centre, R, 5);  // 20480 triangles
    const double e = chordError(mesh, centre, R);
    Camera cam;
    cam.eye = {0.4f, 0.3f, 2.5f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.width = 321;
    cam.height = 239;
    cam.fovYDegrees = 40.0f;
    const cpu::MeshRaster r = cpu::rasteriseMesh(cam, mesh);
    const glm::dvec3 c = cam.toView(centre);
    // Float rounding of the depth (interpolated 1/w, relative ~1e-7) on top of the shell.
    constexpr double kRel = 2e-6;
    // The normal of a point on a flat triangle, interpolated from the radial
    // vertex normals, is radial: only rounding (float vertices, float depth)
    // is left. On the silhouette ring (rays that miss the inner sphere: the
    // triangles are seen edge-on, a few pixels thin) a centre the 1/256 px
    // snapping let in is extrapolated and its 1/w clamped to the triangle's
    // range, which tilts the reconstructed point: 1 degree there.
    constexpr double kMaxDeg = 1e-3, kMaxRingDeg = 1.0;
    int covered = 0, depthBad = 0, normalBad = 0, outsideOuter = 0, missedInner = 0, ringViolations = 0;
    double worstDeg = 0.0, worstRingDeg = 0.0;
    auto outerHit = [&](int x, int y) {
        double a, b;
        return x >= 0 && y >= 0 && x < cam.width && y < cam.height && raySphere(rayOf(cam, x, y), c, R, &a, &b);
    };
    auto coveredAt = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < cam.width && y < cam.height && r.depth.at(x, y) < kInf;
    };
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            const glm::dvec3 ray = rayOf(cam, x, y);
            double zIn = 0, zOut = 0, zInnerIn = 0, zInnerOut = 0;
            const bool outer = raySphere(ray, c, R, &zIn, &zOut);
            const bool inner = raySphere(ray, c, R - e, &zInnerIn, &zInnerOut);
            const float z = r.depth.at(x, y);
            const bool has = z < kInf;
            covered += has;
            if (has && !outer) ++outsideOuter;
            if (!has && inner) ++missedInner;
            // A coverage difference must lie on the silhouette: within one
            // pixel of a pixel of the other kind.
            if ((has && !outer) || (!has && inner)) {
                bool ring = false;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                        ring |= has ? outerHit(x + dx, y + dy) : coveredAt(x + dx, y + dy);
                ringViolations += !ring;
            }
            if (!has) continue;
            // The mesh lies in the shell between the spheres: its nearest hit
            // is no nearer than the outer sphere's and no farther than the
            // inner sphere's entry (or the outer one's exit for grazing rays).
            const double zMax = inner ? zInnerIn : (outer ? zOut : 0.0);
            if (outer && !(z >= zIn * (1 - kRel) && z <= zMax * (1 + kRel))) ++depthBad;
            const double deg = angleDeg(glm::dvec3(r.normal.at(x, y)), double(z) * ray - c);
            worstDeg = std::max(worstDeg, inner ? deg : 0.0);
            worstRingDeg = std::max(worstRingDeg, inner ? 0.0 : deg);
            normalBad += !(deg <= (inner ? kMaxDeg : kMaxRingDeg));
        }
    std::printf("chord error %.3g R; %d covered; depth out of the shell %d; normals max %.3g deg (ring %.3g, %d over);"
                " outside the disc %d, inner disc missed %d\n",
                e / R, covered, depthBad, worstDeg, worstRingDeg, normalBad, outsideOuter, missedInner);
    EXPECT_GT(covered, 5000);
    EXPECT_EQ(depthBad, 0);
    EXPECT_EQ(normalBad, 0);
    EXPECT_EQ(ringViolations, 0);
    // Non-covered pixels hold no normal.
    for (std::size_t k = 0; k < r.depth.size(); ++k)
        if (!(r.depth.pixels[k] < kInf)) {
            EXPECT_EQ(r.normal.pixels[k], glm::vec3(0.0f));
        }
}

// A quad of two triangles sharing the diagonal, its corners and diagonal on
// pixel centres (the exact tie of the fill rule): every centre inside covered
// exactly once, whichever way the triangles wind.
TEST(RasterMesh, SharedEdgeCoversEachPixelOnce) {
    const Camera cam = axisCamera(64, 48);
    for (bool flip : {false, true}) {
        TriangleMesh m;
        // Corners at pixel centres (10.5, 5.5) .. (40.5, 35.5): the diagonal
        // passes through 31 centres, the sides through centres too.
        const double x0 = 10.5, y0 = 5.5, x1 = 40.5, y1 = 35.5, z = 2.0;
        m.positions = {atPixel(cam, x0, y0, z), atPixel(cam, x1, y0, z), atPixel(cam, x1, y1, z), atPixel(cam, x0, y1, z)};
        m.normals.assign(4, glm::vec3(0.0f, 0.0f, 1.0f));
        m.indices = flip ? std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3} : std::vector<std::uint32_t>{0, 2, 1, 0, 3, 2};
        Image<std::uint32_t> count(cam.width, cam.height, 0u);
        const cpu::MeshRaster r = cpu::rasteriseMesh(cam, m, nullptr, &count);
        int inside = 0;
        for (int y = 0; y < cam.height; ++y)
            for (int x = 0; x < cam.width; ++x) {
                const double px = x + 0.5, py = y + 0.5;
                const bool strictlyInside = px > x0 && px < x1 && py > y0 && py < y1;
                const bool onBorder = !strictlyInside && px >= x0 && px <= x1 && py >= y0 && py <= y1;
                if (strictlyInside) {
                    ++inside;
                    EXPECT_EQ(count.at(x, y), 1u) << x << "," << y << " flip " << flip;
                } else if (onBorder) {
                    EXPECT_LE(count.at(x, y), 1u) << x << "," << y;
                } else {
                    EXPECT_EQ(count.at(x, y), 0u) << x << "," << y;
                }
                if (count.at(x, y)) {
                    EXPECT_NEAR(r.depth.at(x, y), z, 1e-5 * z);
                }
            }
        EXPECT_EQ(inside, 29 * 29);
        // Top-left: the top row (y0) and left column (x0) of the border are
        // covered, the bottom row and right column are not.
        EXPECT_EQ(count.at(20, 5), 1u);
        EXPECT_EQ(count.at(10, 20), 1u);
        EXPECT_EQ(count.at(20, 35), 0u);
        EXPECT_EQ(count.at(40, 20), 0u);
    }
}

// A triangulated grid with jittered and exact (on-centre) vertices, random
// diagonals and both windings: the region it tiles is covered exactly once.
TEST(RasterMesh, TriangulatedGridIsWatertight) {
    const Camera cam = axisCamera(200, 150);
    constexpr int N = 24;                      // cells per side
    const double x0 = 20.5, y0 = 10.5, cell = 5.0;  // grid corners on pixel centres
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.2, 0.2);  // small enough that no cell folds
    std::uniform_int_distribution<int> coin(0, 1);
    TriangleMesh m;
    for (int j = 0; j <= N; ++j)
        for (int i = 0; i <= N; ++i) {
            double px = x0 + i * cell, py = y0 + j * cell;
            const bool border = i == 0 || j == 0 || i == N || j == N;
            if (!border && (i + j) % 3 != 0) {  // a third stay exactly on centres
                px += cell * jitter(rng);
                py += cell * jitter(rng);
            }
            m.positions.push_back(atPixel(cam, px, py, 3.0 + 0.01 * i));  // a slanted plane
            m.normals.push_back({0.0f, 0.0f, 1.0f});
        }
    auto v = [](int i, int j) { return std::uint32_t(j * (N + 1) + i); };
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            const std::uint32_t a = v(i, j), b = v(i + 1, j), c = v(i + 1, j + 1), d = v(i, j + 1);
            std::vector<std::uint32_t> t = coin(rng) ? std::vector<std::uint32_t>{a, b, c, a, c, d}
                                                     : std::vector<std::uint32_t>{a, b, d, b, c, d};
            if (coin(rng)) std::swap(t[1], t[2]);  // wind either way
            if (coin(rng)) std::swap(t[4], t[5]);
            m.indices.insert(m.indices.end(), t.begin(), t.end());
        }
    Image<std::uint32_t> count(cam.width, cam.height, 0u);
    cpu::rasteriseMesh(cam, m, nullptr, &count);
    const double x1 = x0 + N * cell, y1 = y0 + N * cell;
    int inside = 0, wrong = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            const double px = x + 0.5, py = y + 0.5;
            if (px > x0 && px < x1 && py > y0 && py < y1) {
                ++inside;
                wrong += count.at(x, y) != 1u;
            } else {
                wrong += count.at(x, y) > 1u;
            }
        }
    EXPECT_EQ(inside, 119 * 119);
    EXPECT_EQ(wrong, 0);
}

// A big floor triangle with a vertex behind the eye: clipped at the near plane
// in view space, the rest drawn with the analytic plane depth and the normal
// interpolated from the vertex normals by the 3-D barycentrics of the hit.
TEST(RasterMesh, TriangleCrossingTheNearPlane) {
    for (float nearM : {0.1f, 1.5f}) {
        const Camera cam = axisCamera(160, 120, 70.0f, nearM);
        const TriangleMesh m = floorTriangle();  // two vertices behind the eye
        const float h = kFloorY;
        const cpu::MeshRaster r = cpu::rasteriseMesh(cam, m);
        const glm::dvec3 a = m.positions[0], b = m.positions[1], c = m.positions[2];
        int covered = 0, expected = 0, coverageBad = 0, depthBad = 0, normalBad = 0;
        double worstRel = 0.0, worstDeg = 0.0;
        for (int y = 0; y < cam.height; ++y)
            for (int x = 0; x < cam.width; ++x) {
                const glm::dvec3 ray = rayOf(cam, x, y);
                bool in = false;
                glm::dvec3 l(0.0);
                double z = 0.0;
                if (ray.y < 0.0) {
                    z = h / ray.y;  // ray.z = -1: the eye depth is the ray parameter
                    const glm::dvec3 p = z * ray;
                    // 3-D barycentrics in the plane (xz).
                    const double det = (b.x - a.x) * (c.z - a.z) - (c.x - a.x) * (b.z - a.z);
                    l.y = ((p.x - a.x) * (c.z - a.z) - (c.x - a.x) * (p.z - a.z)) / det;
                    l.z = ((b.x - a.x) * (p.z - a.z) - (p.x - a.x) * (b.z - a.z)) / det;
                    l.x = 1.0 - l.y - l.z;
                    in = l.x > 0 && l.y > 0 && l.z > 0 && z >= nearM;
                }
                const bool has = r.depth.at(x, y) < kInf;
                covered += has;
                expected += in;
                // Coverage differs only within two pixels of the triangle's
                // edges or the near line: a pixel's footprint on the floor is
                // z/f across and z^2/(|h| f) along the view.
                const double foot = z / cam.focalPx() * std::max(1.0, z / std::abs(h));
                const double margin = 2.0 * foot / 11.0;  // in barycentrics: the triangle's altitudes are >= 11.9 m
                if (has != in && l.x > margin && l.y > margin && l.z > margin && std::abs(z - nearM) > 2.0 * foot)
                    ++coverageBad;
                if (!has || !in) continue;
                const double rel = std::abs(r.depth.at(x, y) - z) / z;
                worstRel = std::max(worstRel, rel);
                depthBad += !(rel <= 1e-5);
                const glm::dvec3 n = l.x * glm::dvec3(m.normals[0]) + l.y * glm::dvec3(m.normals[1]) +
                                     l.z * glm::dvec3(m.normals[2]);
                const double deg = angleDeg(glm::dvec3(r.normal.at(x, y)), n);
                worstDeg = std::max(worstDeg, deg);
                normalBad += !(deg <= 0.01);
            }
        std::printf("near %.2f: %d covered (%d expected), depth rel max %.3g, normals max %.3g deg\n", nearM, covered,
                    expected, worstRel, worstDeg);
        EXPECT_GT(covered, 2000);
        EXPECT_EQ(coverageBad, 0);
        EXPECT_EQ(depthBad, 0);
        EXPECT_EQ(normalBad, 0);
    }
}

// The same bits with 1 thread and with many: a sphere of 327,680 triangles
// (more than one batch), coplanar duplicates with other normals (ties), an
// odd image size with partial tiles.
TEST(RasterMesh, BitIdenticalForAnyThreadCount) {
    TriangleMesh m = icosphere({0.0f, 0.0f, 0.0f}, 0.6f, 7);
    const std::size_t base = m.positions.size(), tris = m.indices.size();
    for (std::size_t i = 0; i < base; ++i) {  // a second copy of every vertex with a tilted normal
        m.positions.push_back(m.positions[i]);
        m.normals.push_back(glm::normalize(m.normals[i] + glm::vec3(0.2f, 0.0f, 0.0f)));
    }
    for (std::size_t k = 0; k < tris; k += 7 * 3)  // every seventh triangle again, on the copies
        for (int j = 0; j < 3; ++j) m.indices.push_back(m.indices[k + j] + std::uint32_t(base));
    Camera cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.6f, 397, 283);
    auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        return cpu::rasteriseMesh(cam, m);
    };
    const cpu::MeshRaster one = run(1), many = run(8);
    ASSERT_EQ(one.depth.size(), many.depth.size());
    EXPECT_EQ(std::memcmp(one.depth.pixels.data(), many.depth.pixels.data(), one.depth.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(one.normal.pixels.data(), many.normal.pixels.data(), one.normal.size() * sizeof(glm::vec3)),
              0);
    int covered = 0;
    for (float z : one.depth.pixels) covered += z < kInf;
    EXPECT_GT(covered, 20000);
}

// Behind the scene: a wall of scene depth through the sphere's middle hides
// the fluid at or behind it; in front of it the image is the one without a scene.
TEST(RasterMesh, SceneDepthOccludes) {
    const TriangleMesh m = icosphere({0.0f, 0.0f, 0.0f}, 0.5f, 4);
    const Camera cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 2.0f, 160, 120);
    const cpu::MeshRaster open = cpu::rasteriseMesh(cam, m);
    Image<float> scene(cam.width, cam.height, kInf);
    const float wall = 1.6f;  // eye depth of the wall: the sphere spans 1.5 .. 2.5
    for (int y = 0; y < cam.height; ++y)
        for (int x = cam.width / 2; x < cam.width; ++x) scene.at(x, y) = wall;  // the right half only
    const cpu::MeshRaster hidden = cpu::rasteriseMesh(cam, m, &scene);
    int shown = 0, cut = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            const float z = open.depth.at(x, y), zh = hidden.depth.at(x, y);
            if (z < scene.at(x, y)) {
                EXPECT_EQ(zh, z) << x << "," << y;
                EXPECT_EQ(hidden.normal.at(x, y), open.normal.at(x, y));
                shown += x >= cam.width / 2;
            } else {
                EXPECT_EQ(zh, kInf) << x << "," << y;
                EXPECT_EQ(hidden.normal.at(x, y), glm::vec3(0.0f));
                cut += z < kInf;
            }
        }
    EXPECT_GT(shown, 200);  // the cap in front of the wall
    EXPECT_GT(cut, 200);    // the rest of the right half
}

namespace {

// One particle (for the splat, thickness and framing) and a mesh sphere around it.
struct MeshFrame {
    std::vector<glm::vec3> particles = {{0.0f, 0.0f, 0.0f}};
    TriangleMesh mesh = icosphere({0.0f, 0.0f, 0.0f}, 0.3f, 4);
    RenderSettings settings;
    MeshFrame() {
        settings.camera = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.5f, 160, 120);
        settings.radiusM = 0.25f;
        settings.mesh = &mesh;
        settings.anisotropy.enabled = false;  // the splat of the one particle's sphere
    }
};

}  // namespace

// Through the Renderer: depth and normals are the rasteriser's (in front of the
// scene), the raw depth and thickness the particles', and the stages say so.
TEST(RasterMeshRenderer, MeshReplacesSmoothingAndNormals) {
    MeshFrame f;
    std::vector<StageTime> times;
    auto aovs = Renderer().render(f.particles, f.settings, &times);
    ASSERT_TRUE(aovs.ok()) << aovs.error().describe();
    std::vector<std::string> names;
    for (const auto& t : times) names.push_back(t.stage);
    EXPECT_EQ(names, (std::vector<std::string>{"scene", "depth-splat+thickness", "rasterise", "shade"}));
    const shared::Studio studio =
        shared::makeStudio(computeBounds(f.particles), f.settings.radiusM, f.settings.camera, f.settings.scene,
                           f.settings.shading.lightDirWorld);
    const cpu::SceneLayer scene = cpu::castScene(f.settings.camera, studio);
    const cpu::MeshRaster ref = cpu::rasteriseMesh(f.settings.camera, f.mesh, &scene.depth);
    EXPECT_EQ(aovs->depth.pixels, ref.depth.pixels);
    EXPECT_EQ(aovs->normal.pixels, ref.normal.pixels);
    const Image<float> splat = cpu::splatDepth(f.settings.camera, f.particles, f.settings.radiusM, &scene.depth);
    EXPECT_EQ(aovs->rawDepth.pixels, splat.pixels);
    // The mesh (radius 0.3) is larger than the particle (0.25): its depth is nearer.
    const int cx = f.settings.camera.width / 2, cy = f.settings.camera.height / 2;
    EXPECT_LT(aovs->depth.at(cx, cy), aovs->rawDepth.at(cx, cy));
    EXPECT_GT(aovs->thickness.at(cx, cy), 0.0f);
    // Shaded where the mesh is: the fluid's pixels are opaque, differ from the scene.
    EXPECT_EQ(aovs->color.at(cx, cy).a, 1.0f);
    EXPECT_NE(glm::vec3(aovs->color.at(cx, cy)), glm::vec3(scene.color.at(cx, cy)));
}

// A bad mesh is an error naming the problem, never a crash.
TEST(RasterMeshRenderer, InvalidMeshIsAnError) {
    struct Case {
        const char* what;
        void (*spoil)(TriangleMesh&);
        const char* message;
    };
    const Case cases[] = {
        {"index out of range", [](TriangleMesh& m) { m.indices[7] = std::uint32_t(m.positions.size()); }, "out of range"},
        {"huge index", [](TriangleMesh& m) { m.indices.back() = 0xffffffffu; }, "out of range"},
        {"partial triangle", [](TriangleMesh& m) { m.indices.push_back(0); }, "whole number of triangles"},
        {"NaN position", [](TriangleMesh& m) { m.positions[3].y = std::nanf(""); }, "non-finite position"},
        {"infinite normal", [](TriangleMesh& m) { m.normals[5].x = kInf; }, "non-finite normal"},
        {"missing normals", [](TriangleMesh& m) { m.normals.pop_back(); }, "normals for"},
    };
    for (const Case& c : cases) {
        MeshFrame f;
        c.spoil(f.mesh);
        auto aovs = Renderer().render(f.particles, f.settings);
        ASSERT_FALSE(aovs.ok()) << c.what;
        EXPECT_NE(aovs.error().describe().find(c.message), std::string::npos) << c.what << ": " << aovs.error().describe();
        EXPECT_NE(aovs.error().describe().find("mesh"), std::string::npos) << aovs.error().describe();
    }
    // An empty mesh is valid: no fluid surface.
    MeshFrame f;
    f.mesh = TriangleMesh{};
    auto aovs = Renderer().render(f.particles, f.settings);
    ASSERT_TRUE(aovs.ok()) << aovs.error().describe();
    for (float z : aovs->depth.pixels) EXPECT_EQ(z, kInf);
}

// An image side larger than the rasterisers hold (shared::kRasterMaxSidePx, GL's
// texture size) never reaches them: the camera check refuses it first, which
// the static_asserts in pipeline.cpp and gl/raster_mesh.cpp keep true.
TEST(RasterMeshRenderer, OversizedImageIsRefusedBeforeRasterising) {
    MeshFrame f;
    f.settings.camera.width = defaults::kMaxImageSizePx + 1;
    f.settings.camera.height = 8;
    auto aovs = Renderer().render(f.particles, f.settings);
    ASSERT_FALSE(aovs.ok());
    EXPECT_NE(aovs.error().describe().find("image size"), std::string::npos) << aovs.error().describe();
}
}  // namespace raster_mesh_test_local
