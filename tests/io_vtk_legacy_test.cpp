// Legacy VTK reader (src/io/vtk_legacy.cpp): the real SPlisHSPlasH .vtk files
// must match their .bgeo twins bit for bit and frame_stats.csv; hand-made
// ASCII/BINARY POLYDATA, UNSTRUCTURED_GRID (legacy and 5.1 cells) and
// STRUCTURED_GRID files; and a malformed-input suite that fails cleanly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include "meniscus/io.h"
#include "test_util.h"

namespace meniscus::io_vtk_legacy_test_local {
namespace {

using test::readBytes;
using test::testData;
using test::toBytes;

// ------------------------------------------------------------------ helpers

ParticleSet parseOk(const std::vector<std::uint8_t>& bytes, const std::string& name) {
    auto r = parseVtkLegacy(bytes, name);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().describe());
    return r.ok() ? std::move(r).value() : ParticleSet{};
}
ParticleSet parseOk(const std::string& text, const std::string& name) { return parseOk(toBytes(text), name); }

// Expects failure with the file name and `word` in the message.
void expectFails(const std::vector<std::uint8_t>& bytes, const std::string& name, const std::string& word,
                 const std::string& context = "") {
    const auto r = parseVtkLegacy(bytes, name);
    ASSERT_FALSE(r.ok()) << context << ": parsed " << r->size() << " particles";
    const std::string text = r.error().describe();
    EXPECT_NE(text.find(name), std::string::npos) << context << ": " << text;
    EXPECT_NE(text.find(word), std::string::npos) << context << ": expected '" << word << "' in: " << text;
}
void expectFails(const std::string& text, const std::string& name, const std::string& word) {
    expectFails(toBytes(text), name, word, name);
}

std::vector<std::uint8_t> prefix(const std::vector<std::uint8_t>& v, std::size_t n) {
    return {v.begin(), v.begin() + std::ptrdiff_t(std::min(n, v.size()))};
}

std::size_t find(const std::vector<std::uint8_t>& v, const std::string& s) {
    const auto it = std::search(v.begin(), v.end(), s.begin(), s.end());
    return it == v.end() ? std::string::npos : std::size_t(it - v.begin());
}

std::vector<std::uint8_t> replaced(std::vector<std::uint8_t> v, const std::string& from, const std::string& to) {
    const std::size_t at = find(v, from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at == std::string::npos) return v;
    v.erase(v.begin() + std::ptrdiff_t(at), v.begin() + std::ptrdiff_t(at + from.size()));
    v.insert(v.begin() + std::ptrdiff_t(at), to.begin(), to.end());
    return v;
}

// Text and big-endian binary blocks for hand-made BINARY files.
struct VtkWriter {
    std::vector<std::uint8_t> b;
    VtkWriter& text(const std::string& s) {
        b.insert(b.end(), s.begin(), s.end());
        return *this;
    }
    template <class T>
    VtkWriter& be(T v) {
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, &v, sizeof(T));
        for (std::size_t i = sizeof(T); i-- > 0;) b.push_back(raw[i]);
        return *this;
    }
};

// ------------------------------------------------------------------ real data

const int kSmallFrames[] = {1, 9, 21, 61};

