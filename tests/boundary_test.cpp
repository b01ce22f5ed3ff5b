// DualSPHysics' boundary particles drawn as walls (include/meniscus/boundary.h,
// docs/geometry.md#dualsphysics-boundaries): a synthetic DualSPHysics-like
// frame, an open tank of one layer of fixed boundary particles around a block
// of fluid, split by its Type attribute; the walls' mesh closed, hole-free and
// within about dp of the particles; the cache; through the Renderer, opaque
// walls where the tank is and no liquid there, the near wall cut away; the
// modes liquid and hidden; and the fixtures of real DualSPHysics output.
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <utility>

#include <gtest/gtest.h>

#include "meniscus/boundary.h"
#include "meniscus/io.h"
#include "meniscus/options.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "test_util.h"

namespace boundary_test_local {

using namespace meniscus;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kDp = 0.02f;  // the particles' spacing, metres

// An open tank (floor y = 0, four walls, no lid) of one layer of particles
// at kDp over [0, 0.4] x [0, 0.3] x [0, 0.3].
std::vector<glm::vec3> tankLayer() {
    std::vector<glm::vec3> p;
    const int nx = 20, ny = 15, nz = 15;
    for (int i = 0; i <= nx; ++i)
        for (int j = 0; j <= ny; ++j)
            for (int k = 0; k <= nz; ++k) {
                const bool wall = j == 0 || i == 0 || i == nx || k == 0 || k == nz;
                if (wall) p.push_back(kDp * glm::vec3(float(i), float(j), float(k)));
            }
    return p;
}

// The tank (Type 0) around a block of fluid (Type 3) at the same spacing,
// with DualSPHysics' Idp and Rhop; `typeAsInt`: Type as the VTK reader
// gives it (an integer), else as the CSV reader (a float).
ParticleSet tankFrame(bool typeAsInt = false) {
    ParticleSet set;
    set.positions = tankLayer();
    const std::size_t walls = set.size();
    for (int i = 3; i <= 17; ++i)
        for (int j = 2; j <= 8; ++j)
            for (int k = 3; k <= 12; ++k) set.positions.push_back(kDp * glm::vec3(float(i), float(j), float(k)));
    Attribute type{"Type", typeAsInt ? AttributeType::Int : AttributeType::Float, 1, {}, {}};
    Attribute idp{"Idp", AttributeType::Int, 1, {}, {}};
    Attribute rho{"Rhop", AttributeType::Float, 1, {}, {}};
    for (std::size_t k = 0; k < set.size(); ++k) {
        const int t = k < walls ? 0 : 3;
        if (typeAsInt) type.ints.push_back(t);
        else type.floats.push_back(float(t));
        idp.ints.push_back(std::int64_t(k));
        rho.floats.push_back(1000.0f + float(k));
    }
    set.attributes = {std::move(idp), std::move(rho), std::move(type)};
    return set;
}

std::size_t wallCount() { return tankLayer().size(); }

// Every edge of the mesh in exactly two triangles (a closed surface).
bool closed(const TriangleMesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            std::uint32_t a = m.indices[t + e], b = m.indices[t + (e + 1) % 3];
            if (a > b) std::swap(a, b);
            ++edges[{a, b}];
        }
    for (const auto& [edge, uses] : edges)
        if (uses != 2) return false;
    return !edges.empty();
}

// V - E + F: 2 for each piece shaped like a ball (no hole through it).
long euler(const TriangleMesh& m) {
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    std::set<std::uint32_t> used;
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            std::uint32_t a = m.indices[t + e], b = m.indices[t + (e + 1) % 3];
            used.insert(a);
            edges.insert({std::min(a, b), std::max(a, b)});
        }
    return long(used.size()) - long(edges.size()) + long(m.triangleCount());
}

// The largest distance from a vertex to its nearest particle.
float farthestVertex(const TriangleMesh& m, const std::vector<glm::vec3>& particles) {
    float worst = 0.0f;
    for (const glm::vec3& v : m.positions) {
        float best = kInf;
        for (const glm::vec3& p : particles) best = std::min(best, glm::length(v - p));
        worst = std::max(worst, best);
    }
    return worst;
}

