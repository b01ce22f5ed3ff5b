// The isosurface path (src/surface/, include/meniscus/surface.h): the
// marching-cubes table, spheres against the analytic surface, vertices on the
// SPH iso-surface, closed 2-manifold meshes of the real dam-break frames, no
// cracks at block seams, the same mesh for any thread count and block size.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <tuple>
#include <unordered_map>

#include "meniscus/io.h"
#include "meniscus/surface.h"
#include "surface/grid.h"
#include "surface/lookup_cache.h"
#include "surface/mc_table.h"
#include "surface/weld.h"
#include "test_util.h"

namespace meniscus::surface_test_local {
namespace {

using test::testData;

constexpr float kR = 0.01f;  // particle radius of the synthetic sets, metres

MeshParams paramsFor(SurfaceField field, float iso = defaults::kSurfaceIso) {
    MeshParams p;
    p.radiusM = kR;
    p.field = field;
    p.iso = iso;
    return p;
}

TriangleMesh mustExtract(const std::vector<glm::vec3>& pts, const MeshParams& p, MeshStats* stats = nullptr) {
    auto mesh = extractSurface(pts, p, stats);
    EXPECT_TRUE(mesh.ok()) << (mesh.ok() ? "" : mesh.error().describe());
    return mesh.ok() ? std::move(*mesh) : TriangleMesh{};
}

// Closed, consistently oriented 2-manifold without degenerate or duplicate
// triangles and without two vertices at one position. Returns "" or the first
// problem.
std::string meshProblem(const TriangleMesh& m) {
    if (m.indices.size() % 3) return "index count not a multiple of 3";
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;  // edge a->b: count
    std::set<std::array<std::uint32_t, 3>> faces;
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        const std::uint32_t a = m.indices[3 * t], b = m.indices[3 * t + 1], c = m.indices[3 * t + 2];
        if (a >= m.positions.size() || b >= m.positions.size() || c >= m.positions.size()) return "index out of range";
        if (a == b || b == c || a == c) return "degenerate triangle (repeated vertex) " + std::to_string(t);
        const glm::vec3 cr = glm::cross(m.positions[b] - m.positions[a], m.positions[c] - m.positions[a]);
        if (!(glm::length(cr) > 0.0f)) return "zero-area triangle " + std::to_string(t);
        std::array<std::uint32_t, 3> key{a, b, c};
        std::sort(key.begin(), key.end());
        if (!faces.insert(key).second) return "duplicate triangle " + std::to_string(t);
        for (auto [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
            if (++directed[{u, v}] > 1) return "edge used twice in the same direction (orientation or non-manifold)";
    }
    for (const auto& [e, n] : directed)
        if (!directed.count({e.second, e.first})) return "open edge (a hole or a crack)";
    std::set<std::tuple<float, float, float>> at;
    for (const glm::vec3& p : m.positions)
        if (!at.insert({p.x, p.y, p.z}).second) return "two vertices at one position (an unwelded seam)";
    if (m.normals.size() != m.positions.size()) return "normal count differs from vertex count";
    for (const glm::vec3& n : m.normals)
        if (!(std::abs(glm::length(n) - 1.0f) < 1e-4f)) return "a normal is not unit length";
    return "";
}

// Volume enclosed (divergence theorem): positive when triangles are
// counter-clockwise seen from outside.
double signedVolume(const TriangleMesh& m) {
    double v = 0.0;
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        const glm::dvec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                         c = m.positions[m.indices[3 * t + 2]];
        v += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    return v;
}

// Triangles as sorted position triples: compares meshes whatever their order.
std::multiset<std::array<std::tuple<float, float, float>, 3>> triangleSet(const TriangleMesh& m) {
    std::multiset<std::array<std::tuple<float, float, float>, 3>> s;
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        std::array<std::tuple<float, float, float>, 3> k;
        for (int i = 0; i < 3; ++i) {
            const glm::vec3 p = m.positions[m.indices[3 * t + i]];
            k[std::size_t(i)] = {p.x, p.y, p.z};
        }
        // Keep the orientation: rotate the smallest first.
        std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
        s.insert(k);
    }
    return s;
}

// Particles on a 2r lattice inside a ball (what SPH codes start a drop as).
std::vector<glm::vec3> latticeBall(glm::vec3 centre, float ballRadius) {
    std::vector<glm::vec3> pts;
    const int m = int(std::ceil(ballRadius / (2 * kR)));
    for (int i = -m; i <= m; ++i)
        for (int j = -m; j <= m; ++j)
            for (int k = -m; k <= m; ++k) {
                const glm::vec3 d = 2.0f * kR * glm::vec3(float(i), float(j), float(k));
                if (glm::length(d) <= ballRadius) pts.push_back(centre + d);
            }
    return pts;
}

// ---- the table

TEST(McTable, EveryCaseIsConsistent) {
    const auto& t = surface::mcTable();
    EXPECT_EQ(t.triangleCount[0], 0);
    EXPECT_EQ(t.triangleCount[255], 0);
    for (int m = 1; m < 255; ++m) {
        ASSERT_GT(t.triangleCount[std::size_t(m)], 0) << "case " << m;
        std::array<int, 12> uses{};
        for (int k = 0; k < 3 * t.triangleCount[std::size_t(m)]; ++k) {
            const int e = t.triangles[std::size_t(m)][std::size_t(k)];
            const int a = t.edgeCorner[std::size_t(e)][0], b = t.edgeCorner[std::size_t(e)][1];
            // Only edges with one corner inside carry a vertex.
            EXPECT_NE((m >> a) & 1, (m >> b) & 1) << "case " << m << " edge " << e;
            ++uses[std::size_t(e)];
        }
        for (int e = 0; e < 12; ++e) {
            const int a = t.edgeCorner[std::size_t(e)][0], b = t.edgeCorner[std::size_t(e)][1];
            if (((m >> a) & 1) != ((m >> b) & 1)) {
                EXPECT_GT(uses[std::size_t(e)], 0) << "case " << m << " edge " << e;
            }
        }
        // Within a case, an edge of a triangle between two vertices on one cube
        // face is a face segment (used once); any other is a diagonal shared
        // by two triangles of the case, in opposite directions.
        std::map<std::pair<int, int>, int> directed;
        for (int k = 0; k < t.triangleCount[std::size_t(m)]; ++k)
            for (int i = 0; i < 3; ++i)
                ++directed[{t.triangles[std::size_t(m)][std::size_t(3 * k + i)],
                            t.triangles[std::size_t(m)][std::size_t(3 * k + (i + 1) % 3)]}];
        for (const auto& [e, count] : directed) {
            const bool reverse = directed.count({e.second, e.first}) > 0;
            auto faces = [&](int edge) {
                const int a = t.edgeCorner[std::size_t(edge)][0], b = t.edgeCorner[std::size_t(edge)][1];
                int mask = 0;
                for (int ax = 0; ax < 3; ++ax)
                    if (((a >> ax) & 1) == ((b >> ax) & 1)) mask |= 1 << (2 * ax + ((a >> ax) & 1));
                return mask;
            };
            EXPECT_EQ(count, 1) << "case " << m;
            EXPECT_EQ(reverse, (faces(e.first) & faces(e.second)) == 0) << "case " << m << " edges " << e.first << "-" << e.second;
        }
        // The complement has the same surface, the other way round.
        EXPECT_EQ(t.triangleCount[std::size_t(m)] > 0, t.triangleCount[std::size_t(255 - m)] > 0);
    }
}

TEST(McTable, OneInsideCornerFacesAwayFromIt) {
    const auto& t = surface::mcTable();
    // Corner 0 inside: one triangle, its normal toward +(1,1,1) (outside).
    ASSERT_EQ(t.triangleCount[1], 1);
    auto mid = [&](int e) {
        const int a = t.edgeCorner[std::size_t(e)][0], b = t.edgeCorner[std::size_t(e)][1];
        auto pos = [](int c) { return glm::vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1)); };
        return 0.5f * (pos(a) + pos(b));
    };
    const glm::vec3 a = mid(t.triangles[1][0]), b = mid(t.triangles[1][1]), c = mid(t.triangles[1][2]);
    EXPECT_GT(glm::dot(glm::cross(b - a, c - a), glm::vec3(1.0f)), 0.0f);
}

