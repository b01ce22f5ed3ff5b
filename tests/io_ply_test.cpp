// PLY reader: ASCII and both binary encodings, attribute mapping, skipping of
// other elements, and malformed files (which must fail cleanly, naming the file).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "test_util.h"

namespace meniscus::io_ply_test_local {
namespace {

namespace fs = std::filesystem;
using test::readBytes;
using test::tempDir;
using test::toBytes;
using test::writeBytes;
using test::writeText;

// Builds a binary PLY body value by value.
class BinaryWriter {
public:
    explicit BinaryWriter(bool bigEndian) : big_(bigEndian) {}
    template <class T>
    BinaryWriter& put(T v) {
        std::uint8_t b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        if (big_) std::reverse(b, b + sizeof(T));  // the tests run on little-endian hosts
        bytes.insert(bytes.end(), b, b + sizeof(T));
        return *this;
    }
    std::vector<std::uint8_t> bytes;

private:
    bool big_;
};

std::vector<std::uint8_t> concat(const std::string& header, const std::vector<std::uint8_t>& body) {
    std::vector<std::uint8_t> out = toBytes(header);
    out.insert(out.end(), body.begin(), body.end());
    return out;
}

// Writes `bytes` to NAME in a fresh temp dir and parses the file from disk.
struct Parsed {
    fs::path path;
    Result<ParticleSet> result;
};
Parsed parseFile(const std::string& fileName, const std::vector<std::uint8_t>& bytes) {
    const fs::path path = tempDir() / fileName;
    writeBytes(path, bytes);
    const auto data = readBytes(path);
    return {path, parsePly(data, path.string())};
}

void expectError(const Parsed& p, const std::string& word) {
    ASSERT_FALSE(p.result.ok()) << "expected an error mentioning '" << word << "'";
    const std::string text = p.result.error().describe();
    EXPECT_NE(text.find(p.path.filename().string()), std::string::npos) << text;
    EXPECT_NE(text.find(word), std::string::npos) << "expected '" << word << "' in: " << text;
}

// A binary file with double positions, int ids and a face element after the vertices.
std::vector<std::uint8_t> makeBinaryPly(bool bigEndian, bool faceFirst) {
    const std::string format = bigEndian ? "binary_big_endian" : "binary_little_endian";
    const std::string faceHeader = "element face 2\nproperty list uchar int vertex_indices\nproperty uchar flags\n";
    std::string header = "ply\nformat " + format + " 1.0\ncomment made by hand\n";
    if (faceFirst) header += faceHeader;
    header += "element vertex 3\nproperty double x\nproperty double y\nproperty double z\nproperty int id\n";
    if (!faceFirst) header += faceHeader;
    header += "end_header\n";

    BinaryWriter faces(bigEndian);
    faces.put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2).put<std::uint8_t>(7);
    faces.put<std::uint8_t>(4).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2).put<std::int32_t>(1);
    faces.put<std::uint8_t>(9);
    BinaryWriter verts(bigEndian);
    verts.put(1.5).put(-2.25).put(1e-3).put<std::int32_t>(10);
    verts.put(0.125).put(3.0).put(-7.5).put<std::int32_t>(-4);
    verts.put(100.0).put(0.0).put(2.5).put<std::int32_t>(2000000000);

    std::vector<std::uint8_t> body = faceFirst ? faces.bytes : verts.bytes;
    const auto& second = faceFirst ? verts.bytes : faces.bytes;
    body.insert(body.end(), second.begin(), second.end());
    return concat(header, body);
}