TEST(VtkRealData, BitIdenticalToBgeoTwins) {
    for (int frame : kSmallFrames) {
        SCOPED_TRACE("frame " + std::to_string(frame));
        const std::string stem = "ParticleData_Fluid_" + std::to_string(frame);
        const auto vtk = parseVtkLegacy(readBytes(testData("splishsplash/vtk/" + stem + ".vtk")), stem + ".vtk");
        const auto bgeo = parseBgeo(readBytes(testData("splishsplash/partio/" + stem + ".bgeo")), stem + ".bgeo");
        ASSERT_TRUE(vtk.ok()) << vtk.error().describe();
        ASSERT_TRUE(bgeo.ok()) << bgeo.error().describe();
        const ParticleSet& a = vtk.value();
        const ParticleSet& b = bgeo.value();
        ASSERT_EQ(a.size(), 6859u);
        ASSERT_EQ(b.size(), 6859u);
        EXPECT_EQ(0, std::memcmp(a.positions.data(), b.positions.data(), a.size() * sizeof(glm::vec3)));

        const Attribute* idA = a.find(kAttrId);
        const Attribute* idB = b.find(kAttrId);
        ASSERT_TRUE(idA && idB);
        EXPECT_EQ(idA->type, AttributeType::Int);
        EXPECT_EQ(idA->ints, idB->ints);

        for (std::string_view name : {kAttrVelocity, kAttrDensity}) {
            const Attribute* fa = a.find(name);
            const Attribute* fb = b.find(name);
            ASSERT_TRUE(fa && fb) << name;
            EXPECT_EQ(fa->type, AttributeType::Float);
            EXPECT_EQ(fa->components, fb->components);
            ASSERT_EQ(fa->floats.size(), fb->floats.size());
            EXPECT_EQ(0, std::memcmp(fa->floats.data(), fb->floats.data(), fa->floats.size() * sizeof(float)))
                << name;
        }
        EXPECT_EQ(a.find(kAttrVelocity)->components, 3);
        EXPECT_EQ(a.attributes.size(), 3u);  // id, density, velocity; cells dropped
    }
}

TEST(VtkRealData, MatchesFrameStats) {
    for (int frame : kSmallFrames) {
        SCOPED_TRACE("frame " + std::to_string(frame));
        const std::string name = "ParticleData_Fluid_" + std::to_string(frame) + ".vtk";
        const ParticleSet set = parseOk(readBytes(testData("splishsplash/vtk/" + name)), name);
        ASSERT_NO_FATAL_FAILURE(test::expectMatchesStats(set, test::frameStatsRow("dambreak_r0.025_small", frame)));
        std::vector<std::int64_t> ids = set.find(kAttrId)->ints;
        std::sort(ids.begin(), ids.end());
        for (std::size_t i = 0; i < ids.size(); ++i) ASSERT_EQ(ids[i], std::int64_t(i));
    }
}

TEST(VtkRealData, ThroughReadParticles) {
    const auto r = readParticles(testData("splishsplash/vtk/ParticleData_Fluid_61.vtk"));
    ASSERT_TRUE(r.ok()) << r.error().describe();
    EXPECT_EQ(r->size(), 6859u);
}

// ------------------------------------------------------------------ hand-made

const char* kAsciiPolydata =
    "# vtk DataFile Version 3.0\n"
    "hand made ascii polydata\n"
    "ASCII\n"
    "DATASET POLYDATA\n"
    "POINTS 4 double\n"
    "0 0 0  1.5 -2 3\n"
    "1e-3 +4 5.25\n"
    "-0.5 0.5 1\n"
    "VERTICES 4 8\n"
    "1 0\n1 1\n1 2\n1 3\n"
    "POINT_DATA 4\n"
    "SCALARS rho float\n"
    "LOOKUP_TABLE default\n"
    "1000 1001.5 999 998\n"
    "VECTORS Velocity float\n"
    "1 0 0 0 1 0 0 0 1 -1 -1 -1\n"
    "SCALARS pressure%20kPa double 2\n"
    "LOOKUP_TABLE default\n"
    "1 2 3 4 5 6 7 8\n"
    "FIELD FieldData 2\n"
    "ID 1 4 int\n"
    "3 2 1 0\n"
    "METADATA\n"
    "INFORMATION 0\n"
    "\n"
    "temperature 1 4 float\n"
    "20 21 22 23\n"
    "CELL_DATA 4\n"
    "SCALARS cellval int 1\n"
    "LOOKUP_TABLE default\n"
    "5 6 7 8\n"
    "FIELD FieldData 1\n"
    "cellvec 3 4 float\n"
    "0 0 0 0 0 0 0 0 0 0 0 0\n";

