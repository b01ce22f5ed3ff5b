// Attributes on the mesh's vertices (interpolateAttributes,
// src/surface/attributes.cpp) and the writers that carry them (PLY float
// properties, VTK PolyData .vtp and .vtk point data): a constant field comes
// back exactly, a linear one within what the normalised kernel's one-sided
// neighbourhood at a surface allows, the fluid index as a weighted mean, the
// same values for any thread count, the errors named; the files read back
// (our own readers, and VTK's where python3-vtk9 is installed) give the
// vertices, normals and attributes written.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "meniscus/surface.h"
#include "test_util.h"

namespace meniscus::mesh_attributes_test_local {
namespace {

constexpr float kR = 0.01f;  // particle radius, metres

// A block of particles on a 2r lattice, n x n x n, with attributes: a
// constant, a linear velocity (x, 2y, -z) 1/s, and a fluid index, 1 in the
// half of larger x.
ParticleSet block(int n) {
    ParticleSet s;
    Attribute constant{"constant", AttributeType::Float, 1, {}, {}};
    Attribute velocity{"velocity", AttributeType::Float, 3, {}, {}};
    Attribute fluid{"fluid", AttributeType::Int, 1, {}, {}};
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                const glm::vec3 p(2.0f * kR * float(i), 2.0f * kR * float(j), 2.0f * kR * float(k));
                s.positions.push_back(p);
                constant.floats.push_back(7.25f);
                velocity.floats.insert(velocity.floats.end(), {p.x, 2.0f * p.y, -p.z});
                fluid.ints.push_back(2 * i >= n ? 1 : 0);
            }
    s.attributes = {constant, velocity, fluid};
    return s;
}

MeshParams params() {
    MeshParams p;
    p.radiusM = kR;
    return p;
}

struct Meshed {
    ParticleSet particles;
    TriangleMesh mesh;
    float support = 0.0f;
};

Meshed meshedBlock(int n) {
    Meshed m;
    m.particles = block(n);
    MeshStats stats;
    auto mesh = extractSurface(ParticleView::of(m.particles), params(), &stats);
    EXPECT_TRUE(mesh.ok()) << mesh.error().describe();
    if (mesh.ok()) m.mesh = std::move(*mesh);
    m.support = stats.supportM;
    return m;
}

TEST(MeshAttributes, ConstantExactLinearCloseFluidAMean) {
    Meshed m = meshedBlock(10);
    ASSERT_GT(m.mesh.vertexCount(), 1000u);
    EXPECT_FLOAT_EQ(m.support, defaults::kSphSupportRadii * kR);
    ASSERT_TRUE(interpolateAttributes(m.particles, {"constant", "velocity", "fluid"}, m.support, m.mesh).ok());
    ASSERT_EQ(m.mesh.attributes.size(), 3u);
    ASSERT_TRUE(m.mesh.validate(true).ok());
    const Attribute &c = m.mesh.attributes[0], &v = m.mesh.attributes[1], &f = m.mesh.attributes[2];
    EXPECT_EQ(c.name, "constant");
    EXPECT_EQ(v.components, 3);
    EXPECT_EQ(f.type, AttributeType::Float);
    double worst = 0.0, sumError = 0.0;
    int below = 0, above = 0;
    for (std::size_t i = 0; i < m.mesh.vertexCount(); ++i) {
        EXPECT_NEAR(c.floats[i], 7.25f, 7.25f * 2e-6f) << i;
        // The linear field: the normalised kernel reproduces it where the
        // neighbourhood is symmetric and is off by the gradient times the
        // offset of the kernel-weighted centre of the particles from the
        // vertex where it is one-sided: at a free surface that offset is
        // about a radius inward; never more than the support.
        const glm::vec3 x = m.mesh.positions[i];
        const glm::vec3 want(x.x, 2.0f * x.y, -x.z);
        const glm::vec3 got(v.floats[3 * i], v.floats[3 * i + 1], v.floats[3 * i + 2]);
        const double e = glm::length(got - want);
        worst = std::max(worst, e);
        sumError += e;
        // The fluid index: 0 on the faces of the x < half side, 1 on the other's.
        if (x.x < 2.0f * kR * 2.0f) below += f.floats[i] == 0.0f;
        if (x.x > 2.0f * kR * 7.0f) above += f.floats[i] == 1.0f;
        EXPECT_GE(f.floats[i], 0.0f);
        EXPECT_LE(f.floats[i], 1.0f);
    }
    const double gradient = std::sqrt(1.0 + 4.0 + 1.0);  // |grad| of (x, 2y, -z) along the worst direction, bounded
    EXPECT_LT(worst, gradient * double(m.support));
    EXPECT_LT(sumError / double(m.mesh.vertexCount()), 2.0 * double(kR) * gradient);
    EXPECT_GT(below, 100);
    EXPECT_GT(above, 100);
    std::printf("linear field (x, 2y, -z) /s on the block's surface: mean error %.3g m/s, worst %.3g m/s (r = %g m)\n",
                sumError / double(m.mesh.vertexCount()), worst, double(kR));
}

TEST(MeshAttributes, SameValuesForAnyThreadCount) {
    Meshed one = meshedBlock(8), two = meshedBlock(8);
    ASSERT_TRUE(interpolateAttributes(one.particles, {"velocity"}, one.support, one.mesh, 1).ok());
    ASSERT_TRUE(interpolateAttributes(two.particles, {"velocity"}, two.support, two.mesh, 2).ok());
    EXPECT_EQ(one.mesh.attributes[0].floats, two.mesh.attributes[0].floats);
}

TEST(MeshAttributes, ErrorsNameTheProblemAndLeaveTheMesh) {
    Meshed m = meshedBlock(4);
    auto refused = [&](const std::vector<std::string>& names, float support, const char* says) {
        const Status st = interpolateAttributes(m.particles, names, support, m.mesh);
        ASSERT_FALSE(st.ok()) << says;
        EXPECT_NE(st.error().message.find(says), std::string::npos) << st.error().message;
        EXPECT_TRUE(m.mesh.attributes.empty());
    };
    refused({"pressure"}, m.support, "no such attribute (they have: constant, velocity, fluid)");
    refused({"velocity", "velocity"}, m.support, "named twice");
    refused({"velocity"}, 0.0f, "positive length");
    // A mesh that is not these particles': moved away from all of them.
    for (glm::vec3& p : m.mesh.positions) p.x += 1.0f;
    refused({"velocity"}, m.support, "beyond the support of every particle");
}

// The attributes through every format that holds them, read back.
TEST(MeshAttributes, WrittenIntoPlyAndVtkAndReadBack) {
    Meshed m = meshedBlock(5);
    ASSERT_TRUE(interpolateAttributes(m.particles, {"velocity", "fluid"}, m.support, m.mesh).ok());
    const std::filesystem::path dir = test::tempDir() / "mesh_attributes";
    std::filesystem::create_directories(dir);
    for (const char* name : {"m.vtp", "m.vtk", "m.ply"}) {
        SCOPED_TRACE(name);
        auto format = meshFormatOf(name);
        ASSERT_TRUE(format.ok());
        ASSERT_TRUE(writeMesh(dir / name, m.mesh, *format).ok());
    }
    // The VTK files as point sets, through our own VTK readers: the vertices
    // and every point data array, in order.
    for (const char* name : {"m.vtp", "m.vtk"}) {
        SCOPED_TRACE(name);
        auto back = readParticles(dir / name);
        ASSERT_TRUE(back.ok()) << back.error().describe();
        EXPECT_EQ(back->positions, m.mesh.positions);
        const Attribute* normals = back->find("Normals");
        const Attribute* velocity = back->find("velocity");
        const Attribute* fluid = back->find("fluid");
        ASSERT_TRUE(normals && velocity && fluid);
        for (std::size_t i = 0; i < m.mesh.vertexCount(); ++i)
            for (int c = 0; c < 3; ++c) ASSERT_EQ(normals->floats[3 * i + std::size_t(c)], m.mesh.normals[i][c]);
        EXPECT_EQ(velocity->floats, m.mesh.attributes[0].floats);
        EXPECT_EQ(fluid->floats, m.mesh.attributes[1].floats);
    }
    // The PLY as a mesh (its extra vertex properties skipped) and its header.
    auto ply = readMesh(dir / "m.ply");
    ASSERT_TRUE(ply.ok()) << ply.error().describe();
    EXPECT_EQ(ply->positions, m.mesh.positions);
    EXPECT_EQ(ply->normals, m.mesh.normals);
    EXPECT_EQ(ply->indices, m.mesh.indices);
    const auto bytes = test::readBytes(dir / "m.ply");
    const std::string header(bytes.begin(), bytes.begin() + 600);
    EXPECT_NE(header.find("property float velocity_x\nproperty float velocity_y\nproperty float velocity_z\n"
                          "property float fluid\n"),
              std::string::npos)
        << header;
    // VTK's own readers (ParaView's), where installed.
    if (test::runCommand("/usr/bin/python3 -c 'import vtk' 2>/dev/null") == 0) {
        const std::filesystem::path script =
            std::filesystem::path(MENISCUS_TEST_DATA).parent_path().parent_path() / "scripts" / "check_mesh_vtk.py";
        std::string out;
        ASSERT_EQ(test::runCommand("/usr/bin/python3 " + script.string() + " " + (dir / "m.vtp").string() + " " +
                                       (dir / "m.vtk").string(),
                                   &out),
                  0)
            << out;
        EXPECT_NE(out.find("point data velocity: 3 components"), std::string::npos) << out;
        EXPECT_NE(out.find("point data fluid: 1 components"), std::string::npos) << out;
        EXPECT_NE(out.find("open or non-manifold edges 0"), std::string::npos) << out;
    }
}

}  // namespace
}  // namespace meniscus::mesh_attributes_test_local
