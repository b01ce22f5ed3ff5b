// Mesh reader (readMesh, src/io/mesh_reader.cpp): what writeMesh writes reads
// back the same, hand-written OBJ and PLY in the forms other tools write
// (quads, negative indices, v/t/n corners, ascii and big-endian PLY, extra
// elements), and broken files fail naming the file and the problem.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>

#include "meniscus/io.h"
#include "mesh_test_util.h"
#include "test_util.h"

namespace meniscus::io_mesh_reader_test_local {
namespace {

namespace fs = std::filesystem;
using test::tempDir;
using test::toBytes;
using test::writeText;

Result<TriangleMesh> readText(const std::string& fileName, const std::string& text) {
    const fs::path path = tempDir() / fileName;
    writeText(path, text);
    return readMesh(path);
}

TriangleMesh ok(Result<TriangleMesh> r) {
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().describe());
    return r.ok() ? std::move(*r) : TriangleMesh{};
}

// Fails naming `name`, with `word` in the message.
void expectError(const Result<TriangleMesh>& r, const std::string& name, const std::string& word) {
    ASSERT_FALSE(r.ok()) << name << ": read " << r->triangleCount() << " triangles";
    EXPECT_EQ(r.error().file, name);
    EXPECT_NE(r.error().message.find(word), std::string::npos) << "expected '" << word << "' in: " << r.error().describe();
}

void expectErrorText(const std::string& fileName, const std::string& text, const std::string& word) {
    const fs::path path = tempDir() / fileName;
    writeText(path, text);
    expectError(readMesh(path), path.string(), word);
}

// ------------------------------------------------------------------ what writeMesh writes

TEST(MeshReader, PlyFromWriteMeshReadsBackIdentical) {
    for (const bool normals : {true, false}) {
        TriangleMesh m = test::icosphere({0.5f, -1.0f, 2.0f}, 0.75f, 3);
        if (!normals) m.normals.clear();
        const fs::path path = tempDir() / "sphere.ply";
        ASSERT_TRUE(writeMesh(path, m, MeshFormat::Ply).ok());
        const TriangleMesh back = ok(readMesh(path));
        EXPECT_EQ(back.positions, m.positions);
        EXPECT_EQ(back.normals, m.normals);
        EXPECT_EQ(back.indices, m.indices);
    }
}

TEST(MeshReader, ObjFromWriteMeshReadsBackIdentical) {
    for (const bool normals : {true, false}) {
        TriangleMesh m = test::icosphere({0.5f, -1.0f, 2.0f}, 0.75f, 3);
        if (!normals) m.normals.clear();
        const fs::path path = tempDir() / "sphere.obj";
        ASSERT_TRUE(writeMesh(path, m, MeshFormat::Obj).ok());
        const TriangleMesh back = ok(readMesh(path));
        EXPECT_EQ(back.positions, m.positions) << "%.9g text gives every float back";
        EXPECT_EQ(back.indices, m.indices);
        ASSERT_EQ(back.normals.size(), m.normals.size());
        for (std::size_t i = 0; i < m.normals.size(); ++i)  // written with 6 digits
            for (int k = 0; k < 3; ++k) ASSERT_NEAR(back.normals[i][k], m.normals[i][k], 1e-6f) << i;
    }
}

// ------------------------------------------------------------------ hand-written OBJ

TEST(MeshReader, ObjQuadsNegativeIndicesAndEveryCornerForm) {
    // A unit cube as other tools write it: comments, groups, materials,
    // texture coordinates, CRLF line ends, a w coordinate, quads, corners
    // v, v/t, v//n, v/t/n, and the last face by negative (relative) indices.
    const std::string obj =
        "# cube\r\nmtllib cube.mtl\r\no Cube\r\n"
        "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0 1.0\r\n"
        "v 0 0 1\r\nv 1 0 1\r\nv 1 1 1\r\nv 0 1 1\r\n"
        "vt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvt 0 1\r\n"
        "vn 0 0 -1\r\nvn 0 0 1\r\n"
        "g sides\r\nusemtl grey\r\ns off\r\n"
        "f 1 4 3 2\r\n"              // bottom (z = 0), plain
        "f 5/1 6/2 7/3 8/4\r\n"      // top, v/t
        "f 1//1 2//1 6//1 5//1\r\n"  // v//n
        "f 2/1/1 3/2/1 7/3/1 6/4/1\r\n"
        "f 3 4 8 7 # trailing comment\r\n"
        "f -8/-4/-2 -4/-3/-1 -1 -5\r\n";  // 1 5 8 4
    const TriangleMesh m = ok(readText("cube.obj", obj));
    ASSERT_EQ(m.positions.size(), 8u);
    EXPECT_EQ(m.positions[3], glm::vec3(0, 1, 0));
    EXPECT_TRUE(m.normals.empty()) << "2 normals for 8 vertices: not per-vertex";
    const std::vector<std::uint32_t> want = {0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                             1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 0, 4, 7, 0, 7, 3};
    EXPECT_EQ(m.indices, want);
}

TEST(MeshReader, ObjPentagonIsAFan) {
    const TriangleMesh m = ok(readText("p.obj", "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\n"));
    EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 3, 4}));
}