void expectBinaryContent(const ParticleSet& set) {
    ASSERT_EQ(set.size(), 3u);
    EXPECT_FLOAT_EQ(set.positions[0].x, 1.5f);
    EXPECT_FLOAT_EQ(set.positions[0].y, -2.25f);
    EXPECT_FLOAT_EQ(set.positions[0].z, 1e-3f);
    EXPECT_FLOAT_EQ(set.positions[1].z, -7.5f);
    EXPECT_FLOAT_EQ(set.positions[2].x, 100.0f);
    const Attribute* id = set.find(kAttrId);
    ASSERT_NE(id, nullptr);
    EXPECT_EQ(id->type, AttributeType::Int);
    ASSERT_EQ(id->ints.size(), 3u);
    EXPECT_EQ(id->ints[0], 10);
    EXPECT_EQ(id->ints[1], -4);
    EXPECT_EQ(id->ints[2], 2000000000);
    EXPECT_EQ(set.attributes.size(), 1u);  // face properties are not vertex attributes
}

// ---------------------------------------------------------------- well-formed files

TEST(PlyReader, AsciiWithExtraPropertiesAndFacesBeforeAndAfter) {
    const std::string text =
        "ply\n"
        "format ascii 1.0\n"
        "comment exported by hand\n"
        "obj_info not a real object\n"
        "element face 2\n"
        "property list uchar int vertex_indices\n"
        "element vertex 3\n"
        "property float x\n"
        "property float y\n"
        "property float z\n"
        "property float temperature\n"
        "property uchar flags\n"
        "property list uchar float neighbours\n"
        "element edge 1\n"
        "property int vertex1\n"
        "property list ushort uint chain\n"
        "end_header\n"
        "3 0 1 2\n"
        "4 0 1 2 0\n"
        "0 0 0 300.5 1 0\n"
        "1 2 3 301 255 2 0.5 0.25\n"
        "\n"
        "-1.5 2e-2 +4 -12.25 7 1 9\n"
        "0 3 0 1 2\n";
    const Parsed p = parseFile("ascii.ply", toBytes(text));
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    const ParticleSet& set = p.result.value();
    ASSERT_EQ(set.size(), 3u);
    EXPECT_FLOAT_EQ(set.positions[1].x, 1.0f);
    EXPECT_FLOAT_EQ(set.positions[1].z, 3.0f);
    EXPECT_FLOAT_EQ(set.positions[2].x, -1.5f);
    EXPECT_FLOAT_EQ(set.positions[2].y, 0.02f);
    EXPECT_FLOAT_EQ(set.positions[2].z, 4.0f);

    const Attribute* temperature = set.find("temperature");
    ASSERT_NE(temperature, nullptr);
    EXPECT_EQ(temperature->type, AttributeType::Float);
    EXPECT_EQ(temperature->components, 1);
    ASSERT_EQ(temperature->floats.size(), 3u);
    EXPECT_FLOAT_EQ(temperature->floats[2], -12.25f);

    const Attribute* flags = set.find("flags");
    ASSERT_NE(flags, nullptr);
    EXPECT_EQ(flags->type, AttributeType::Int);
    ASSERT_EQ(flags->ints.size(), 3u);
    EXPECT_EQ(flags->ints[1], 255);
    EXPECT_EQ(set.find("neighbours"), nullptr);  // list properties are skipped
    EXPECT_EQ(set.find("vertex_indices"), nullptr);
}

TEST(PlyReader, BinaryLittleEndianDoublePositionsIntIds) {
    const Parsed p = parseFile("le.ply", makeBinaryPly(false, false));
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    expectBinaryContent(p.result.value());
}

TEST(PlyReader, BinaryLittleEndianFacesBeforeVertices) {
    const Parsed p = parseFile("le_faces_first.ply", makeBinaryPly(false, true));
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    expectBinaryContent(p.result.value());
}

TEST(PlyReader, BinaryBigEndianDoublePositionsIntIds) {
    const Parsed p = parseFile("be.ply", makeBinaryPly(true, false));
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    expectBinaryContent(p.result.value());
    const Parsed q = parseFile("be_faces_first.ply", makeBinaryPly(true, true));
    ASSERT_TRUE(q.result.ok()) << q.result.error().describe();
    expectBinaryContent(q.result.value());
}