TEST(VtkHandMade, AsciiPolydataScalarsVectorsField) {
    const ParticleSet set = parseOk(kAsciiPolydata, "ascii.vtk");
    ASSERT_EQ(set.size(), 4u);
    EXPECT_EQ(set.positions[0], glm::vec3(0, 0, 0));
    EXPECT_EQ(set.positions[1], glm::vec3(1.5f, -2, 3));
    EXPECT_EQ(set.positions[2], glm::vec3(float(1e-3), 4, 5.25f));
    EXPECT_EQ(set.positions[3], glm::vec3(-0.5f, 0.5f, 1));

    ASSERT_EQ(set.attributes.size(), 5u);  // cell data dropped
    EXPECT_EQ(set.attributes[0].name, "density");
    EXPECT_EQ(set.attributes[0].floats, (std::vector<float>{1000, 1001.5f, 999, 998}));
    EXPECT_EQ(set.attributes[1].name, "velocity");
    EXPECT_EQ(set.attributes[1].components, 3);
    EXPECT_EQ(set.attributes[1].floats, (std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 1, -1, -1, -1}));
    EXPECT_EQ(set.attributes[2].name, "pressure kPa");
    EXPECT_EQ(set.attributes[2].components, 2);
    EXPECT_EQ(set.attributes[2].floats, (std::vector<float>{1, 2, 3, 4, 5, 6, 7, 8}));
    EXPECT_EQ(set.attributes[3].name, "id");
    EXPECT_EQ(set.attributes[3].type, AttributeType::Int);
    EXPECT_EQ(set.attributes[3].ints, (std::vector<std::int64_t>{3, 2, 1, 0}));
    EXPECT_EQ(set.attributes[4].name, "temperature");
    EXPECT_EQ(set.attributes[4].floats, (std::vector<float>{20, 21, 22, 23}));
}

TEST(VtkHandMade, AsciiCrLfAndLowerCaseKeywords) {
    std::string text;
    for (const char* p = kAsciiPolydata; *p; ++p) {
        if (*p == '\n') text += '\r';
        text += *p;
    }
    const ParticleSet set = parseOk(text, "crlf.vtk");
    EXPECT_EQ(set.size(), 4u);
    EXPECT_EQ(set.attributes.size(), 5u);
    const ParticleSet lowerSet = parseOk(
        "# vtk DataFile Version 2.0\nt\nascii\ndataset polydata\npoints 1 float\n1 2 3\npoint_data 1\n"
        "scalars density float\nlookup_table default\n7\n",
        "lower.vtk");
    ASSERT_EQ(lowerSet.size(), 1u);
    EXPECT_EQ(lowerSet.find("density")->floats[0], 7.0f);
}

std::vector<std::uint8_t> binaryPolydata(bool newlineAfterBlocks) {
    const std::string nl = newlineAfterBlocks ? "\n" : "";
    VtkWriter w;
    w.text("# vtk DataFile Version 4.2\nbinary polydata\nBINARY\nDATASET POLYDATA\nPOINTS 3 float\n");
    for (int i = 0; i < 9; ++i) w.be(float(i) * 0.5f - 1.0f);
    w.text(nl + "VERTICES 3 6\n");
    for (int i = 0; i < 3; ++i) w.be(std::int32_t(1)).be(std::int32_t(i));
    w.text(nl + "POINT_DATA 3\nSCALARS density double 1\nLOOKUP_TABLE default\n");
    for (int i = 0; i < 3; ++i) w.be(1000.25 + i);
    w.text(nl + "VECTORS v float\n");
    for (int i = 0; i < 9; ++i) w.be(float(-i));
    w.text(nl + "FIELD FieldData 3\nid 1 3 vtktypeint64\n");
    w.be(std::int64_t(5000000000LL)).be(std::int64_t(-1)).be(std::int64_t(7));
    w.text(nl + "flags 2 3 short\n");
    for (int i = 0; i < 6; ++i) w.be(std::int16_t(-3 + i));
    w.text(nl + "count 1 3 unsigned_int\n");
    w.be(std::uint32_t(0xffffffffu)).be(std::uint32_t(10)).be(std::uint32_t(0x0a0a0a0a));  // bytes that look like newlines
    w.text(nl + "CELL_DATA 3\nSCALARS c unsigned_char 1\nLOOKUP_TABLE default\n");
    w.b.push_back(1);
    w.b.push_back(2);
    w.b.push_back(3);
    w.text(nl);
    return w.b;
}