// The options' settings for the tank seen from the front (+z), 96 x 72.
struct Scene {
    ParticleSet liquid;
    RenderSettings settings;
};
Result<Scene> tankScene(const std::string& mode, const std::string& cutAway) {
    RenderOptions o;
    o.boundaryParticles = mode;
    o.cutAway = cutAway;
    o.anisotropy = "off";
    auto s = renderSettings(o);
    if (!s) return s.error();
    Scene scene{tankFrame(), std::move(*s)};
    auto geometry = prepareBoundary(scene.liquid, o, scene.settings.geometry, "tank");
    if (!geometry) return geometry.error();
    scene.settings.geometry = std::move(*geometry);
    scene.settings.radiusM = 0.5f * kDp;
    Camera& c = scene.settings.camera;
    c.eye = {0.2f, 0.2f, 1.6f};
    c.target = {0.2f, 0.12f, 0.15f};
    c.width = 96;
    c.height = 72;
    c.fovYDegrees = 30.0f;
    return scene;
}

// The pixel where the world point p is seen.
glm::ivec2 pixelOf(const Camera& c, const glm::vec3& p) {
    const glm::vec2 px = c.projectView(c.toView(p));
    return {int(px.x), int(px.y)};
}

}  // namespace

TEST(Boundary, TheTypeAttributeSplitsTheFluidFromTheWalls) {
    for (bool asInt : {false, true}) {
        ParticleSet set = tankFrame(asInt);
        const std::size_t all = set.size(), walls = wallCount();
        auto taken = takeBoundaryParticles(set, "tank");
        ASSERT_TRUE(taken) << taken.error().describe();
        EXPECT_EQ(taken->fixed.size(), walls);
        EXPECT_TRUE(taken->moving.empty());
        EXPECT_EQ(set.size(), all - walls);
        // Every attribute kept alike: the fluid's ids, densities and types.
        const Attribute* idp = set.find("Idp");
        const Attribute* rho = set.find("Rhop");
        ASSERT_EQ(idp->ints.size(), set.size());
        ASSERT_EQ(rho->floats.size(), set.size());
        for (std::size_t k = 0; k < set.size(); ++k) {
            EXPECT_EQ(idp->ints[k], std::int64_t(walls + k));
            EXPECT_EQ(rho->floats[k], 1000.0f + float(walls + k));
        }
        const Attribute* type = set.find("Type");
        for (std::size_t k = 0; k < set.size(); ++k) EXPECT_EQ(asInt ? double(type->ints[k]) : type->floats[k], 3.0);
    }
    // Moving and floating boundaries apart from the fixed ones.
    ParticleSet set;
    set.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
    set.attributes.push_back({"Type", AttributeType::Float, 1, {2.0f, 3.0f, 1.0f, 0.0f}, {}});
    auto taken = takeBoundaryParticles(set, "f");
    ASSERT_TRUE(taken);
    EXPECT_EQ(taken->fixed, (std::vector<glm::vec3>{{3, 0, 0}}));
    EXPECT_EQ(taken->moving, (std::vector<glm::vec3>{{0, 0, 0}, {2, 0, 0}}));
    EXPECT_EQ(set.positions, (std::vector<glm::vec3>{{1, 0, 0}}));
}

TEST(Boundary, AnotherProgramsTypeOrNoneIsLeftAlone) {
    // No Type: nothing taken.
    ParticleSet plain;
    plain.positions = {{0, 0, 0}, {1, 0, 0}};
    auto none = takeBoundaryParticles(plain, "p");
    ASSERT_TRUE(none);
    EXPECT_TRUE(none->empty());
    EXPECT_EQ(plain.size(), 2u);
    // A Type that is not DualSPHysics' (7): every particle stays, with a warning.
    ParticleSet other = plain;
    other.attributes.push_back({"Type", AttributeType::Int, 1, {}, {0, 7}});
    auto left = takeBoundaryParticles(other, "o");
    ASSERT_TRUE(left);
    EXPECT_TRUE(left->empty());
    EXPECT_EQ(other.size(), 2u);
    ASSERT_EQ(other.warnings.size(), 1u);
    EXPECT_NE(other.warnings[0].find("DualSPHysics"), std::string::npos);
    // A count that is not one per particle: an error naming the file.
    ParticleSet bad = plain;
    bad.attributes.push_back({"Type", AttributeType::Float, 1, {0.0f}, {}});
    auto refused = takeBoundaryParticles(bad, "bad.csv");
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().file, "bad.csv");
}