TEST(PlyReader, VelocityAndDensityAscii) {
    const std::string text =
        "ply\r\nformat ascii 1.0\r\nelement vertex 2\r\n"
        "property float x\r\nproperty float y\r\nproperty float z\r\n"
        "property float vx\r\nproperty float vy\r\nproperty float vz\r\nproperty float density\r\n"
        "end_header\r\n"
        "0 0 0 1 2 3 1000\r\n"
        "1 1 1 -1 -2 -3 998.5\r\n";
    const Parsed p = parseFile("vel.ply", toBytes(text));
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    const ParticleSet& set = p.result.value();
    const Attribute* v = set.find(kAttrVelocity);
    ASSERT_NE(v, nullptr);
    EXPECT_EQ(v->type, AttributeType::Float);
    EXPECT_EQ(v->components, 3);
    ASSERT_EQ(v->floats.size(), 6u);
    EXPECT_FLOAT_EQ(v->floats[0], 1.0f);
    EXPECT_FLOAT_EQ(v->floats[2], 3.0f);
    EXPECT_FLOAT_EQ(v->floats[4], -2.0f);
    const Attribute* d = set.find(kAttrDensity);
    ASSERT_NE(d, nullptr);
    ASSERT_EQ(d->floats.size(), 2u);
    EXPECT_FLOAT_EQ(d->floats[1], 998.5f);
    EXPECT_EQ(set.find("vx"), nullptr);
}

TEST(PlyReader, RhoAndScatteredVelocityBinary) {
    // vz before vx, rho instead of density, uint8 density-like property kept by name.
    const std::string header =
        "ply\nformat binary_little_endian 1.0\nelement vertex 1\n"
        "property float32 vz\nproperty float32 x\nproperty float32 vx\nproperty float32 y\n"
        "property float32 vy\nproperty float32 z\nproperty float64 rho\nproperty uint8 phase\nend_header\n";
    BinaryWriter w(false);
    w.put(3.0f).put(10.0f).put(1.0f).put(20.0f).put(2.0f).put(30.0f).put(1001.0).put<std::uint8_t>(2);
    const Parsed p = parseFile("rho.ply", concat(header, w.bytes));
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    const ParticleSet& set = p.result.value();
    ASSERT_EQ(set.size(), 1u);
    EXPECT_EQ(set.positions[0], glm::vec3(10, 20, 30));
    const Attribute* v = set.find(kAttrVelocity);
    ASSERT_NE(v, nullptr);
    EXPECT_EQ(v->floats, (std::vector<float>{1, 2, 3}));
    ASSERT_NE(set.find(kAttrDensity), nullptr);
    EXPECT_FLOAT_EQ(set.find(kAttrDensity)->floats[0], 1001.0f);
    ASSERT_NE(set.find("phase"), nullptr);
    EXPECT_EQ(set.find("phase")->ints[0], 2);
}

TEST(PlyReader, PartialVelocityKeptByName) {
    const std::string text =
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
        "property float vx\nproperty float vy\nend_header\n1 2 3 4 5\n";
    const Parsed p = parseFile("partial.ply", toBytes(text));
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    EXPECT_EQ(p.result->find(kAttrVelocity), nullptr);
    ASSERT_NE(p.result->find("vx"), nullptr);
    EXPECT_FLOAT_EQ(p.result->find("vy")->floats[0], 5.0f);
}