TEST(VtkHandMade, BinaryPolydata) {
    for (bool nl : {true, false}) {
        SCOPED_TRACE(nl ? "newline after blocks" : "no newline after blocks");
        const ParticleSet set = parseOk(binaryPolydata(nl), "binary.vtk");
        ASSERT_EQ(set.size(), 3u);
        EXPECT_EQ(set.positions[0], glm::vec3(-1.0f, -0.5f, 0.0f));
        EXPECT_EQ(set.positions[2], glm::vec3(2.0f, 2.5f, 3.0f));
        ASSERT_EQ(set.attributes.size(), 5u);
        EXPECT_EQ(set.find("density")->floats, (std::vector<float>{1000.25f, 1001.25f, 1002.25f}));
        EXPECT_EQ(set.find("velocity")->floats, (std::vector<float>{0, -1, -2, -3, -4, -5, -6, -7, -8}));
        EXPECT_EQ(set.find("id")->ints, (std::vector<std::int64_t>{5000000000LL, -1, 7}));
        EXPECT_EQ(set.find("flags")->components, 2);
        EXPECT_EQ(set.find("flags")->ints, (std::vector<std::int64_t>{-3, -2, -1, 0, 1, 2}));
        EXPECT_EQ(set.find("count")->ints, (std::vector<std::int64_t>{0xffffffffLL, 10, 0x0a0a0a0aLL}));
    }
}

TEST(VtkHandMade, BinaryBytesThatLookLikeTextAreStillBinary) {
    // Zero bytes, newlines and digit-like bytes inside binary data must not be
    // taken for ASCII numbers.
    const std::uint32_t bits[6] = {0, 0x0a0a0a0au, 0x31313131u, 0x20202020u, 0, 0x30303030u};
    VtkWriter w;
    w.text("# vtk DataFile Version 4.1\nt\nBINARY\nDATASET POLYDATA\nPOINTS 2 float\n");
    for (std::uint32_t u : bits) w.be(u);
    w.text("\n");
    const ParticleSet set = parseOk(w.b, "bits.vtk");
    ASSERT_EQ(set.size(), 2u);
    for (int i = 0; i < 6; ++i) {
        std::uint32_t got;
        std::memcpy(&got, &set.positions[std::size_t(i / 3)][i % 3], 4);
        EXPECT_EQ(got, bits[i]) << i;
    }
}

TEST(VtkHandMade, UnstructuredGridAscii) {
    const ParticleSet set = parseOk(
        "# vtk DataFile Version 2.0\n"
        "ug\n"
        "ASCII\n"
        "DATASET UNSTRUCTURED_GRID\n"
        "POINTS 3 float\n"
        "0 0 0 1 0 0 0 1 0\n"
        "CELLS 2 6\n"
        "3 0 1 2\n"
        "1 2\n"
        "CELL_TYPES 2\n"
        "5\n"
        "1\n"
        "CELL_DATA 2\n"
        "SCALARS quality float\n"
        "LOOKUP_TABLE default\n"
        "0.5 1\n"
        "POINT_DATA 3\n"
        "SCALARS Density float 1\n"
        "LOOKUP_TABLE default\n"
        "1 2 3\n"
        "NORMALS n float\n"
        "0 0 1 0 0 1 0 0 1\n"
        "TEXTURE_COORDINATES uv 2 float\n"
        "0 0 1 0 0 1\n"
        "SCALARS Id unsigned_char\n"
        "LOOKUP_TABLE default\n"
        "0 1 2\n",
        "ug.vtk");
    ASSERT_EQ(set.size(), 3u);
    EXPECT_EQ(set.positions[1], glm::vec3(1, 0, 0));
    ASSERT_EQ(set.attributes.size(), 4u);
    EXPECT_EQ(set.find("density")->floats, (std::vector<float>{1, 2, 3}));
    EXPECT_EQ(set.find("n")->components, 3);
    EXPECT_EQ(set.find("uv")->components, 2);
    EXPECT_EQ(set.find("id")->ints, (std::vector<std::int64_t>{0, 1, 2}));
}