// ---- spheres

// A lone particle with the thesis field: the iso-surface is the sphere
// f(d) = iso * F0, d = Rc sqrt(1 - sqrt(4 iso F0)) (eq. 4.16).
TEST(Surface, OneParticleIsTheAnalyticSphere) {
    for (SurfaceField field : {SurfaceField::Thesis, SurfaceField::Sph}) {
        // sph: a lone particle is below the default iso 0.5 (refsurf: invisible); iso 0.25 shows it.
        const float iso = field == SurfaceField::Sph ? 0.25f : 0.5f;
        MeshParams p = paramsFor(field, iso);
        p.cubeSizeRadii = 0.1f;  // the lone spheres are 0.6 r (thesis) and 0.85 r (sph) across
        const glm::vec3 c(0.3f, 0.2f, -0.1f);
        // The analytic radius: bisect the direct field (1 particle).
        double lo = 0.0, hi = 8.0 * kR;
        for (int i = 0; i < 60; ++i) {
            const double mid = 0.5 * (lo + hi);
            (surfaceFieldValue(std::vector<glm::vec3>{c}, p, c + glm::vec3(float(mid), 0, 0)) >= iso ? lo : hi) = mid;
        }
        const double radius = lo;
        ASSERT_GT(radius, 0.4 * kR) << surfaceFieldName(field);
        MeshStats stats;
        const TriangleMesh m = mustExtract({c}, p, &stats);
        ASSERT_GT(m.triangleCount(), 50u);
        EXPECT_EQ(meshProblem(m), "");
        double worst = 0.0;
        for (const glm::vec3& v : m.positions) worst = std::max(worst, std::abs(glm::length(glm::dvec3(v - c)) - radius));
        // Hausdorff bound (vertices to sphere): 0.02 r at cube 0.1 r.
        EXPECT_LT(worst, 0.02 * kR) << surfaceFieldName(field) << " radius " << radius / kR << " r";
        // ... and the other way: the enclosed volume is the ball's within 3%.
        const double ball = 4.0 / 3.0 * M_PI * radius * radius * radius;
        EXPECT_NEAR(signedVolume(m) / ball, 1.0, 0.03) << surfaceFieldName(field);
        // Normals point out of the sphere.
        float cosWorst = 1.0f;
        for (std::size_t i = 0; i < m.positions.size(); ++i)
            cosWorst = std::min(cosWorst, glm::dot(m.normals[i], glm::normalize(m.positions[i] - c)));
        EXPECT_GT(cosWorst, std::cos(glm::radians(5.0f))) << surfaceFieldName(field);
    }
}