// One flat layer of particles at dp: a closed slab with no hole, also where a
// particle is missing, its faces within about dp of the layer.
TEST(Boundary, OneLayerIsAClosedHoleFreeSlab) {
    std::vector<glm::vec3> layer;
    for (int i = 0; i < 12; ++i)
        for (int k = 0; k < 12; ++k)
            if (!(i == 5 && k == 6)) layer.push_back(kDp * glm::vec3(float(i), 0.0f, float(k)));
    auto mesh = meshBoundaryParticles(layer);
    ASSERT_TRUE(mesh) << mesh.error().describe();
    EXPECT_TRUE(closed(*mesh));
    EXPECT_EQ(euler(*mesh), 2) << "one piece, no hole through it";
    float thickness = 0.0f;
    for (const glm::vec3& v : mesh->positions) thickness = std::max(thickness, std::abs(v.y));
    EXPECT_GT(thickness, 0.4f * kDp);
    EXPECT_LT(thickness, 1.0f * kDp);
    // Over the missing particle the slab is still there, both faces.
    int above = 0, below = 0;
    for (const glm::vec3& v : mesh->positions)
        if (glm::length(glm::vec2(v.x - 5 * kDp, v.z - 6 * kDp)) < 0.5f * kDp) (v.y > 0 ? above : below)++;
    EXPECT_GT(above, 0);
    EXPECT_GT(below, 0);
}

TEST(Boundary, TheTanksMeshIsClosedAndHugsItsParticles) {
    const std::vector<glm::vec3> tank = tankLayer();
    EXPECT_NEAR(boundarySpacing(tank), kDp, 1e-6f);
    auto mesh = meshBoundaryParticles(tank);
    ASSERT_TRUE(mesh) << mesh.error().describe();
    EXPECT_TRUE(closed(*mesh));
    EXPECT_EQ(euler(*mesh), 2) << "an open box of one layer: one piece, no hole";
    EXPECT_LT(farthestVertex(*mesh, tank), 1.05f * kDp);
    EXPECT_TRUE(mesh->validate()) << "indices in range, unit normals";
}

TEST(Boundary, TheCacheMeshesTheSamePositionsOnce) {
    BoundaryMeshCache cache;
    std::vector<glm::vec3> tank = tankLayer();
    auto a = cache.mesh(tank);
    ASSERT_TRUE(a);
    auto b = cache.mesh(tank);
    ASSERT_TRUE(b);
    EXPECT_EQ(a->get(), b->get()) << "the same mesh, not meshed again";
    EXPECT_EQ(cache.meshed(), 1u);
    tank[7].y += 0.001f;  // moved: meshed again
    auto c = cache.mesh(tank);
    ASSERT_TRUE(c);
    EXPECT_NE(c->get(), a->get());
    EXPECT_EQ(cache.meshed(), 2u);
    // Bounded: the oldest leave.
    for (std::size_t k = 0; k < BoundaryMeshCache::kEntries; ++k) {
        std::vector<glm::vec3> small = {{0, 0, 0}, {kDp, 0, 0}, {float(k), 1, 0}};
        ASSERT_TRUE(cache.mesh(small));
    }
    tank[7].y -= 0.001f;
    ASSERT_TRUE(cache.mesh(tank));
    EXPECT_EQ(cache.meshed(), 3u + BoundaryMeshCache::kEntries);
}