const char* kVersion51 =
    "# vtk DataFile Version 5.1\n"
    "vtk output\n"
    "ASCII\n"
    "DATASET UNSTRUCTURED_GRID\n"
    "POINTS 3 float\n"
    "0 0 0 1 0 0 0 1 0\n"
    "\n"
    "METADATA\n"
    "INFORMATION 0\n"
    "\n"
    "CELLS 4 3\n"
    "OFFSETS vtktypeint64\n"
    "0 1 2 3\n"
    "CONNECTIVITY vtktypeint64\n"
    "0 1 2\n"
    "CELL_TYPES 3\n"
    "1\n1\n1\n"
    "\n"
    "POINT_DATA 3\n"
    "FIELD FieldData 2\n"
    "velocity 3 3 float\n"
    "1 2 3 4 5 6 7 8 9\n"
    "\n"
    "METADATA\n"
    "INFORMATION 1\n"
    "NAME L2_NORM_RANGE LOCATION vtkDataArray\n"
    "DATA 2 3.74166 13.9284\n"
    "\n"
    "density 1 3 double\n"
    "1000 1000.5 1001\n"
    "\n";

TEST(VtkHandMade, Version51OffsetsConnectivityAscii) {
    const ParticleSet set = parseOk(kVersion51, "v51.vtk");
    ASSERT_EQ(set.size(), 3u);
    ASSERT_EQ(set.attributes.size(), 2u);
    EXPECT_EQ(set.find("velocity")->floats, (std::vector<float>{1, 2, 3, 4, 5, 6, 7, 8, 9}));
    EXPECT_EQ(set.find("density")->floats, (std::vector<float>{1000, 1000.5f, 1001}));
}

TEST(VtkHandMade, Version51OffsetsConnectivityBinary) {
    VtkWriter w;
    w.text("# vtk DataFile Version 5.1\nvtk output\nBINARY\nDATASET POLYDATA\nPOINTS 2 double\n");
    for (int i = 0; i < 6; ++i) w.be(double(i) + 0.125);
    w.text("\nMETADATA\nINFORMATION 0\n\nVERTICES 3 2\nOFFSETS vtktypeint64\n");
    for (int i = 0; i < 3; ++i) w.be(std::int64_t(i));
    w.text("\nCONNECTIVITY vtktypeint64\n");
    for (int i = 0; i < 2; ++i) w.be(std::int64_t(i));
    w.text("\nPOINT_DATA 2\nSCALARS density float 1\nLOOKUP_TABLE default\n");
    w.be(999.0f).be(1001.0f);
    w.text("\n");
    const ParticleSet set = parseOk(w.b, "v51bin.vtk");
    ASSERT_EQ(set.size(), 2u);
    EXPECT_EQ(set.positions[1], glm::vec3(3.125f, 4.125f, 5.125f));
    EXPECT_EQ(set.find("density")->floats, (std::vector<float>{999, 1001}));
}

TEST(VtkHandMade, StructuredGridAndPointsOnly) {
    const ParticleSet grid = parseOk(
        "# vtk DataFile Version 3.0\nsg\nASCII\nDATASET STRUCTURED_GRID\nDIMENSIONS 2 1 1\n"
        "POINTS 2 float\n0 0 0 1 1 1\n",
        "sg.vtk");
    EXPECT_EQ(grid.size(), 2u);
    const ParticleSet bare =
        parseOk("# vtk DataFile Version 2.0\nbare\nASCII\nDATASET POLYDATA\nPOINTS 1 int\n1 2 3\n", "bare.vtk");
    ASSERT_EQ(bare.size(), 1u);
    EXPECT_EQ(bare.positions[0], glm::vec3(1, 2, 3));
    EXPECT_TRUE(bare.attributes.empty());
}