// A ball of particles: the surface lies about 1 r beyond the outermost
// centres (refsurf's flat face: 1.00 r), bumpy by the lattice.
TEST(Surface, BallOfParticlesIsCloseToItsSphere) {
    const glm::vec3 c(0.0f);
    const float ballRadius = 10.0f * kR;
    const auto pts = latticeBall(c, ballRadius);
    const TriangleMesh m = mustExtract(pts, paramsFor(SurfaceField::Sph));
    EXPECT_EQ(meshProblem(m), "");
    // Hausdorff bound to the best-fit sphere (mean vertex distance): 0.9 r,
    // the 2r lattice's steps at the rim. That sphere holds the particles'
    // volume, (2r)^3 each (as a flat face lies 1 r beyond the last centres).
    double mean = 0.0;
    for (const glm::vec3& v : m.positions) mean += glm::length(v - c);
    mean /= double(m.vertexCount());
    double worst = 0.0;
    for (const glm::vec3& v : m.positions) worst = std::max(worst, std::abs(glm::length(v - c) - mean));
    EXPECT_LT(worst, 0.9 * kR);
    const double volumeRadius = std::cbrt(double(pts.size()) * 8.0 * kR * kR * kR * 3.0 / (4.0 * M_PI));
    EXPECT_NEAR(mean, volumeRadius, 0.3 * kR);
    EXPECT_GT(signedVolume(m), 0.0);
}