TEST(PlyReader, EveryTypeNameBothEndians) {
    const char* names[] = {"char",  "uchar",  "short",  "ushort", "int",    "uint",    "float",  "double",
                           "int8",  "uint8",  "int16",  "uint16", "int32",  "uint32",  "float32", "float64"};
    for (bool big : {false, true}) {
        std::string header = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                             " 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n";
        for (const char* n : names) header += std::string("property ") + n + " p_" + n + "\n";
        header += "end_header\n";
        BinaryWriter w(big);
        w.put(1.0f).put(2.0f).put(3.0f);
        for (int twice = 0; twice < 2; ++twice) {
            w.put<std::int8_t>(-5).put<std::uint8_t>(250).put<std::int16_t>(-30000).put<std::uint16_t>(60000);
            w.put<std::int32_t>(-2000000000).put<std::uint32_t>(4000000000u).put(0.5f).put(-0.25);
        }
        const Parsed p = parseFile(big ? "types_be.ply" : "types_le.ply", concat(header, w.bytes));
        ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
        const ParticleSet& set = p.result.value();
        EXPECT_EQ(set.positions[0], glm::vec3(1, 2, 3));
        auto intOf = [&](const char* n) { return set.find(std::string("p_") + n)->ints.at(0); };
        auto floatOf = [&](const char* n) { return set.find(std::string("p_") + n)->floats.at(0); };
        EXPECT_EQ(intOf("char"), -5);
        EXPECT_EQ(intOf("int8"), -5);
        EXPECT_EQ(intOf("uchar"), 250);
        EXPECT_EQ(intOf("uint8"), 250);
        EXPECT_EQ(intOf("short"), -30000);
        EXPECT_EQ(intOf("int16"), -30000);
        EXPECT_EQ(intOf("ushort"), 60000);
        EXPECT_EQ(intOf("uint16"), 60000);
        EXPECT_EQ(intOf("int"), -2000000000);
        EXPECT_EQ(intOf("int32"), -2000000000);
        EXPECT_EQ(intOf("uint"), 4000000000LL);
        EXPECT_EQ(intOf("uint32"), 4000000000LL);
        EXPECT_FLOAT_EQ(floatOf("float"), 0.5f);
        EXPECT_FLOAT_EQ(floatOf("float32"), 0.5f);
        EXPECT_FLOAT_EQ(floatOf("double"), -0.25f);
        EXPECT_FLOAT_EQ(floatOf("float64"), -0.25f);
    }
}

TEST(PlyReader, ComponentRunsBecomeOneAttribute) {
    // NAME_0 .. NAME_k-1 of one kind, with NAME itself free: one k-component
    // attribute (what writeParticles writes); anything else stays by name.
    const std::string text =
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
        "property float uv_0\nproperty float uv_1\nproperty int c_0\nproperty int c_1\nproperty int c_2\n"
        "property float m_0\nproperty int m_1\nproperty float s_0\nproperty float t\nproperty float t_0\n"
        "property float t_1\nend_header\n"
        "0 0 0 0.5 1.5 1 2 3 7 8 9 10 11 12\n1 1 1 2.5 3.5 4 5 6 7 8 9 10 11 12\n";
    const auto p = parseFile("runs.ply", toBytes(text));
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    const ParticleSet& set = *p.result;
    const Attribute* uv = set.find("uv");
    ASSERT_NE(uv, nullptr);
    EXPECT_EQ(uv->components, 2);
    EXPECT_EQ(uv->floats, (std::vector<float>{0.5f, 1.5f, 2.5f, 3.5f}));
    const Attribute* c = set.find("c");
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->type, AttributeType::Int);
    EXPECT_EQ(c->ints, (std::vector<std::int64_t>{1, 2, 3, 4, 5, 6}));
    for (const char* kept : {"m_0", "m_1", "s_0", "t", "t_0", "t_1"}) {
        ASSERT_NE(set.find(kept), nullptr) << kept;
        EXPECT_EQ(set.find(kept)->components, 1) << kept;
    }
    EXPECT_EQ(set.attributes.size(), 8u);
}

TEST(PlyReader, IntegerPositions) {
    const std::string header =
        "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty short x\nproperty short y\n"
        "property short z\nend_header\n";
    BinaryWriter w(true);
    w.put<std::int16_t>(1).put<std::int16_t>(-2).put<std::int16_t>(3);
    w.put<std::int16_t>(4).put<std::int16_t>(5).put<std::int16_t>(-6);
    const Parsed p = parseFile("ints.ply", concat(header, w.bytes));
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    EXPECT_EQ(p.result->positions[1], glm::vec3(4, 5, -6));
}

