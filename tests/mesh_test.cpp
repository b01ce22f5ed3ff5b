// TriangleMesh::validate (src/core/mesh.cpp), the one check of a mesh's
// structure, and its users: the mesh writers refuse what it refuses, naming
// the file, and write nothing. And meshFormatOf, the one rule for a mesh
// file's extension.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "meniscus/mesh.h"
#include "test_util.h"

namespace mesh_test_local {

using namespace meniscus;

namespace {

// A tetrahedron: 4 vertices, 4 triangles, one unit normal per vertex.
TriangleMesh tetrahedron() {
    TriangleMesh m;
    m.positions = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    for (const glm::vec3& p : m.positions) m.normals.push_back(glm::normalize(p));
    m.indices = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    return m;
}

struct Spoilt {
    const char* what;
    void (*spoil)(TriangleMesh&);
    const char* message;  // a part of the error the user reads
};
const Spoilt kSpoilt[] = {
    {"index out of range", [](TriangleMesh& m) { m.indices[7] = 4; },
     "triangle 2 has vertex index 4, out of range (4 vertices)"},
    {"huge index", [](TriangleMesh& m) { m.indices.back() = 0xffffffffu; }, "out of range"},
    {"partial triangle", [](TriangleMesh& m) { m.indices.push_back(0); }, "13 indices is not a whole number of triangles"},
    {"NaN position", [](TriangleMesh& m) { m.positions[3].y = std::nanf(""); }, "vertex 3 has a non-finite position"},
    {"infinite normal", [](TriangleMesh& m) { m.normals[2].x = std::numeric_limits<float>::infinity(); },
     "vertex 2 has a non-finite normal"},
    {"a normal missing", [](TriangleMesh& m) { m.normals.pop_back(); }, "3 normals for 4 vertices"},
    {"a normal too many", [](TriangleMesh& m) { m.normals.push_back({0, 1, 0}); }, "5 normals for 4 vertices"},
    {"an attribute short of a value",
     [](TriangleMesh& m) { m.attributes.push_back({"speed", AttributeType::Float, 1, {1, 2, 3}, {}}); },
     "vertex attribute speed: 3 float values for 4 vertices of 1 components"},
    {"an attribute without a name",
     [](TriangleMesh& m) { m.attributes.push_back({"", AttributeType::Float, 1, {1, 2, 3, 4}, {}}); },
     "a vertex attribute has no name"},
};

}  // namespace

TEST(MeshValidate, WholeMeshesPass) {
    EXPECT_TRUE(tetrahedron().validate().ok());
    EXPECT_TRUE(tetrahedron().validate(/*needNormals=*/true).ok());
    EXPECT_TRUE(TriangleMesh{}.validate(true).ok());  // no surface at all
    TriangleMesh bare = tetrahedron();                // normals are optional unless asked for
    bare.normals.clear();
    EXPECT_TRUE(bare.validate().ok());
    // Unused vertices are no error (a mesh may carry them).
    TriangleMesh spare = tetrahedron();
    spare.positions.push_back({0, 0, 0});
    spare.normals.push_back({0, 1, 0});
    EXPECT_TRUE(spare.validate(true).ok());
}

TEST(MeshValidate, EachBrokenMeshIsNamed) {
    for (const Spoilt& c : kSpoilt) {
        for (bool needNormals : {false, true}) {
            TriangleMesh m = tetrahedron();
            c.spoil(m);
            const Status st = m.validate(needNormals);
            ASSERT_FALSE(st.ok()) << c.what;
            EXPECT_TRUE(st.error().file.empty()) << c.what;  // the caller names the source
            EXPECT_NE(st.error().message.find(c.message), std::string::npos) << c.what << ": " << st.error().message;
        }
    }
}

TEST(MeshValidate, NormalsCanBeRequired) {
    TriangleMesh m = tetrahedron();
    m.normals.clear();
    const Status st = m.validate(/*needNormals=*/true);
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().message.find("0 normals for 4 vertices (one normal per vertex is needed)"), std::string::npos)
        << st.error().message;
    // Without normals the non-finite check has nothing to read past.
    m.positions[1].z = -std::numeric_limits<float>::infinity();
    EXPECT_NE(m.validate().error().message.find("vertex 1 has a non-finite position"), std::string::npos);
}

// The writers refuse every mesh validate() refuses: an error naming the file
// and the problem, and no file left behind.
TEST(MeshValidate, WritersRefuseBrokenMeshes) {
    const auto dir = test::tempDir();
    for (const Spoilt& c : kSpoilt) {
        for (const char* name : {"bad.ply", "bad.obj", "bad.vtp", "bad.vtk"}) {
            const MeshFormat format = *meshFormatOf(name);
            TriangleMesh m = tetrahedron();
            c.spoil(m);
            const std::filesystem::path out = dir / name;
            const Status st = writeMesh(out, m, format);
            ASSERT_FALSE(st.ok()) << c.what;
            EXPECT_EQ(st.error().file, out.string());
            EXPECT_NE(st.error().message.find(c.message), std::string::npos) << c.what << ": " << st.error().message;
            EXPECT_FALSE(std::filesystem::exists(out)) << c.what;
        }
    }
    // A mesh without normals is written (PLY and OBJ have them optional).
    TriangleMesh bare = tetrahedron();
    bare.normals.clear();
    EXPECT_TRUE(writeMesh(dir / "bare.ply", bare, MeshFormat::Ply).ok());
    EXPECT_TRUE(writeMesh(dir / "bare.obj", bare, MeshFormat::Obj).ok());
}

TEST(MeshFormat, ByExtensionInAnyCase) {
    const std::pair<const char*, MeshFormat> known[] = {
        {"a.ply", MeshFormat::Ply}, {"dir.obj/A.PLY", MeshFormat::Ply}, {"mesh_%04d.Ply", MeshFormat::Ply},
        {"a.obj", MeshFormat::Obj}, {"A.OBJ", MeshFormat::Obj},         {"dir.ply/mesh_%04d.oBj", MeshFormat::Obj},
        {"a.vtp", MeshFormat::Vtp}, {"m_%04d.VTP", MeshFormat::Vtp},    {"a.vtk", MeshFormat::VtkLegacy},
    };
    for (const auto& [name, format] : known) {
        auto f = meshFormatOf(name);
        ASSERT_TRUE(f.ok()) << name;
        EXPECT_EQ(*f, format) << name;
    }
    for (const char* name : {"a.stl", "a", "a.ply.gz", ".obj", "dir.obj/a", "a.vtu"}) {
        auto f = meshFormatOf(name);
        ASSERT_FALSE(f.ok()) << name;
        EXPECT_EQ(f.error().describe(), std::string(name) + ": output must end in .ply, .obj, .vtp or .vtk");
    }
}
}  // namespace mesh_test_local