// ---- the SPH field: vertices on the iso-surface refsurf ray-traces

TEST(Surface, SphVerticesLieOnTheIsoSurface) {
    auto set = readParticles(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
    ASSERT_TRUE(set.ok()) << set.error().describe();
    const float r = defaultRadius(*set).radius;
    MeshParams p;
    p.radiusM = r;
    p.field = SurfaceField::Sph;
    auto mesh = extractSurface(ParticleView::of(*set), p);
    ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
    ASSERT_GT(mesh->vertexCount(), 1000u);
    // Every 7th vertex, the field summed directly over all particles (double):
    // linear interpolation along a cube edge of 0.5 r leaves it within 0.05
    // of the rest value from the iso level 0.5.
    double worst = 0.0, sum = 0.0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < mesh->vertexCount(); i += 7) {
        const double err = std::abs(surfaceFieldValue(ParticleView::of(*set), p, mesh->positions[i]) - p.iso);
        worst = std::max(worst, err);
        sum += err;
        ++count;
    }
    EXPECT_LT(worst, 0.05) << "mean " << sum / double(count);
    EXPECT_LT(sum / double(count), 0.01);
}

// ---- the real dam-break frames: closed 2-manifold; surface following finds
// what plain marching cubes over every cube finds.

// Surface following against plain marching cubes over every cube: its
// triangles are a subset, and what it misses is only closed pieces smaller
// than a (2r)^3 cell (|enclosed volume| < maxVolume): specks of the field and
// voids between particles inside the liquid, which no walk from the outside
// of the occupied cells reaches (thesis §4.2.3, Fig. 4.11).
std::string missedPieces(const TriangleMesh& found, const TriangleMesh& all, double maxVolume) {
    const auto got = triangleSet(found);
    const auto every = triangleSet(all);
    if (!std::includes(every.begin(), every.end(), got.begin(), got.end())) return "a triangle plain MC does not have";
    // Pieces (vertex-connected components) of the full mesh.
    std::vector<std::uint32_t> parent(all.vertexCount());
    for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
    auto root = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (std::size_t t = 0; t < all.triangleCount(); ++t) {
        const std::uint32_t a = root(all.indices[3 * t]);
        parent[root(all.indices[3 * t + 1])] = a;
        parent[root(all.indices[3 * t + 2])] = a;
    }
    std::map<std::uint32_t, double> volume;
    std::map<std::uint32_t, bool> missed;
    for (std::size_t t = 0; t < all.triangleCount(); ++t) {
        const std::uint32_t piece = root(all.indices[3 * t]);
        const glm::dvec3 a = all.positions[all.indices[3 * t]], b = all.positions[all.indices[3 * t + 1]],
                         c = all.positions[all.indices[3 * t + 2]];
        volume[piece] += glm::dot(a, glm::cross(b, c)) / 6.0;
        std::array<std::tuple<float, float, float>, 3> k;
        for (int i = 0; i < 3; ++i) {
            const glm::vec3 p = all.positions[all.indices[3 * t + i]];
            k[std::size_t(i)] = {p.x, p.y, p.z};
        }
        std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
        if (!got.count(k)) missed[piece] = true;
    }
    for (const auto& [piece, yes] : missed)
        if (std::abs(volume[piece]) >= maxVolume)
            return "missed a piece of volume " + std::to_string(volume[piece] / maxVolume * 8.0) + " r^3";
    return "";
}