TEST(PlyReader, NanAndInfTokensPreserved) {
    const std::string text =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "end_header\nnan 0 0\n1 inf -INF\n1 2 3\n";
    const Parsed p = parseFile("nan.ply", toBytes(text));
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    const ParticleSet& set = p.result.value();
    ASSERT_EQ(set.size(), 3u);
    EXPECT_TRUE(std::isnan(set.positions[0].x));
    EXPECT_TRUE(std::isinf(set.positions[1].y) && set.positions[1].y > 0);
    EXPECT_TRUE(std::isinf(set.positions[1].z) && set.positions[1].z < 0);
    EXPECT_EQ(set.positions[2], glm::vec3(1, 2, 3));
}

TEST(PlyReader, BinaryNanPreserved) {
    const std::string header =
        "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n";
    BinaryWriter w(false);
    w.put(std::nanf("")).put(1.0f).put(2.0f);
    const Parsed p = parseFile("nan_bin.ply", concat(header, w.bytes));
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    EXPECT_TRUE(std::isnan(p.result->positions[0].x));
}

TEST(PlyReader, ZeroVerticesIsAnEmptySet) {
    const std::string text =
        "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n";
    const Parsed p = parseFile("none.ply", toBytes(text));
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    EXPECT_EQ(p.result->size(), 0u);
}

// ---------------------------------------------------------------- malformed files

TEST(PlyMalformed, TruncatedBinaryAtSeveralOffsets) {
    for (bool faceFirst : {false, true}) {
        const std::vector<std::uint8_t> full = makeBinaryPly(false, faceFirst);
        const std::string fullText(full.begin(), full.end());
        const std::size_t body = fullText.find("end_header\n") + 11;
        const std::vector<std::size_t> cuts = {5, body - 6, body, body + 1, body + 7, body + 20, (body + full.size()) / 2,
                                               full.size() - 1};
        for (std::size_t cut : cuts) {
            SCOPED_TRACE("cut at " + std::to_string(cut) + (faceFirst ? ", faces first" : ""));
            const std::vector<std::uint8_t> part(full.begin(), full.begin() + std::ptrdiff_t(cut));
            const Parsed p = parseFile("truncated.ply", part);
            expectError(p, cut < body ? "end_header" : "truncated");
        }
    }
}

TEST(PlyMalformed, WrongMagic) {
    expectError(parseFile("magic.ply", toBytes("plx\nformat ascii 1.0\nend_header\n")), "not a PLY file");
    expectError(parseFile("binary_junk.ply", std::vector<std::uint8_t>{0x00, 0xff, 0x13, 0x37}), "not a PLY file");
}

TEST(PlyMalformed, UnknownFormat) {
    expectError(parseFile("fmt.ply", toBytes("ply\nformat binary_middle_endian 1.0\nelement vertex 0\nend_header\n")),
                "unknown PLY format");
}

TEST(PlyMalformed, UnknownPropertyType) {
    expectError(parseFile("type.ply", toBytes("ply\nformat ascii 1.0\nelement vertex 1\nproperty half x\nend_header\n")),
                "unknown PLY property type");
}

TEST(PlyMalformed, HeaderCountLargerThanData) {
    const std::string binHeader =
        "ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n";
    BinaryWriter w(false);
    w.put(1.0f).put(2.0f).put(3.0f).put(4.0f).put(5.0f).put(6.0f);
    expectError(parseFile("count_bin.ply", concat(binHeader, w.bytes)), "declares 1000");

    const std::string asciiText =
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
        "end_header\n1 2 3\n4 5 6\n7 8 9\n10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25\n";
    expectError(parseFile("count_ascii.ply", toBytes(asciiText)), "line 11");
    const std::string asciiShort =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "end_header\n1 2 3\n4 5 6\n";
    expectError(parseFile("count_ascii_short.ply", toBytes(asciiShort)), "too few values");
}

