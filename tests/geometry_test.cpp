// Scene geometry's primitives and helpers (src/core/geometry_shapes.cpp) and
// the simulator's scene as geometry (simulationGeometry, src/sim/geometry.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include "geometry_test.h"
#include "meniscus/geometry.h"
#include "meniscus/io.h"
#include "meniscus/sim.h"
#include "test_util.h"

#include <glm/gtc/matrix_transform.hpp>

namespace meniscus::geometry_test_local {
namespace {

TEST(GeometryShapes, BoxIsTwelveOutwardTrianglesOnTwentyFourVertices) {
    const glm::vec3 lo(-1.0f, 0.0f, 2.0f), hi(3.0f, 0.5f, 2.25f);
    const TriangleMesh m = makeBoxMesh(lo, hi);
    EXPECT_EQ(m.triangleCount(), 12u);
    EXPECT_EQ(m.vertexCount(), 24u);
    ASSERT_TRUE(m.validate(true).ok());
    test::expectClosedAndOriented(m);
    test::expectOutward(m, 0.5f * (lo + hi));
    // Flat: each vertex's normal is its face's, an axis.
    for (const glm::vec3& n : m.normals) EXPECT_FLOAT_EQ(std::abs(n.x) + std::abs(n.y) + std::abs(n.z), 1.0f);
    Bounds b;
    for (const glm::vec3& p : m.positions) b.extend(p);
    EXPECT_EQ(b.min, lo);
    EXPECT_EQ(b.max, hi);
}

TEST(GeometryShapes, SphereIsClosedOutwardAndWithinATenthOfAPercent) {
    const glm::vec3 c(0.5f, -2.0f, 1.0f);
    const float r = 0.3f;
    const TriangleMesh m = makeSphereMesh(c, r);
    ASSERT_TRUE(m.validate(true).ok());
    EXPECT_GT(m.triangleCount(), 1000u);
    EXPECT_LT(m.triangleCount(), 40000u);
    test::expectClosedAndOriented(m);
    test::expectOutward(m, c);
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        EXPECT_NEAR(glm::length(m.positions[i] - c), r, 1e-6f);
        EXPECT_LT(glm::length(m.normals[i] - glm::normalize(m.positions[i] - c)), 1e-5f);
    }
    // Every facet's plane lies within 0.1 % of the radius of the centre.
    double worst = 0.0;
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        const glm::dvec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], d = m.positions[m.indices[t + 2]];
        const glm::dvec3 n = glm::normalize(glm::cross(b - a, d - a));
        worst = std::max(worst, 1.0 - glm::dot(n, a - glm::dvec3(c)) / r);
    }
    EXPECT_LT(worst, 1.0e-3 + 1e-5);
    EXPECT_GT(worst, 2.0e-4);  // not far finer than asked
}

TEST(GeometryShapes, PlaneIsTwoTrianglesFacingItsNormal) {
    const glm::vec3 p(1.0f, 2.0f, 3.0f), n = glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f));
    const TriangleMesh m = makePlaneMesh(p, n, 2.0f);
    ASSERT_TRUE(m.validate(true).ok());
    EXPECT_EQ(m.triangleCount(), 2u);
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        EXPECT_NEAR(glm::dot(m.positions[i] - p, n), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::length(m.positions[i] - p), 2.0f * std::sqrt(2.0f), 1e-5f);  // the corners
        EXPECT_LT(glm::length(m.normals[i] - n), 1e-6f);
    }
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
        EXPECT_GT(glm::dot(glm::cross(b - a, c - a), n), 0.0f);
    }
}

TEST(GeometryShapes, TransformMeshKeepsNormalsPerpendicularAndFixesMirroredWinding) {
    TriangleMesh m = makeSphereMesh(glm::vec3(0.0f), 1.0f);
    // Non-uniform scale then a turn then a move: an ellipsoid. Its normals
    // are the gradient of the implicit function, (x/a^2, y/b^2, z/c^2).
    const glm::vec3 s(2.0f, 0.5f, 1.0f), t(1.0f, 2.0f, 3.0f);
    glm::mat4 x = glm::translate(glm::mat4(1.0f), t) * glm::scale(glm::mat4(1.0f), s);
    transformMesh(m, x);
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        const glm::vec3 q = m.positions[i] - t;
        const glm::vec3 expected = glm::normalize(q / (s * s));
        EXPECT_LT(glm::length(m.normals[i] - expected), 1e-4f) << i;
    }
    test::expectClosedAndOriented(m);
    test::expectOutward(m, t);
    // A mirror: the winding is reversed back, normals still outward.
    TriangleMesh box = makeBoxMesh(glm::vec3(0.0f), glm::vec3(1.0f));
    transformMesh(box, glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 2.0f, 1.0f)));
    test::expectClosedAndOriented(box);
    test::expectOutward(box, glm::vec3(-0.5f, 1.0f, 0.5f));
}

TEST(GeometryShapes, FillMissingNormalsGivesAreaWeightedUnitNormals) {
    TriangleMesh m = makeBoxMesh(glm::vec3(0.0f), glm::vec3(1.0f));
    m.normals.clear();
    fillMissingNormals(m);
    ASSERT_TRUE(m.validate(true).ok());
    test::expectOutward(m, glm::vec3(0.5f));
    m.normals[3] = glm::vec3(std::nanf(""));
    m.normals[4] = glm::vec3(0.0f);
    fillMissingNormals(m);
    ASSERT_TRUE(m.validate(true).ok());
    test::expectOutward(m, glm::vec3(0.5f));
}