struct Frame {
    const char* file;
    bool inRepoData;
};

class RealFrames : public ::testing::TestWithParam<Frame> {};

TEST_P(RealFrames, MeshIsClosedManifoldAndComplete) {
    const Frame f = GetParam();
    auto set = readParticles(f.inRepoData ? test::repoData(f.file) : testData(f.file));
    ASSERT_TRUE(set.ok()) << set.error().describe();
    for (SurfaceField field : {SurfaceField::Sph, SurfaceField::Thesis}) {
        MeshParams p;
        p.radiusM = defaultRadius(*set).radius;
        p.field = field;
        MeshStats stats;
        auto mesh = extractSurface(ParticleView::of(*set), p, &stats);
        ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
        ASSERT_GT(mesh->triangleCount(), 1000u);
        EXPECT_EQ(meshProblem(*mesh), "") << f.file << " " << surfaceFieldName(field);
        EXPECT_GT(signedVolume(*mesh), 0.0);
        if (set->size() > 50000) continue;  // the exhaustive pass is volume work
        MeshParams all = p;
        all.exhaustive = true;
        auto reference = extractSurface(ParticleView::of(*set), all);
        ASSERT_TRUE(reference.ok());
        EXPECT_EQ(missedPieces(*mesh, *reference, 8.0 * double(p.radiusM) * p.radiusM * p.radiusM), "")
            << f.file << " " << surfaceFieldName(field);
    }
}

INSTANTIATE_TEST_SUITE_P(DamBreak, RealFrames,
                         ::testing::Values(Frame{"splishsplash/partio/ParticleData_Fluid_1.bgeo", false},
                                           Frame{"splishsplash/partio/ParticleData_Fluid_9.bgeo", false},
                                           Frame{"splishsplash/partio/ParticleData_Fluid_21.bgeo", false},
                                           Frame{"splishsplash/partio/ParticleData_Fluid_61.bgeo", false},
                                           Frame{"demo/ParticleData_Fluid_19.bgeo", true},
                                           Frame{"demo/ParticleData_Fluid_20.bgeo", true},
                                           Frame{"demo/ParticleData_Fluid_22.bgeo", true},
                                           Frame{"demo/ParticleData_Fluid_23.bgeo", true},
                                           Frame{"dambreak_r0.01/ParticleData_Fluid_21.bgeo", true}),
                         [](const ::testing::TestParamInfo<Frame>& info) {
                             // small_1, small_9, ..., demo_19, ..., large_21
                             const std::string file = info.param.file;
                             std::string name = file.rfind("demo", 0) == 0 ? "demo_"
                                                : info.param.inRepoData    ? "large_"
                                                                           : "small_";
                             const auto digits = file.find_last_of('_') + 1;
                             return name + file.substr(digits, file.find('.', digits) - digits);
                         });

// ---- the lookup cache