TEST(VtkHandMade, DatasetFieldDataAndColorScalarsAndLookupTable) {
    const ParticleSet set = parseOk(
        "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\n"
        "FIELD FieldData 1\nTIME 1 1 double\n0.5\n"
        "POINTS 2 float\n0 0 0 1 1 1\n"
        "POINT_DATA 2\n"
        "COLOR_SCALARS rgb 3\n1 0 0 0 1 0\n"
        "SCALARS s float 1\nLOOKUP_TABLE mytable\n0.25 0.75\n"
        "LOOKUP_TABLE mytable 2\n0 0 0 1 1 1 1 1\n",
        "misc.vtk");
    ASSERT_EQ(set.size(), 2u);
    ASSERT_EQ(set.attributes.size(), 2u);
    EXPECT_EQ(set.find("rgb")->floats, (std::vector<float>{1, 0, 0, 0, 1, 0}));
    EXPECT_EQ(set.find("s")->floats, (std::vector<float>{0.25f, 0.75f}));
}

// ------------------------------------------------------------------ malformed

class VtkMalformed : public ::testing::Test {
protected:
    void SetUp() override {
        real = readBytes(testData("splishsplash/vtk/ParticleData_Fluid_21.vtk"));
        ASSERT_EQ(real.size(), 302065u);
        headerEnd = find(real, "POINTS 6859 float\n") + std::string("POINTS 6859 float\n").size();
        ASSERT_GT(headerEnd, 20u);
    }
    std::vector<std::uint8_t> real;
    std::size_t headerEnd = 0;  // first byte of the POINTS binary block
};

TEST_F(VtkMalformed, TruncatedRealFile) {
    const std::size_t cuts[] = {0,
                                3,
                                10,
                                30,
                                headerEnd - 1,
                                headerEnd,
                                headerEnd + 100,
                                real.size() / 2,
                                find(real, "FIELD FieldData 2\n") + 18,
                                find(real, "SCALARS id") + 60,
                                real.size() - 2};
    for (std::size_t cut : cuts)
        expectFails(prefix(real, cut), "cut.vtk", "truncated", "cut at " + std::to_string(cut));
}

TEST_F(VtkMalformed, WrongMagic) {
    auto bad = real;
    bad[2] = 'V';
    expectFails(bad, "magic.vtk", "magic");
    expectFails(toBytes("<?xml version=\"1.0\"?>\n<VTKFile>"), "xml.vtk", "magic");
}

TEST_F(VtkMalformed, HeaderCountLargerThanData) {
    expectFails(replaced(real, "POINTS 6859 float", "POINTS 68590 float"), "points.vtk", "truncated");
    expectFails(replaced(real, "POINTS 6859 float", "POINTS 999999999999 float"), "points.vtk", "truncated");
    expectFails(replaced(real, "POINTS 6859 float", "POINTS 99999999999999999999999 float"), "points.vtk", "count");
    expectFails(replaced(real, "density 1 6859 float", "density 1 6860 float"), "field.vtk", "count mismatch");
    expectFails("# vtk DataFile Version 2.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 5 float\n0 0 0 1 1 1\n",
                "short.vtk", "truncated");
}

TEST_F(VtkMalformed, PointDataCountMismatch) {
    expectFails(replaced(real, "POINT_DATA 6859", "POINT_DATA 6860"), "pd.vtk", "count mismatch");
    expectFails(replaced(toBytes(kAsciiPolydata), "POINT_DATA 4", "POINT_DATA 3"), "pd.vtk", "count mismatch");
}

TEST_F(VtkMalformed, AsciiWhereBinaryDeclared) {
    expectFails(replaced(toBytes(kAsciiPolydata), "\nASCII\n", "\nBINARY\n"), "asciibin.vtk", "BINARY");
    expectFails("# vtk DataFile Version 2.0\nt\nBINARY\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\n", "tiny.vtk",
                "BINARY");
    expectFails(replaced(toBytes(kVersion51), "\nASCII\n", "\nBINARY\n"), "v51.vtk", "BINARY");
}

TEST_F(VtkMalformed, BinaryBlockShorterThanDeclared) {
    auto bin = binaryPolydata(true);
    expectFails(prefix(bin, find(bin, "VECTORS v float\n") + 16 + 20), "short.vtk", "truncated");
}