// A sequence whose tank stands still meshes it once, through the one place
// frames are made ready (prepareBoundary); a moved tank is meshed again.
TEST(Boundary, ASequencesFixedWallsAreMeshedOnce) {
    RenderOptions o;
    // Metres aside: positions no other test (nor an earlier run of this one)
    // has put in the process-wide cache.
    static int runs = 0;
    const float offset = 1.0f + float(runs++);
    const auto aside = [offset] {
        ParticleSet set = tankFrame();
        for (glm::vec3& p : set.positions) p.x += offset;
        return set;
    };
    const std::size_t before = boundaryMeshCache().meshed();
    std::shared_ptr<const SceneGeometry> first;
    for (int frame = 0; frame < 3; ++frame) {
        ParticleSet set = aside();
        for (std::size_t k = wallCount(); k < set.size(); ++k) set.positions[k].y += 0.001f * float(frame);  // the fluid moves
        auto g = prepareBoundary(set, o, nullptr, "frame");
        ASSERT_TRUE(g) << g.error().describe();
        ASSERT_EQ((*g)->objects.size(), 1u);
        if (!first) first = *g;
        EXPECT_EQ((*g)->objects[0].mesh.positions, first->objects[0].mesh.positions);
    }
    EXPECT_EQ(boundaryMeshCache().meshed(), before + 1);
    ParticleSet moved = aside();
    moved.positions[0].x -= 0.002f;
    ASSERT_TRUE(prepareBoundary(moved, o, nullptr, "frame"));
    EXPECT_EQ(boundaryMeshCache().meshed(), before + 2);
}

// The cut-away orientation: every triangle's outside faces away from the
// liquid, so the faces the eye sees the outside of are the near walls'.
TEST(Boundary, PrepareBoundaryAddsAnOpaqueCutAwayTank) {
    RenderOptions o;
    ParticleSet set = tankFrame();
    auto base = std::make_shared<const SceneGeometry>();
    auto g = prepareBoundary(set, o, base, "tank");
    ASSERT_TRUE(g) << g.error().describe();
    EXPECT_EQ(set.size(), tankFrame().size() - wallCount());
    ASSERT_EQ((*g)->objects.size(), 1u);
    const GeometryObject& walls = (*g)->objects[0];
    EXPECT_EQ(walls.name, "boundary particles (fixed)");
    EXPECT_TRUE(walls.cutaway);
    EXPECT_TRUE(walls.visible);
    EXPECT_FALSE(walls.material.glass);
    EXPECT_EQ(walls.material, GeometryMaterial{});
    EXPECT_TRUE(closed(walls.mesh));
    const glm::vec3 centre{0.2f, 0.15f, 0.15f};
    for (std::size_t t = 0; t + 2 < walls.mesh.indices.size(); t += 3) {
        const glm::vec3 a = walls.mesh.positions[walls.mesh.indices[t]];
        const glm::vec3 b = walls.mesh.positions[walls.mesh.indices[t + 1]];
        const glm::vec3 c = walls.mesh.positions[walls.mesh.indices[t + 2]];
        ASSERT_GE(glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0f - centre), 0.0f);
    }
    // --cut-away off: drawn whole; liquid and hidden: the base itself.
    o.cutAway = "off";
    set = tankFrame();
    g = prepareBoundary(set, o, base, "tank");
    ASSERT_TRUE(g);
    EXPECT_FALSE((*g)->objects[0].cutaway);
    o.boundaryParticles = "liquid";
    set = tankFrame();
    g = prepareBoundary(set, o, base, "tank");
    ASSERT_TRUE(g);
    EXPECT_EQ(g->get(), base.get());
    EXPECT_EQ(set.size(), tankFrame().size());
    o.boundaryParticles = "hidden";
    g = prepareBoundary(set, o, base, "tank");
    ASSERT_TRUE(g);
    EXPECT_EQ(g->get(), base.get());
    EXPECT_EQ(set.size(), tankFrame().size() - wallCount());
    o.boundaryParticles = "solid";
    EXPECT_FALSE(prepareBoundary(set, o, base, "tank"));
}