// One block's corner passes, for both fields: the SSE lanes equal the scalar
// twin bit for bit, and both equal the direct sum of the kernel over every
// particle (jittered lattice at 2r spacing around and inside the block).
TEST(LookupCache, CornerPassIsTheFieldSum) {
    for (SurfaceField kind : {SurfaceField::Sph, SurfaceField::Thesis}) {
        const MeshParams p = paramsFor(kind);
        const surface::Field field = surface::makeField(p);
        surface::Grid grid;
        grid.cube = p.cubeSizeRadii * p.radiusM;
        grid.n = 8;
        grid.origin = glm::ivec3(-21, 13, -7);  // corners away from 0: coordinates of both signs
        grid.cubes = glm::ivec3(48);
        grid.blocks = grid.cubes / grid.n;
        const glm::ivec3 corner0(16, 16, 16);  // block (2, 2, 2)
        const glm::vec3 lo = grid.corner(corner0.x, corner0.y, corner0.z) - field.support;
        const glm::vec3 hi = grid.corner(corner0.x + 8, corner0.y + 8, corner0.z + 8) + field.support;
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> jitter(-0.4f * kR, 0.4f * kR);
        std::vector<glm::vec3> pos;
        for (float z = lo.z; z < hi.z; z += 2 * kR)
            for (float y = lo.y; y < hi.y; y += 2 * kR)
                for (float x = lo.x; x < hi.x; x += 2 * kR) pos.push_back(glm::vec3(x, y, z) + jitter(rng));
        std::vector<std::uint32_t> ids(pos.size());
        for (std::size_t q = 0; q < ids.size(); ++q) ids[q] = std::uint32_t(q);
        std::sort(ids.begin(), ids.end(), [&](std::uint32_t a, std::uint32_t b) {
            return pos[a].z < pos[b].z || (pos[a].z == pos[b].z && a < b);
        });
        surface::LookupCache cache;
        cache.build(grid, field, corner0, pos, ids);
        double worst = 0.0;
        int differ = 0;
        for (int j = 0; j <= 8; ++j)
            for (int i = 0; i <= 8; ++i)
                for (int k = 0; k + surface::LookupCache::kLanes - 1 <= 8; ++k) {
                    float zs[surface::LookupCache::kLanes], simd[surface::LookupCache::kLanes],
                        scalar[surface::LookupCache::kLanes];
                    for (int q = 0; q < surface::LookupCache::kLanes; ++q)
                        zs[q] = grid.corner(0, 0, corner0.z + k + q).z;
                    cache.values(i, j, k, zs, simd);
                    cache.valuesScalar(i, j, k, zs, scalar);
                    differ += std::memcmp(simd, scalar, sizeof simd) != 0;
                    for (int q = 0; q < surface::LookupCache::kLanes; ++q) {
                        const glm::vec3 at = grid.corner(corner0.x + i, corner0.y + j, corner0.z + k + q);
                        double direct = 0.0;
                        for (const glm::vec3& x : pos) {
                            const glm::vec3 d = x - at;
                            direct += double(field.kernel(glm::dot(d, d)));
                        }
                        worst = std::max(worst, std::abs(double(simd[q]) - direct) / field.rest);
                    }
                }
        EXPECT_EQ(differ, 0) << surfaceFieldName(kind);
        EXPECT_LT(worst, 1e-5) << surfaceFieldName(kind);  // float sums of about 40 terms near 1
    }
}

// The normals' angle weight (a polynomial acos) against std::acos in double
// over the whole range: within float rounding of the angle.
TEST(Normals, AngleWeightAcosIsAcos) {
    double worst = 0.0;
    for (int s = -100000; s <= 100000; ++s) {
        const float x = float(s) / 100000.0f;
        worst = std::max(worst, std::abs(double(surface::fastAcos(x)) - std::acos(double(x))));
    }
    EXPECT_LT(worst, 5e-7);  // a float ulp at pi is 2.4e-7
}

// ---- seams, threads, block size