TEST(MeshReader, ObjForwardReferencesAreAbsolute) {
    // Positive indices are absolute: a face may come before its vertices.
    const TriangleMesh m = ok(readText("fwd.obj", "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"));
    EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2}));
}

// ------------------------------------------------------------------ hand-written PLY

TEST(MeshReader, AsciiPlyWithQuadsColoursAndOtherElements) {
    const std::string ply =
        "ply\nformat ascii 1.0\ncomment made by hand\n"
        "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element face 2\nproperty list uchar int vertex_index\nproperty uchar flags\n"
        "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
        "end_header\n"
        "0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 255\n0 1 0 9 9 9\n"
        "4 0 1 2 3 7\n3 0 2 3 1\n"
        "0 1\n";
    const TriangleMesh m = ok(readText("quad.ply", ply));
    EXPECT_EQ(m.positions, (std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
    EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 2, 3}));
    EXPECT_TRUE(m.normals.empty());
}

// Binary PLY body, value by value, in either byte order.
struct Body {
    bool big;
    std::vector<std::uint8_t> bytes;
    template <class T>
    Body& put(T v) {
        std::uint8_t b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        if (big) std::reverse(b, b + sizeof(T));
        bytes.insert(bytes.end(), b, b + sizeof(T));
        return *this;
    }
};

std::vector<std::uint8_t> binaryPly(bool big, bool doubles) {
    std::string header = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                         " 1.0\nelement face 1\nproperty list uint uint vertex_indices\n"
                         "element vertex 3\n";
    for (const char* c : {"x", "y", "z", "nx", "ny", "nz"})
        header += std::string("property ") + (doubles ? "double " : "float ") + c + "\n";
    header += "end_header\n";
    Body b{big, {}};
    b.put(std::uint32_t(3)).put(std::uint32_t(2)).put(std::uint32_t(1)).put(std::uint32_t(0));
    const float v[3][6] = {{0, 0, 0, 0, 0, 1}, {1, 0, 0, 0, 0, 1}, {0, 1, 0, 0, 0, 1}};
    for (const auto& row : v)
        for (const float f : row) doubles ? (void)b.put(double(f)) : (void)b.put(f);
    std::vector<std::uint8_t> out = toBytes(header);
    out.insert(out.end(), b.bytes.begin(), b.bytes.end());
    return out;
}

TEST(MeshReader, BinaryPlyBothByteOrdersFacesFirstWithNormals) {
    for (const bool big : {false, true})
        for (const bool doubles : {false, true}) {
            const auto r = parsePlyMesh(binaryPly(big, doubles), "t.ply");
            const TriangleMesh m = ok(r);
            EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{2, 1, 0}));
            EXPECT_EQ(m.positions, (std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
            EXPECT_EQ(m.normals, (std::vector<glm::vec3>(3, glm::vec3(0, 0, 1))));
        }
}

// ------------------------------------------------------------------ broken files

TEST(MeshMalformed, ObjIndexProblems) {
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    expectErrorText("a.obj", tri + "f 1 2 4\n", "line 4: vertex index 4 is out of range (the file has 3 vertices)");
    expectErrorText("b.obj", tri + "f 0 1 2\n", "line 4: vertex index 0 (OBJ indices count from 1)");
    expectErrorText("c.obj", tri + "f -1 -2 -4\n", "vertex index -4 reaches before the first vertex");
    expectErrorText("d.obj", tri + "f 1 2\n", "line 4: face has 2 corners");
    expectErrorText("e.obj", tri + "f 1 2 x\n", "'x' is not a vertex index");
    expectErrorText("f.obj", tri + "f 1 2 /3\n", "has no vertex index");
    expectErrorText("g.obj", tri + "f 1//1 2//1 3//-2\n", "normal index -2 reaches before the first normal");
    expectErrorText("h.obj", tri + "f 1 2 99999999999999999999\n", "is not a vertex index");
}