TEST(PlyMalformed, AbsurdCountsRejectedBeforeAllocating) {
    for (const char* count : {"18446744073709551615", "4000000000", "99999999999999999999999"}) {
        for (const char* format : {"ascii", "binary_little_endian"}) {
            SCOPED_TRACE(std::string(count) + " " + format);
            const std::string text = std::string("ply\nformat ") + format + " 1.0\nelement vertex " + count +
                                     "\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n";
            const Parsed p = parseFile("absurd.ply", toBytes(text));
            ASSERT_FALSE(p.result.ok());
            EXPECT_NE(p.result.error().describe().find("absurd.ply"), std::string::npos);
        }
    }
    // A face element with a huge count before the vertices, and a huge list length.
    const std::string faces =
        "ply\nformat binary_little_endian 1.0\nelement face 4000000000\nproperty list uint int vertex_indices\n"
        "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    BinaryWriter w(false);
    w.put<std::uint32_t>(0xFFFFFFF0u).put<std::int32_t>(1);
    expectError(parseFile("faces.ply", concat(faces, w.bytes)), "truncated");
}

TEST(PlyReader, ElementsWithoutPropertiesTakeNoData) {
    for (const char* format : {"ascii", "binary_little_endian"}) {
        const std::string text = std::string("ply\nformat ") + format +
                                 " 1.0\nelement marker 18446744073709551615\nelement vertex 0\nproperty float x\n"
                                 "property float y\nproperty float z\nend_header\n";
        const Parsed p = parseFile("markers.ply", toBytes(text));
        ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
        EXPECT_EQ(p.result->size(), 0u);
    }
}

TEST(PlyMalformed, AsciiBodyUnderBinaryFormat) {
    const std::string text =
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n0 0 0\n1 1 1\n2 2 2\n3 3 3\n";
    const Parsed p = parseFile("asciibody.ply", toBytes(text));
    expectError(p, "ASCII");
}

TEST(PlyMalformed, MissingZProperty) {
    const std::string text =
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n";
    expectError(parseFile("noz.ply", toBytes(text)), "'z'");
}

TEST(PlyMalformed, NoVertexElement) {
    const std::string text = "ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n";
    expectError(parseFile("novertex.ply", toBytes(text)), "vertex");
}

TEST(PlyMalformed, NonNumericAsciiValue) {
    const std::string text =
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
        "end_header\n1 2 3\n4 five 6\n";
    const Parsed p = parseFile("word.ply", toBytes(text));
    expectError(p, "not a number");
    expectError(p, "line 9");
}

TEST(PlyMalformed, TooManyAsciiValuesOnALine) {
    const std::string text =
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
        "end_header\n1 2 3 4\n";
    expectError(parseFile("many.ply", toBytes(text)), "found 4");
}

TEST(PlyMalformed, MissingEndHeader) {
    expectError(parseFile("noend.ply", toBytes("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n")),
                "end_header");
}

TEST(PlyMalformed, EmptyFile) { expectError(parseFile("empty.ply", {}), "empty"); }

TEST(PlyMalformed, RandomCorruptionNeverCrashes) {
    const std::vector<std::vector<std::uint8_t>> seeds = {
        makeBinaryPly(false, false), makeBinaryPly(true, true),
        toBytes("ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nelement vertex 2\n"
                "property float x\nproperty float y\nproperty float z\nend_header\n3 0 1 1\n1 2 3\n4 5 6\n")};
    std::mt19937 rng(1234);
    for (const auto& seed : seeds) {
        for (int round = 0; round < 400; ++round) {
            std::vector<std::uint8_t> bytes = seed;
            const int flips = 1 + int(rng() % 4);
            for (int f = 0; f < flips; ++f) bytes[rng() % bytes.size()] = std::uint8_t(rng());
            if (rng() % 3 == 0) bytes.resize(rng() % bytes.size());
            const auto r = parsePly(bytes, "fuzz.ply");
            if (!r.ok()) {
                EXPECT_NE(r.error().describe().find("fuzz.ply"), std::string::npos);
            } else {
                for (const Attribute& a : r->attributes) EXPECT_EQ(a.count(), r->size());
            }
        }
    }
}

}  // namespace
}  // namespace meniscus::io_ply_test_local