TEST_F(VtkMalformed, AsciiProblems) {
    expectFails(replaced(toBytes(kAsciiPolydata), "1000 1001.5 999 998", "1000 1001.5 abc 998"), "nan.vtk",
                "non-numeric");
    expectFails(replaced(toBytes(kAsciiPolydata), "1000 1001.5 999 998", "1000 1001.5 999"), "few.vtk",
                "truncated");
    expectFails(replaced(toBytes(kAsciiPolydata), "3 2 1 0", "3 2 1.5 0"), "int.vtk", "non-numeric");
    expectFails(replaced(toBytes(kAsciiPolydata), "ID 1 4 int", "ID 1 4 bit"), "bit.vtk", "bit");
    expectFails(replaced(toBytes(kAsciiPolydata), "ID 1 4 int", "ID 1 4 string"), "str.vtk", "string");
    expectFails(replaced(toBytes(kAsciiPolydata), "ID 1 4 int", "ID 1 4 quaternion"), "type.vtk", "unknown data type");
    expectFails(replaced(toBytes(kAsciiPolydata), "VECTORS Velocity", "WIBBLE Velocity"), "kw.vtk", "WIBBLE");
}

TEST_F(VtkMalformed, HeaderProblems) {
    expectFails("# vtk DataFile Version 6.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 0 float\n", "v6.vtk", "version");
    expectFails("# vtk DataFile Version 3.0\nt\nTEXT\nDATASET POLYDATA\n", "mode.vtk", "ASCII or BINARY");
    expectFails("# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\n", "sp.vtk",
                "unsupported dataset");
    expectFails("# vtk DataFile Version 3.0\nt\nASCII\nDATASET RECTILINEAR_GRID\n", "rg.vtk", "unsupported dataset");
    expectFails("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINT_DATA 0\n", "order.vtk", "POINTS");
    expectFails("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\n", "nopoints.vtk", "POINTS");
    expectFails("# vtk DataFile Version 3.0\nt\nASCII\nFIELD f 0\n", "nodataset.vtk", "DATASET");
    expectFails("# vtk DataFile Version 5.1\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\nVERTICES 2 1\n0 1\n",
                "v5cells.vtk", "OFFSETS");
}

TEST_F(VtkMalformed, EveryPrefixIsHandled) {
    // Prefixes that end between sections are valid files; all others must fail
    // with the name; none may crash.
    auto check = [](const std::vector<std::uint8_t>& bytes, std::size_t step) {
        for (std::size_t cut = 0; cut + 1 < bytes.size(); cut += step) {
            const auto r = parseVtkLegacy(prefix(bytes, cut), "p.vtk");
            if (!r.ok()) {
                ASSERT_NE(r.error().describe().find("p.vtk"), std::string::npos);
            }
        }
    };
    check(real, 911);
    check(toBytes(kAsciiPolydata), 1);
    check(toBytes(kVersion51), 1);
    check(binaryPolydata(true), 1);
    check(binaryPolydata(false), 1);
}

TEST_F(VtkMalformed, RandomByteFlipsNeverCrash) {
    std::mt19937 rng(4242);
    const std::vector<std::vector<std::uint8_t>> seeds = {prefix(real, 4000), toBytes(kAsciiPolydata),
                                                          toBytes(kVersion51), binaryPolydata(true)};
    for (const auto& seed : seeds) {
        for (int trial = 0; trial < 300; ++trial) {
            auto bad = seed;
            const int flips = 1 + int(rng() % 4);
            for (int f = 0; f < flips; ++f) {
                const std::size_t at = rng() % bad.size();
                bad[at] = (rng() % 2) ? std::uint8_t(rng()) : std::uint8_t("0123456789 \n-.e"[rng() % 15]);
            }
            const auto r = parseVtkLegacy(bad, "fuzz.vtk");
            if (!r.ok()) {
                EXPECT_NE(r.error().describe().find("fuzz.vtk"), std::string::npos);
            }
        }
    }
}

}  // namespace
}  // namespace meniscus::io_vtk_legacy_test_local