TEST(GeometryShapes, SceneGeometryBoundsCountsAndAppend) {
    SceneGeometry g;
    EXPECT_TRUE(g.empty());
    EXPECT_TRUE(g.bounds().empty());
    GeometryObject a{"a", makeBoxMesh(glm::vec3(0.0f), glm::vec3(1.0f)), {}, true, false, {}};
    GeometryObject hidden{"hidden", makeBoxMesh(glm::vec3(-10.0f), glm::vec3(-9.0f)), {}, false, false, {}};
    g.objects.push_back(a);
    SceneGeometry more;
    more.objects.push_back(hidden);
    more.objects.push_back({"plane", makePlaneMesh(glm::vec3(0, 2, 0), glm::vec3(0, 1, 0), 1.0f), {}, true, false, {}});
    g.append(std::move(more));
    ASSERT_EQ(g.objects.size(), 3u);
    EXPECT_EQ(g.objects[1].name, "hidden");
    EXPECT_EQ(g.triangleCount(), 12u + 12u + 2u);
    const Bounds b = g.bounds();  // the hidden box is left out
    EXPECT_EQ(b.min, glm::vec3(-1.0f, 0.0f, -1.0f));
    EXPECT_EQ(b.max, glm::vec3(1.0f, 2.0f, 1.0f));
}

TEST(SimulationGeometry, CollidersWhereTheSimulatorPutsThemAndTheDomainCutAway) {
    sim::Scene s;
    s.domain = {glm::vec3(-1.0f, 0.0f, -0.5f), glm::vec3(1.0f, 1.0f, 0.5f)};
    sim::Collider box;
    box.kind = sim::Collider::Kind::Box;
    box.box = {glm::vec3(0.1f, 0.0f, -0.1f), glm::vec3(0.3f, 0.2f, 0.1f)};
    sim::Collider ball;
    ball.kind = sim::Collider::Kind::Sphere;
    ball.center = glm::vec3(-0.5f, 0.5f, 0.0f);
    ball.radius = 0.1f;
    sim::Collider floor;
    floor.kind = sim::Collider::Kind::Plane;
    floor.point = glm::vec3(0.0f, 0.05f, 0.0f);
    floor.normal = glm::vec3(0.0f, 2.0f, 0.0f);
    s.colliders = {box, ball, floor};
    auto g = simulationGeometry(s);
    ASSERT_TRUE(g.ok()) << g.error().describe();
    ASSERT_EQ(g->objects.size(), 4u);
    for (const GeometryObject& o : g->objects) EXPECT_TRUE(o.mesh.validate(true).ok()) << o.name;
    Bounds b;
    for (const glm::vec3& p : g->objects[0].mesh.positions) b.extend(p);
    EXPECT_EQ(b.min, box.box.min);
    EXPECT_EQ(b.max, box.box.max);
    for (const glm::vec3& p : g->objects[1].mesh.positions) EXPECT_NEAR(glm::length(p - ball.center), 0.1f, 1e-6f);
    for (const glm::vec3& p : g->objects[2].mesh.positions) EXPECT_NEAR(p.y, 0.05f, 1e-6f);
    const GeometryObject& walls = g->objects[3];
    EXPECT_EQ(walls.name, "domain");
    EXPECT_TRUE(walls.cutaway);
    EXPECT_FALSE(g->objects[0].cutaway);
    Bounds w;
    for (const glm::vec3& p : walls.mesh.positions) w.extend(p);
    EXPECT_EQ(w.min, s.domain.min);
    EXPECT_EQ(w.max, s.domain.max);
}

TEST(SimulationGeometry, TheGlassSceneMeshColliderAsTheSimulatorReadsIt) {
    auto scene = sim::readScene(std::filesystem::path(MENISCUS_SOURCE_DIR) / "scenes" / "glass.json");
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    auto g = simulationGeometry(*scene);
    ASSERT_TRUE(g.ok()) << g.error().describe();
    ASSERT_EQ(g->objects.size(), 2u);
    EXPECT_EQ(g->objects[0].name, "glass.obj");
    ASSERT_TRUE(g->objects[0].mesh.validate(true).ok());
    auto raw = readMesh(scene->colliders[0].mesh);
    ASSERT_TRUE(raw.ok());
    ASSERT_EQ(g->objects[0].mesh.triangleCount(), raw->triangleCount());
    const sim::Collider& c = scene->colliders[0];
    for (std::size_t i = 0; i < raw->positions.size(); ++i)
        EXPECT_EQ(g->objects[0].mesh.positions[i], raw->positions[i] * c.scale + c.translate);
    const Bounds b = g->bounds();  // the glass stands inside the domain
    EXPECT_GE(b.min.y, scene->domain.min.y - 1e-6f);
    EXPECT_TRUE(g->objects[1].cutaway);
}

TEST(SimulationGeometry, AMissingMeshColliderIsAnErrorNamingTheFile) {
    sim::Scene s;
    s.domain = {glm::vec3(0.0f), glm::vec3(1.0f)};
    sim::Collider m;
    m.kind = sim::Collider::Kind::Mesh;
    m.mesh = test::tempDir() / "no_such_collider.obj";
    s.colliders = {m};
    auto g = simulationGeometry(s);
    ASSERT_FALSE(g.ok());
    EXPECT_EQ(g.error().file, m.mesh.string());
}

}  // namespace
}  // namespace meniscus::geometry_test_local