TEST(MeshMalformed, ObjBadVerticesAndNoFaces) {
    expectErrorText("a.obj", "v 0 0\nf 1 1 1\n", "line 1: vertex has fewer than 3 coordinates");
    expectErrorText("b.obj", "v 0 zero 0\n", "line 1: 'zero' is not a number (vertex coordinate 2)");
    expectErrorText("c.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "OBJ file holds no faces");
    expectErrorText("d.obj", "# nothing\n", "holds no vertices");
    expectErrorText("e.obj", "", "file is empty");
    expectErrorText("f.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "vertex 0 has a non-finite position");
}

TEST(MeshMalformed, PlyIndexAndStructureProblems) {
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                             "0 0 0\n1 0 0\n0 1 0\n";
    expectErrorText("a.ply", head + "3 0 1 3\n", "PLY face 0 has vertex index 3, out of range (3 vertices)");
    expectErrorText("b.ply", head + "3 0 1 -1\n", "vertex index -1, out of range");
    expectErrorText("c.ply", head + "2 0 1\n", "PLY face 0 has 2 vertices");
    expectErrorText("d.ply", head, "PLY element 'face' declares 1 rows");
    expectErrorText("e.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                    "end_header\n0 0 0\n",
                    "no 'face' element");
    expectErrorText("f.ply",
                    "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 0\nproperty list uchar int vertex_indices\nend_header\n",
                    "PLY file holds no faces");
    expectErrorText("g.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                    "element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0\n",
                    "no scalar 'z' property");
    expectErrorText("h.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 1\nproperty list uchar int corners\nend_header\n0 0 0\n3 0 0 0\n",
                    "no 'vertex_indices' list");
    expectErrorText("i.ply", "solid ascii stl\n", "not a PLY file");
}

TEST(MeshMalformed, TruncatedBinaryPlyAtEveryLength) {
    const auto full = binaryPly(false, false);
    const std::string text(full.begin(), full.end());
    const std::size_t body = text.find("end_header\n") + 11;
    for (std::size_t n = 0; n < full.size(); ++n) {
        const std::vector<std::uint8_t> cut(full.begin(), full.begin() + std::ptrdiff_t(n));
        const auto r = parsePlyMesh(cut, "cut.ply");
        ASSERT_FALSE(r.ok()) << "cut at " << n;
        EXPECT_EQ(r.error().file, "cut.ply");
        if (n > body) {
            EXPECT_NE(r.error().message.find("truncated"), std::string::npos) << n << ": " << r.error().message;
        }
    }
}

TEST(MeshMalformed, AbsurdCountsAreRefusedBeforeAllocating) {
    // Four billion vertices and faces in a file of a few bytes: refused from
    // the header, without reserving memory for them.
    const std::string h = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                          "property float y\nproperty float z\nelement face 4000000000\n"
                          "property list uchar uint vertex_indices\nend_header\n";
    const auto r = parsePlyMesh(toBytes(h + "0123456789"), "big.ply");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("declares 4000000000 rows"), std::string::npos) << r.error().message;
    const std::string tooMany = "ply\nformat binary_little_endian 1.0\nelement vertex 5000000000\nproperty float x\n"
                                "property float y\nproperty float z\nelement face 1\n"
                                "property list uchar uint vertex_indices\nend_header\n";
    const auto r2 = parsePlyMesh(toBytes(tooMany), "huge.ply");
    ASSERT_FALSE(r2.ok());
    EXPECT_NE(r2.error().message.find("more than 2^32 - 1 vertices"), std::string::npos) << r2.error().message;
}

TEST(MeshMalformed, FileProblems) {
    const fs::path dir = tempDir();
    expectError(readMesh(dir / "missing.obj"), (dir / "missing.obj").string(), "no such file");
    writeText(dir / "mesh.stl", "solid\n");
    expectError(readMesh(dir / "mesh.stl"), (dir / "mesh.stl").string(), "must end in .obj or .ply");
    // The extension picks the reader, in any case.
    writeText(dir / "TRI.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_EQ(ok(readMesh(dir / "TRI.OBJ")).triangleCount(), 1u);
}

// Regression: a mesh file was read into memory whole before any check (a
// 3 GB file of zeros took 3 GB); it is refused from its first bytes now.
TEST(MeshReader, HugeFileOfZerosIsRefusedFromItsFirstBytes) {
    const fs::path dir = tempDir() / "mesh_zeros";
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const auto& [file, message] : {std::pair<std::string, std::string>{"z.obj", "not a text file (a NUL byte"},
                                        std::pair<std::string, std::string>{"z.ply", "not a PLY file"}}) {
        test::writeText(dir / file, "");
        fs::resize_file(dir / file, std::uintmax_t(3) << 30);  // sparse
        const auto mesh = readMesh(dir / file);
        ASSERT_FALSE(mesh.ok()) << file;
        EXPECT_NE(mesh.error().describe().find((dir / file).string() + ": " + message), std::string::npos)
            << mesh.error().describe();
        fs::remove(dir / file);
    }
}

}  // namespace
}  // namespace meniscus::io_mesh_reader_test_local