// Blocks of 8 cubes (4 r) with the ball centred on a block corner: seams run
// through it on all three axes. Same triangles as one block holding it all.
TEST(Surface, NoCracksAtBlockSeams) {
    MeshParams p = paramsFor(SurfaceField::Sph);
    p.blockCubes = 8;
    const float blockM = 8 * p.cubeSizeRadii * kR;
    const auto pts = latticeBall(glm::vec3(3 * blockM, 2 * blockM, -blockM), 6.0f * kR);
    MeshStats stats;
    const TriangleMesh seamed = mustExtract(pts, p, &stats);
    EXPECT_GT(stats.blocksWithSurface, 8u);
    // Some blocks resume with cubes handed on across a seam (their own walks
    // missed the piece), and append it to what they had.
    EXPECT_GT(stats.blocksRerun, 0u);
    EXPECT_EQ(meshProblem(seamed), "");
    MeshParams one = p;
    one.blockCubes = 64;
    const TriangleMesh whole = mustExtract(pts, one);
    EXPECT_EQ(seamed.vertexCount(), whole.vertexCount());
    EXPECT_TRUE(triangleSet(seamed) == triangleSet(whole));
    // Normals are summed per block and joined at the seams: they match the
    // angle-weighted normals of the welded mesh, summed here in double with
    // std::acos (within 0.1 degree).
    std::vector<glm::dvec3> ref(seamed.vertexCount(), glm::dvec3(0.0));
    for (std::size_t t = 0; t < seamed.triangleCount(); ++t) {
        const std::uint32_t* id = &seamed.indices[3 * t];
        const glm::dvec3 a(seamed.positions[id[0]]), b(seamed.positions[id[1]]), c(seamed.positions[id[2]]);
        const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
        auto angle = [](glm::dvec3 u, glm::dvec3 v) { return std::acos(glm::dot(glm::normalize(u), glm::normalize(v))); };
        ref[id[0]] += n * angle(b - a, c - a);
        ref[id[1]] += n * angle(c - b, a - b);
        ref[id[2]] += n * angle(a - c, b - c);
    }
    double worst = 1.0;
    for (std::size_t v = 0; v < ref.size(); ++v)
        worst = std::min(worst, glm::dot(glm::normalize(ref[v]), glm::dvec3(seamed.normals[v])));
    EXPECT_GT(worst, std::cos(glm::radians(0.1)));
}

TEST(Surface, SameMeshForAnyThreadCount) {
    auto set = readParticles(testData("splishsplash/partio/ParticleData_Fluid_9.bgeo"));
    ASSERT_TRUE(set.ok());
    MeshParams p;
    p.radiusM = defaultRadius(*set).radius;
    p.blockCubes = 12;  // many blocks, so threads interleave
    p.threads = 1;
    auto a = extractSurface(ParticleView::of(*set), p);
    p.threads = 4;
    auto b = extractSurface(ParticleView::of(*set), p);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_TRUE(a->positions == b->positions);
    EXPECT_TRUE(a->normals == b->normals);
    EXPECT_TRUE(a->indices == b->indices);
    // ... and as files.
    const auto dir = test::tempDir();
    ASSERT_TRUE(writeMesh(dir / "a.ply", *a, MeshFormat::Ply).ok());
    ASSERT_TRUE(writeMesh(dir / "b.ply", *b, MeshFormat::Ply).ok());
    EXPECT_TRUE(test::readBytes(dir / "a.ply") == test::readBytes(dir / "b.ply"));
}

TEST(Surface, ScaleInvariant) {
    // The whole scene 10x larger, radius too: the same mesh, 10x larger.
    const auto pts = latticeBall(glm::vec3(0.05f, 0.0f, 0.0f), 5.0f * kR);
    std::vector<glm::vec3> big;
    for (const auto& q : pts) big.push_back(q * 8.0f);
    MeshParams p = paramsFor(SurfaceField::Sph);
    const TriangleMesh a = mustExtract(pts, p);
    p.radiusM = 8.0f * kR;
    const TriangleMesh b = mustExtract(big, p);
    ASSERT_EQ(a.vertexCount(), b.vertexCount());
    ASSERT_TRUE(a.indices == b.indices);
    for (std::size_t i = 0; i < a.vertexCount(); ++i)
        EXPECT_LT(glm::length(a.positions[i] * 8.0f - b.positions[i]), 1e-5f * 8.0f);
}

// ---- errors