// Through the Renderer on the CPU: the tank's far wall above the water is an
// opaque wall with no liquid in walls mode, liquid in liquid mode, the studio
// in hidden mode; the near wall is cut away (the liquid seen through where it
// stands) unless --cut-away off, when it hides the liquid.
TEST(Boundary, RenderedWallsAreOpaqueAndHoldNoLiquid) {
    std::map<std::string, Aovs> shots;
    for (const char* mode : {"walls", "liquid", "hidden"}) {
        auto scene = tankScene(mode, "on");
        ASSERT_TRUE(scene) << scene.error().describe();
        auto aovs = renderFrame(ParticleView::of(scene->liquid), scene->settings);
        ASSERT_TRUE(aovs) << aovs.error().describe();
        shots[mode] = std::move(*aovs);
    }
    auto scene = tankScene("walls", "on");
    ASSERT_TRUE(scene);
    const Camera& cam = scene->settings.camera;
    // The far wall (z = 0) above the water (y = 0.24), between the side walls.
    const glm::ivec2 wall = pixelOf(cam, {0.2f, 0.26f, 0.0f});
    EXPECT_EQ(shots["walls"].depth.at(wall.x, wall.y), kInf) << "no liquid on the wall";
    EXPECT_EQ(shots["walls"].rawDepth.at(wall.x, wall.y), kInf);
    EXPECT_LT(shots["liquid"].rawDepth.at(wall.x, wall.y), kInf) << "the wall's particles as liquid";
    EXPECT_EQ(shots["hidden"].rawDepth.at(wall.x, wall.y), kInf);
    const glm::vec4 w = shots["walls"].color.at(wall.x, wall.y), h = shots["hidden"].color.at(wall.x, wall.y);
    EXPECT_EQ(w.a, 1.0f);
    EXPECT_GT(glm::length(glm::vec3(w) - glm::vec3(h)), 0.02f) << "the wall drawn over the studio";
    // The fluid's middle: seen through the cut-away near wall, liquid in every mode.
    const glm::ivec2 middle = pixelOf(cam, {0.2f, 0.1f, 0.15f});
    for (const char* mode : {"walls", "hidden"}) EXPECT_LT(shots[mode].depth.at(middle.x, middle.y), kInf) << mode;
    // --cut-away off: the near wall hides it.
    auto whole = tankScene("walls", "off");
    ASSERT_TRUE(whole);
    auto closedTank = renderFrame(ParticleView::of(whole->liquid), whole->settings);
    ASSERT_TRUE(closedTank) << closedTank.error().describe();
    EXPECT_EQ(closedTank->depth.at(middle.x, middle.y), kInf);
    EXPECT_EQ(closedTank->color.at(middle.x, middle.y).a, 1.0f);
}

// The fixtures (tests/data/dualsphysics/README.txt): real DualSPHysics
// layouts with 8 fixed, 4 moving, 4 floating and 24 fluid particles.
TEST(Boundary, DualSphysicsFixturesSplitByType) {
    for (const char* file : {"dualsphysics/PartCsv_0000.csv", "dualsphysics/PartAll_comma_0000.csv",
                             "dualsphysics/PartAll_0000.vtk"}) {
        auto set = readParticles(test::testData(file));
        ASSERT_TRUE(set) << set.error().describe();
        ASSERT_NE(dualSphysicsTypeAttribute(*set), nullptr) << file;
        auto taken = takeBoundaryParticles(*set, file);
        ASSERT_TRUE(taken) << taken.error().describe();
        EXPECT_EQ(taken->fixed.size(), 8u) << file;
        EXPECT_EQ(taken->moving.size(), 8u) << file;
        EXPECT_EQ(set->size(), 24u) << file;
        EXPECT_TRUE(set->warnings.empty()) << file;
        // The floor is a row of 8 particles 0.02 m apart: a closed rod around it.
        auto rod = meshBoundaryParticles(taken->fixed);
        ASSERT_TRUE(rod) << rod.error().describe();
        EXPECT_TRUE(closed(*rod)) << file;
        EXPECT_NEAR(boundarySpacing(taken->fixed), 0.02f, 1e-6f);
        EXPECT_LT(farthestVertex(*rod, taken->fixed), 0.02f) << file;
    }
}
}  // namespace boundary_test_local