TEST(Surface, BadParametersAreErrors) {
    const std::vector<glm::vec3> pts{glm::vec3(0.0f)};
    MeshParams p = paramsFor(SurfaceField::Sph);
    p.radiusM = 0.0f;
    EXPECT_FALSE(extractSurface(pts, p).ok());
    p = paramsFor(SurfaceField::Sph);
    p.cubeSizeRadii = 0.0f;
    EXPECT_FALSE(extractSurface(pts, p).ok());
    p = paramsFor(SurfaceField::Sph);
    p.iso = -1.0f;
    EXPECT_FALSE(extractSurface(pts, p).ok());
    p = paramsFor(SurfaceField::Sph);
    p.blockCubes = 1;
    EXPECT_FALSE(extractSurface(pts, p).ok());
    // A far outlier: the grid would exceed 2^24 cubes; an error, not a crash.
    p = paramsFor(SurfaceField::Sph);
    p.cubeSizeRadii = 0.05f;
    const std::vector<glm::vec3> far{glm::vec3(0.0f), glm::vec3(1e5f, 0.0f, 0.0f)};
    auto r = extractSurface(far, p);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("cube size"), std::string::npos) << r.error().message;
    // Nothing in, nothing out.
    auto none = extractSurface(std::vector<glm::vec3>{}, paramsFor(SurfaceField::Sph));
    ASSERT_TRUE(none.ok());
    EXPECT_TRUE(none->empty());
}

// ---- writers

TEST(MeshWriter, PlyAndObjHoldTheMesh) {
    const TriangleMesh m = mustExtract(latticeBall(glm::vec3(0.0f), 3.0f * kR), paramsFor(SurfaceField::Sph));
    ASSERT_FALSE(m.empty());
    const auto dir = test::tempDir();
    ASSERT_TRUE(writeMesh(dir / "m.ply", m, *meshFormatOf(dir / "m.ply")).ok());
    ASSERT_TRUE(writeMesh(dir / "m.obj", m, *meshFormatOf(dir / "m.OBJ")).ok());
    // PLY: our own reader reads the vertices back exactly; the size is the
    // header plus 24 bytes a vertex and 13 a triangle.
    auto back = readParticles(dir / "m.ply");
    ASSERT_TRUE(back.ok()) << back.error().describe();
    ASSERT_EQ(back->size(), m.vertexCount());
    for (std::size_t i = 0; i < m.vertexCount(); ++i) EXPECT_EQ(back->positions[i], m.positions[i]);
    const auto bytes = test::readBytes(dir / "m.ply");
    const std::string text(bytes.begin(), bytes.end());
    const std::size_t header = text.find("end_header\n") + 11;
    EXPECT_EQ(bytes.size(), header + 24 * m.vertexCount() + 13 * m.triangleCount());
    EXPECT_NE(text.find("element face " + std::to_string(m.triangleCount())), std::string::npos);
    // OBJ: one v, one vn per vertex, one f per triangle, 1-based.
    const auto obj = test::readBytes(dir / "m.obj");
    const std::string o(obj.begin(), obj.end());
    std::size_t v = 0, vn = 0, f = 0;
    for (std::size_t at = 0; at < o.size();) {
        const std::size_t end = o.find('\n', at);
        const std::string line = o.substr(at, end - at);
        v += line.rfind("v ", 0) == 0;
        vn += line.rfind("vn ", 0) == 0;
        f += line.rfind("f ", 0) == 0;
        at = end + 1;
    }
    EXPECT_EQ(v, m.vertexCount());
    EXPECT_EQ(vn, m.vertexCount());
    EXPECT_EQ(f, m.triangleCount());
    // A mesh with a bad index is refused and leaves no file.
    TriangleMesh bad = m;
    bad.indices[0] = std::uint32_t(m.vertexCount());
    EXPECT_FALSE(writeMesh(dir / "bad.ply", bad, MeshFormat::Ply).ok());
    EXPECT_FALSE(std::filesystem::exists(dir / "bad.ply"));
}

}  // namespace
}  // namespace meniscus::surface_test_local
