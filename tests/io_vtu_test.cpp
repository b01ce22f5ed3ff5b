// VTK XML (.vtu/.vtp) reader tests.
//
// The fixtures in tests/data/vtu/ were written by VTK 9.1 itself
// (scripts/make_vtu_fixtures.py) from the SPlisHSPlasH legacy file
// tests/data/splishsplash/vtk/ParticleData_Fluid_21.vtk. Every variant must
// give the legacy file's float32 values bit for bit; the expected values come
// from a tiny reader of that legacy binary layout written here, so these tests
// do not depend on the project's legacy VTK parser.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <zlib.h>

#include "meniscus/io.h"
#include "test_util.h"

namespace meniscus::io_vtu_test_local {
namespace {

using test::readBytes;
using test::testData;
using test::failsNaming;
using test::toBytes;

// ---------------------------------------------------------------- helpers

// The SPlisHSPlasH legacy binary layout (VTK 4.1, BINARY, big-endian,
// UNSTRUCTURED_GRID): POINTS N float, CELLS (one VTK_VERTEX per particle),
// CELL_TYPES, then POINT_DATA: SCALARS id unsigned_int and a FIELD of velocity
// (3 floats) and density (1 float), in the run's attribute order; each binary
// block is followed by one newline.
struct LegacyFrame {
    std::size_t n = 0;
    std::vector<float> positions;  // 3n
    std::vector<std::uint32_t> ids;
    std::vector<float> density;
    std::vector<float> velocity;  // 3n
};

LegacyFrame readLegacyBinary(const std::filesystem::path& path) {
    const std::vector<std::uint8_t> b = readBytes(path);
    std::size_t p = 0;
    auto line = [&]() {
        const auto nl = std::find(b.begin() + std::ptrdiff_t(p), b.end(), std::uint8_t('\n'));
        std::string s(b.begin() + std::ptrdiff_t(p), nl);
        p = std::size_t(nl - b.begin()) + (nl == b.end() ? 0 : 1);
        return s;
    };
    auto be32 = [&](std::size_t at) {
        if (at + 4 > b.size()) throw std::runtime_error("legacy file truncated");
        return std::uint32_t(b[at]) << 24 | std::uint32_t(b[at + 1]) << 16 | std::uint32_t(b[at + 2]) << 8 |
               std::uint32_t(b[at + 3]);
    };
    auto floats = [&](std::size_t count) {
        std::vector<float> v(count);
        for (std::size_t i = 0; i < count; ++i) v[i] = std::bit_cast<float>(be32(p + 4 * i));
        p += 4 * count;
        return v;
    };
    LegacyFrame f;
    if (line().rfind("# vtk DataFile", 0) != 0) throw std::runtime_error("not legacy vtk");
    line();  // title
    if (line() != "BINARY") throw std::runtime_error("not BINARY");
    while (p < b.size()) {
        std::istringstream in(line());
        std::string key;
        if (!(in >> key)) continue;
        std::size_t n = 0, k = 0;
        if (key == "POINTS") {
            in >> f.n;
            f.positions = floats(3 * f.n);
        } else if (key == "CELLS") {
            in >> n >> k;
            p += 4 * k;
        } else if (key == "CELL_TYPES") {
            in >> n;
            p += 4 * n;
        } else if (key == "SCALARS") {
            line();  // LOOKUP_TABLE
            f.ids.resize(f.n);
            for (std::size_t i = 0; i < f.n; ++i) f.ids[i] = be32(p + 4 * i);
            p += 4 * f.n;
        } else if (key == "FIELD") {
            std::string fieldName;
            in >> fieldName >> k;
            for (std::size_t a = 0; a < k; ++a) {
                std::string l;
                do l = line();
                while (l.empty());
                std::istringstream al(l);
                std::string name;
                std::size_t comps = 0;
                al >> name >> comps >> n;
                auto v = floats(comps * n);
                if (name == "density") f.density = std::move(v);
                if (name == "velocity") f.velocity = std::move(v);
            }
        }
    }
    return f;
}

const LegacyFrame& legacyFrame21() {
    static const LegacyFrame f = readLegacyBinary(testData("splishsplash/vtk/ParticleData_Fluid_21.vtk"));
    return f;
}

std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v); }

std::string base64(const std::vector<std::uint8_t>& in) {
    static const char* a = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < in.size(); i += 3) {
        const std::uint32_t v = std::uint32_t(in[i]) << 16 | (i + 1 < in.size() ? std::uint32_t(in[i + 1]) << 8 : 0) |
                                (i + 2 < in.size() ? in[i + 2] : 0);
        out += a[v >> 18 & 63];
        out += a[v >> 12 & 63];
        out += i + 1 < in.size() ? a[v >> 6 & 63] : '=';
        out += i + 2 < in.size() ? a[v & 63] : '=';
    }
    return out;
}

template <class T>
void appendLE(std::vector<std::uint8_t>& out, T v) {
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    out.insert(out.end(), b, b + sizeof(T));
}

std::vector<std::uint8_t> zlibCompress(const std::vector<std::uint8_t>& raw) {
    uLongf len = compressBound(uLong(raw.size()));
    std::vector<std::uint8_t> out(len);
    EXPECT_EQ(compress2(out.data(), &len, raw.data(), uLong(raw.size()), 6), Z_OK);
    out.resize(len);
    return out;
}

Result<ParticleSet> parseText(const std::string& text, const std::string& name = "hand.vtu") {
    const auto bytes = toBytes(text);
    return parseVtu(bytes, name);
}

std::string replaceFirst(std::string s, const std::string& from, const std::string& to) {
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) s.replace(at, from.size(), to);
    return s;
}

std::string fixtureText(const std::string& file) {
    const auto b = readBytes(testData("vtu/" + file));
    return std::string(b.begin(), b.end());
}

// Position of the first appended byte (after '_').
std::size_t appendedStart(const std::string& s) {
    const auto tag = s.find("<AppendedData");
    return s.find('_', tag) + 1;
}

// ---------------------------------------------------------------- VTK-written fixtures

class VtuFixture : public ::testing::TestWithParam<const char*> {};

TEST_P(VtuFixture, MatchesLegacyTwinBitForBit) {
    const std::string file = GetParam();
    const LegacyFrame& ref = legacyFrame21();
    ASSERT_EQ(ref.n, 6859u);
    ASSERT_EQ(ref.density.size(), ref.n);
    ASSERT_EQ(ref.velocity.size(), 3 * ref.n);

    const auto bytes = readBytes(testData("vtu/" + file));
    const auto r = parseVtu(bytes, file);
    ASSERT_TRUE(r.ok()) << r.error().describe();
    const std::size_t n = file.find("first500") != std::string::npos ? 500 : ref.n;
    ASSERT_EQ(r->size(), n);
    EXPECT_TRUE(r->warnings.empty());
    EXPECT_EQ(r->attributes.size(), 3u);

    const Attribute* id = r->find(kAttrId);
    const Attribute* vel = r->find(kAttrVelocity);
    const Attribute* rho = r->find(kAttrDensity);
    ASSERT_TRUE(id && vel && rho);
    ASSERT_EQ(id->type, AttributeType::Int);
    ASSERT_EQ(vel->type, AttributeType::Float);
    ASSERT_EQ(rho->type, AttributeType::Float);
    ASSERT_EQ(id->components, 1);
    ASSERT_EQ(vel->components, 3);
    ASSERT_EQ(rho->components, 1);
    ASSERT_EQ(id->count(), n);
    ASSERT_EQ(vel->count(), n);
    ASSERT_EQ(rho->count(), n);

    std::size_t bad = 0;
    for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            bad += bits(r->positions[i][c]) != bits(ref.positions[3 * i + std::size_t(c)]);
            bad += bits(vel->floats[3 * i + std::size_t(c)]) != bits(ref.velocity[3 * i + std::size_t(c)]);
        }
        bad += bits(rho->floats[i]) != bits(ref.density[i]);
        bad += id->ints[i] != std::int64_t(ref.ids[i]);
    }
    EXPECT_EQ(bad, 0u) << "values differing from the legacy file";
}

INSTANTIATE_TEST_SUITE_P(AllVariants, VtuFixture,
                         ::testing::Values("fluid21_ascii_first500.vtu", "fluid21_binary.vtu",
                                           "fluid21_binary_zlib.vtu", "fluid21_appended_raw.vtu",
                                           "fluid21_appended_raw_zlib.vtu", "fluid21_appended_base64.vtu",
                                           "fluid21_appended_base64_zlib.vtu", "fluid21_uint64_binary_zlib.vtu",
                                           "fluid21_uint64_appended_raw_zlib.vtu", "fluid21_bigendian_binary.vtu",
                                           "fluid21_bigendian_appended_raw_zlib.vtu", "fluid21_polydata.vtp"),
                         [](const auto& info) {
                             std::string s = info.param;
                             for (char& c : s)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return s;
                         });

TEST(VtuReader, LegacyReferenceLooksLikeTheDamBreak) {
    // Guards the in-test legacy reader itself: ids are a permutation of 0..N-1,
    // densities are SPH densities, everything is inside the tank.
    const LegacyFrame& ref = legacyFrame21();
    ASSERT_EQ(ref.ids.size(), ref.n);
    std::vector<std::uint32_t> ids = ref.ids;
    std::sort(ids.begin(), ids.end());
    for (std::size_t i = 0; i < ids.size(); ++i) ASSERT_EQ(ids[i], i);
    for (std::size_t i = 0; i < ref.n; ++i) {
        EXPECT_GT(ref.density[i], 200.f);
        EXPECT_LT(ref.density[i], 1200.f);
        EXPECT_GE(ref.positions[3 * i], -2.f);
        EXPECT_LE(ref.positions[3 * i], 2.f);
        EXPECT_GE(ref.positions[3 * i + 1], 0.f);
        EXPECT_LE(ref.positions[3 * i + 1], 3.f);
    }
}

TEST(VtuReader, ParseParticlesDispatchesByExtension) {
    const auto bytes = readBytes(testData("vtu/fluid21_polydata.vtp"));
    const auto r = parseParticles(bytes, "frame.vtp");
    ASSERT_TRUE(r.ok()) << r.error().describe();
    EXPECT_EQ(r->size(), 6859u);
    const auto r2 = readParticles(testData("vtu/fluid21_appended_raw.vtu"));
    ASSERT_TRUE(r2.ok()) << r2.error().describe();
    EXPECT_EQ(r2->size(), 6859u);
}

// ---------------------------------------------------------------- hand-made files

TEST(VtuReader, HandMadeAsciiThreePointsWithInt32Attribute) {
    const std::string text = R"(<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">
  <UnstructuredGrid>
    <Piece NumberOfPoints="3" NumberOfCells="0">
      <PointData>
        <DataArray type="Int32" Name="phase" format="ascii">
          7 -2 2147483647
        </DataArray>
        <DataArray type="Float32" Name="Velocity" NumberOfComponents="3" format="ascii">
          1 2 3  4 5 6
          7 8 9
        </DataArray>
        <DataArray type="Float64" Name="rho" format="ascii">998.5 1000 1e3</DataArray>
        <DataArray type="UInt8" Name="ID" format="ascii">0 1 255</DataArray>
      </PointData>
      <Points>
        <DataArray type="Float32" NumberOfComponents="3" format="ascii">
          0.1 0.2 0.3 -1.5 2.5 -3.5 1e-3 4 5
        </DataArray>
      </Points>
      <Cells>
        <DataArray type="Int64" Name="connectivity" format="ascii"></DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
)";
    const auto r = parseText(text);
    ASSERT_TRUE(r.ok()) << r.error().describe();
    ASSERT_EQ(r->size(), 3u);
    EXPECT_EQ(r->positions[0], glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_EQ(r->positions[1], glm::vec3(-1.5f, 2.5f, -3.5f));
    EXPECT_EQ(r->positions[2], glm::vec3(1e-3f, 4.f, 5.f));
    const Attribute* phase = r->find("phase");
    ASSERT_TRUE(phase);
    EXPECT_EQ(phase->type, AttributeType::Int);
    EXPECT_EQ(phase->ints, (std::vector<std::int64_t>{7, -2, 2147483647}));
    const Attribute* vel = r->find(kAttrVelocity);
    ASSERT_TRUE(vel);
    EXPECT_EQ(vel->floats, (std::vector<float>{1, 2, 3, 4, 5, 6, 7, 8, 9}));
    const Attribute* rho = r->find(kAttrDensity);
    ASSERT_TRUE(rho);
    EXPECT_EQ(rho->floats, (std::vector<float>{998.5f, 1000.f, 1000.f}));
    const Attribute* id = r->find(kAttrId);
    ASSERT_TRUE(id);
    EXPECT_EQ(id->type, AttributeType::Int);
    EXPECT_EQ(id->ints, (std::vector<std::int64_t>{0, 1, 255}));
}

// Points (Float32) and ids (Int64) as format="binary", UInt32 header, one stream each.
std::string base64UInt32File(const std::vector<float>& pts, const std::vector<std::int64_t>& ids) {
    std::vector<std::uint8_t> p, i;
    appendLE(p, std::uint32_t(pts.size() * 4));
    for (float v : pts) appendLE(p, v);
    appendLE(i, std::uint32_t(ids.size() * 8));
    for (auto v : ids) appendLE(i, v);
    return R"(<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian" header_type="UInt32">
<UnstructuredGrid><Piece NumberOfPoints=")" +
           std::to_string(ids.size()) + R"(" NumberOfCells="0">
<PointData><DataArray type="Int64" Name="id" format="binary">
)" + base64(i) + R"(
</DataArray></PointData>
<Points><DataArray type="Float32" NumberOfComponents="3" format="binary">)" +
           base64(p) + R"(</DataArray></Points>
</Piece></UnstructuredGrid></VTKFile>
)";
}

TEST(VtuReader, HandMadeBase64UncompressedUInt32Header) {
    const std::vector<float> pts = {1.f, 2.f, 3.f, -0.f, 1e-30f, 3.5e10f, 0.25f, -7.f, 8.f};
    const auto r = parseText(base64UInt32File(pts, {42, -1, 1LL << 40}));
    ASSERT_TRUE(r.ok()) << r.error().describe();
    ASSERT_EQ(r->size(), 3u);
    for (std::size_t k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(bits(r->positions[k][c]), bits(pts[3 * k + std::size_t(c)]));
    const Attribute* id = r->find(kAttrId);
    ASSERT_TRUE(id);
    EXPECT_EQ(id->ints, (std::vector<std::int64_t>{42, -1, 1LL << 40}));
}

// Compressed inline data: VTK encodes header and blocks separately; other
// writers use one stream. Both must read.
TEST(VtuReader, HandMadeCompressedBase64EitherStreamLayout) {
    std::vector<std::uint8_t> raw;
    const int n = 1000;
    for (int k = 0; k < 3 * n; ++k) appendLE(raw, float(k) * 0.5f);
    // Four full blocks of 3000 bytes: lastblocksize is 0, meaning "full".
    const std::size_t bs = 3000;
    std::vector<std::vector<std::uint8_t>> blocks;
    for (std::size_t off = 0; off < raw.size(); off += bs)
        blocks.push_back(zlibCompress({raw.begin() + std::ptrdiff_t(off),
                                       raw.begin() + std::ptrdiff_t(std::min(raw.size(), off + bs))}));
    std::vector<std::uint8_t> header, data;
    appendLE(header, std::uint32_t(blocks.size()));
    appendLE(header, std::uint32_t(bs));
    appendLE(header, std::uint32_t(raw.size() % bs));
    for (const auto& b : blocks) appendLE(header, std::uint32_t(b.size()));
    for (const auto& b : blocks) data.insert(data.end(), b.begin(), b.end());
    std::vector<std::uint8_t> joined = header;
    joined.insert(joined.end(), data.begin(), data.end());
    ASSERT_NE(header.size() % 3, 0u);  // so the two layouts really differ

    for (const std::string& encoded : {base64(header) + base64(data), base64(joined)}) {
        const std::string text =
            R"(<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian" compressor="vtkZLibDataCompressor">
<PolyData><Piece NumberOfPoints="1000" NumberOfVerts="0"><Points>
<DataArray type="Float32" NumberOfComponents="3" format="binary">)" +
            encoded + "</DataArray></Points></Piece></PolyData></VTKFile>";
        const auto r = parseText(text, "zlib.vtp");
        ASSERT_TRUE(r.ok()) << r.error().describe();
        ASSERT_EQ(r->size(), std::size_t(n));
        EXPECT_EQ(r->positions[0], glm::vec3(0.f, 0.5f, 1.f));
        EXPECT_EQ(r->positions[999], glm::vec3(1498.5f, 1499.f, 1499.5f));
    }
}

TEST(VtuReader, SeveralPiecesAreConcatenated) {
    const std::string text = R"(<VTKFile type="UnstructuredGrid" version="0.1">
<UnstructuredGrid>
<Piece NumberOfPoints="2">
  <PointData>
    <DataArray type="Float32" Name="density" format="ascii">1 2</DataArray>
    <DataArray type="Int16" Name="only_first" format="ascii">5 6</DataArray>
  </PointData>
  <Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 1 1</DataArray></Points>
</Piece>
<Piece NumberOfPoints="1">
  <PointData><DataArray type="Float32" Name="density" format="ascii">3</DataArray></PointData>
  <Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">2 2 2</DataArray></Points>
</Piece>
<Piece NumberOfPoints="0"><PointData><DataArray type="Float32" Name="density" format="ascii"></DataArray></PointData></Piece>
</UnstructuredGrid></VTKFile>)";
    const auto r = parseText(text);
    ASSERT_TRUE(r.ok()) << r.error().describe();
    ASSERT_EQ(r->size(), 3u);
    EXPECT_EQ(r->positions[2], glm::vec3(2.f));
    const Attribute* rho = r->find(kAttrDensity);
    ASSERT_TRUE(rho);
    EXPECT_EQ(rho->floats, (std::vector<float>{1, 2, 3}));
    EXPECT_EQ(r->find("only_first"), nullptr);  // not in every piece: dropped with a warning
    EXPECT_FALSE(r->warnings.empty());
}

TEST(VtuReader, ZeroPointsIsNotAnError) {
    const auto r = parseText(R"(<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece NumberOfPoints="0">
<Points><DataArray type="Float32" NumberOfComponents="3" format="ascii"></DataArray></Points></Piece>
</UnstructuredGrid></VTKFile>)");
    ASSERT_TRUE(r.ok()) << r.error().describe();
    EXPECT_EQ(r->size(), 0u);
}

TEST(VtuReader, UnsupportedPointArrayIsSkippedWithWarning) {
    const auto r = parseText(R"(<VTKFile type="PolyData"><PolyData><Piece NumberOfPoints="2">
<PointData>
  <DataArray type="String" Name="label" format="ascii">97 0 98 0</DataArray>
  <DataArray type="Float64" Name="big" format="ascii">1e300 -1e300</DataArray>
</PointData>
<Points><DataArray type="Int32" NumberOfComponents="3" format="ascii">1 2 3 4 5 6</DataArray></Points>
</Piece></PolyData></VTKFile>)");
    ASSERT_TRUE(r.ok()) << r.error().describe();
    EXPECT_EQ(r->positions[1], glm::vec3(4.f, 5.f, 6.f));
    EXPECT_EQ(r->find("label"), nullptr);
    ASSERT_EQ(r->warnings.size(), 1u);
    EXPECT_NE(r->warnings[0].find("label"), std::string::npos);
    const Attribute* big = r->find("big");
    ASSERT_TRUE(big);
    EXPECT_EQ(big->floats[0], std::numeric_limits<float>::infinity());
    EXPECT_EQ(big->floats[1], -std::numeric_limits<float>::infinity());
}

// ---------------------------------------------------------------- malformed input

TEST(VtuMalformed, EmptyFile) {
    const std::vector<std::uint8_t> none;
    EXPECT_TRUE(failsNaming(parseVtu(none, "empty.vtu"), "empty.vtu", {"empty"}));
}

TEST(VtuMalformed, NotXmlAtAll) {
    EXPECT_TRUE(failsNaming(parseText("ply\nformat ascii 1.0\n", "x.vtu"), "x.vtu", {"not a VTKFile"}));
    std::vector<std::uint8_t> bin(300);
    for (std::size_t i = 0; i < bin.size(); ++i) bin[i] = std::uint8_t(i * 37);
    EXPECT_TRUE(failsNaming(parseVtu(bin, "bin.vtu"), "bin.vtu", {"not a VTKFile"}));
}

TEST(VtuMalformed, WrongRootElement) {
    std::string s = fixtureText("fluid21_ascii_first500.vtu");
    s = replaceFirst(s, "<VTKFile", "<VTKFolder");
    s = replaceFirst(s, "</VTKFile>", "</VTKFolder>");
    EXPECT_TRUE(failsNaming(parseText(s, "root.vtu"), "root.vtu", {"not a VTKFile"}));
}

TEST(VtuMalformed, UnsupportedDatasetTypeAndSettings) {
    EXPECT_TRUE(failsNaming(parseText(R"(<VTKFile type="ImageData"><ImageData/></VTKFile>)"), "hand.vtu",
                          {"unsupported", "ImageData"}));
    std::string s = fixtureText("fluid21_binary_zlib.vtu");
    EXPECT_TRUE(failsNaming(parseText(replaceFirst(s, "vtkZLibDataCompressor", "vtkZstdDataCompressor"), "zstd.vtu"),
                          "zstd.vtu", {"unsupported compressor"}));
    EXPECT_TRUE(failsNaming(parseText(replaceFirst(s, "header_type=\"UInt32\"", "header_type=\"Int8\""), "h.vtu"),
                          "h.vtu", {"header_type"}));
    EXPECT_TRUE(failsNaming(parseText(replaceFirst(s, "LittleEndian", "MiddleEndian"), "bo.vtu"), "bo.vtu",
                          {"byte_order"}));
}

TEST(VtuMalformed, UnsupportedPointsType) {
    std::string s = fixtureText("fluid21_ascii_first500.vtu");
    const auto at = s.find("<Points>");
    ASSERT_NE(at, std::string::npos);
    s.replace(s.find("Float32", at), 7, "Float16");
    EXPECT_TRUE(failsNaming(parseText(s, "f16.vtu"), "f16.vtu", {"unsupported type"}));
}

TEST(VtuMalformed, MissingPoints) {
    EXPECT_TRUE(failsNaming(parseText(R"(<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece NumberOfPoints="4">
<PointData/></Piece></UnstructuredGrid></VTKFile>)",
                                    "nopts.vtu"),
                          "nopts.vtu", {"missing Points"}));
    EXPECT_TRUE(failsNaming(parseText(R"(<VTKFile type="UnstructuredGrid"><UnstructuredGrid></UnstructuredGrid></VTKFile>)",
                                    "nopiece.vtu"),
                          "nopiece.vtu", {"Piece"}));
    EXPECT_TRUE(failsNaming(parseText(R"(<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece NumberOfPoints="2">
<Points><DataArray type="Float32" NumberOfComponents="2" format="ascii">1 2 3 4</DataArray></Points>
</Piece></UnstructuredGrid></VTKFile>)",
                                    "two.vtu"),
                          "two.vtu", {"components"}));
}

TEST(VtuMalformed, NumberOfPointsLargerThanData) {
    for (const char* file : {"fluid21_binary.vtu", "fluid21_binary_zlib.vtu", "fluid21_appended_raw.vtu",
                             "fluid21_appended_raw_zlib.vtu", "fluid21_appended_base64.vtu",
                             "fluid21_uint64_appended_raw_zlib.vtu", "fluid21_bigendian_binary.vtu"}) {
        const std::string s = replaceFirst(fixtureText(file), "NumberOfPoints=\"6859\"", "NumberOfPoints=\"6860\"");
        EXPECT_TRUE(failsNaming(parseText(s, file), file, {"count mismatch"})) << file;
    }
    const std::string a =
        replaceFirst(fixtureText("fluid21_ascii_first500.vtu"), "NumberOfPoints=\"500\"", "NumberOfPoints=\"501\"");
    EXPECT_TRUE(failsNaming(parseText(a, "a.vtu"), "a.vtu", {"count mismatch"}));
    const std::string b =
        replaceFirst(fixtureText("fluid21_ascii_first500.vtu"), "NumberOfPoints=\"500\"", "NumberOfPoints=\"499\"");
    EXPECT_TRUE(failsNaming(parseText(b, "b.vtu"), "b.vtu", {"count mismatch"}));
    // An absurd count must fail cleanly, not allocate.
    const std::string c = replaceFirst(fixtureText("fluid21_appended_raw_zlib.vtu"), "NumberOfPoints=\"6859\"",
                                       "NumberOfPoints=\"999999999999999\"");
    EXPECT_TRUE(failsNaming(parseText(c, "c.vtu"), "c.vtu", {"count mismatch", "impossibly"}));
    EXPECT_TRUE(failsNaming(parseText(replaceFirst(fixtureText("fluid21_binary.vtu"), "NumberOfPoints=\"6859\"",
                                                 "NumberOfPoints=\"-3\""),
                                    "neg.vtu"),
                          "neg.vtu", {"NumberOfPoints"}));
}

TEST(VtuMalformed, Base64Garbage) {
    const std::string text = R"(<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece NumberOfPoints="1">
<Points><DataArray type="Float32" NumberOfComponents="3" format="binary">DAAAA@@#!AAAAAAAAAAAAAAAA</DataArray></Points>
</Piece></UnstructuredGrid></VTKFile>)";
    EXPECT_TRUE(failsNaming(parseText(text, "g.vtu"), "g.vtu", {"bad base64"}));

    std::string s = fixtureText("fluid21_binary.vtu");
    const auto at = s.find("format=\"binary\"", s.find("<Points>"));
    const auto gt = s.find('>', at);
    s.replace(gt + 200, 4, "*%$&");
    EXPECT_TRUE(failsNaming(parseText(s, "bin.vtu"), "bin.vtu", {"bad base64"}));

    std::string z = fixtureText("fluid21_appended_base64_zlib.vtu");
    z[appendedStart(z) + 2] = '=';
    EXPECT_TRUE(failsNaming(parseText(z, "pad.vtu"), "pad.vtu", {"bad base64"}));

    // Base64 text that simply ends early.
    const std::string shortText = R"(<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece NumberOfPoints="1">
<Points><DataArray type="Float32" NumberOfComponents="3" format="binary">DAAAAAAAgD8=</DataArray></Points>
</Piece></UnstructuredGrid></VTKFile>)";
    EXPECT_TRUE(failsNaming(parseText(shortText, "s.vtu"), "s.vtu", {"truncated"}));
}

TEST(VtuMalformed, CorruptZlibBlock) {
    for (const char* file : {"fluid21_appended_raw_zlib.vtu", "fluid21_uint64_appended_raw_zlib.vtu"}) {
        std::string s = fixtureText(file);
        const std::size_t start = appendedStart(s);
        const std::size_t hs = std::string(file).find("uint64") != std::string::npos ? 8 : 4;
        std::uint64_t nblocks = 0;
        std::memcpy(&nblocks, s.data() + start, hs);
        ASSERT_GT(nblocks, 0u);
        const std::size_t blockStart = start + hs * (3 + nblocks);
        for (std::size_t k = 10; k < 30; ++k) s[blockStart + k] = char(s[blockStart + k] ^ 0x5a);
        EXPECT_TRUE(failsNaming(parseText(s, file), file, {"zlib block"})) << file;
    }
    // Inline compressed data: replace the first zlib block with other valid base64.
    std::string b = fixtureText("fluid21_binary_zlib.vtu");
    const auto gt = b.find('>', b.find("format=\"binary\""));
    const auto dataStart = b.find("==", gt) + 2;  // the separately encoded header ends in padding
    for (std::size_t k = 8; k < 40; ++k) b[dataStart + k] = 'Q';
    EXPECT_TRUE(failsNaming(parseText(b, "inl.vtu"), "inl.vtu", {"zlib block"}));
}

TEST(VtuMalformed, CompressedSizeBeyondData) {
    std::string s = fixtureText("fluid21_appended_raw_zlib.vtu");
    const std::size_t start = appendedStart(s);
    const std::uint32_t huge = 0x7fffffff;
    std::memcpy(s.data() + start + 12, &huge, 4);  // csize_1 of the first array
    EXPECT_TRUE(failsNaming(parseText(s, "cs.vtu"), "cs.vtu", {"beyond"}));

    // Number of blocks beyond data.
    std::string t = fixtureText("fluid21_appended_raw_zlib.vtu");
    std::memcpy(t.data() + appendedStart(t), &huge, 4);
    EXPECT_TRUE(failsNaming(parseText(t, "nb.vtu"), "nb.vtu", {"corrupt"}));
}

TEST(VtuMalformed, AppendedArrayOffsetsChecked) {
    std::string s = fixtureText("fluid21_appended_raw.vtu");
    const auto at = s.find("offset=\"", s.find("<Points>"));
    s.replace(at, 8, "offset=\"99999999");  // prefixes the old digits: far beyond the data
    EXPECT_TRUE(failsNaming(parseText(s, "off.vtu"), "off.vtu", {"truncated appended data"}));

    std::string noSection = fixtureText("fluid21_appended_raw.vtu");
    noSection.resize(noSection.find("<AppendedData"));
    noSection += "</VTKFile>\n";
    EXPECT_TRUE(failsNaming(parseText(noSection, "nosec.vtu"), "nosec.vtu", {"AppendedData"}));

    std::string noMarker = fixtureText("fluid21_appended_raw.vtu");
    noMarker[appendedStart(noMarker) - 1] = 'X';
    EXPECT_TRUE(failsNaming(parseText(noMarker, "mark.vtu"), "mark.vtu", {"marker"}));
}

TEST(VtuMalformed, TruncatedAppendedRawAtManyOffsets) {
    const std::string s = fixtureText("fluid21_appended_raw.vtu");
    const std::size_t tag = s.find("<AppendedData");
    const std::size_t start = appendedStart(s);
    const std::vector<std::size_t> cuts = {1,         10,        100,       tag / 2,       tag - 1,    tag + 5,
                                           start - 1, start,     start + 1, start + 3,     start + 5,  start + 1000,
                                           s.size() / 2, s.size() - 200, s.size() - 40, s.size() - 12,
                                           s.size() - 2};
    for (std::size_t cut : cuts) {
        const std::string t = s.substr(0, cut);
        EXPECT_TRUE(failsNaming(parseText(t, "cut.vtu"), "cut.vtu", {"truncated", "XML", "missing", "empty"}))
            << "cut at " << cut;
    }
    // Cut inside the appended data, then the closing tags put back: the
    // offsets and sizes themselves must catch it. (Cells are not read, so the
    // cuts are inside the point arrays.)
    const auto offsetOf = [&](const std::string& marker) {
        const auto at = s.find("offset=\"", s.find(marker)) + 8;
        return std::stoul(s.substr(at, s.find('"', at) - at));
    };
    const std::size_t velocity = start + offsetOf("Name=\"velocity\""), points = start + offsetOf("<Points>");
    for (std::size_t cut : {start + 2, start + 30, velocity + 2, velocity + 1000, points + 10, points + 50000}) {
        const std::string t = s.substr(0, cut) + "\n  </AppendedData>\n</VTKFile>\n";
        EXPECT_TRUE(failsNaming(parseText(t, "cut2.vtu"), "cut2.vtu", {"truncated"})) << "cut at " << cut;
    }
}

TEST(VtuMalformed, EveryFixtureTruncatedFails) {
    for (const char* file : {"fluid21_ascii_first500.vtu", "fluid21_binary.vtu", "fluid21_binary_zlib.vtu",
                             "fluid21_appended_raw_zlib.vtu", "fluid21_appended_base64.vtu",
                             "fluid21_appended_base64_zlib.vtu", "fluid21_uint64_binary_zlib.vtu",
                             "fluid21_bigendian_appended_raw_zlib.vtu", "fluid21_polydata.vtp"}) {
        const std::string s = fixtureText(file);
        for (double frac : {0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.999}) {
            const std::string t = s.substr(0, std::size_t(double(s.size()) * frac));
            EXPECT_TRUE(failsNaming(parseText(t, file), file, {"truncated", "XML", "missing", "mismatch"}))
                << file << " cut at " << frac;
        }
    }
}

// Random corruption must never crash (run this under ASan/UBSan).
TEST(VtuMalformed, RandomCorruptionNeverCrashes) {
    std::mt19937 rng(1234);
    int failed = 0, total = 0;
    // The LZ4 and LZMA files VTK wrote (tests/data/vtk_compressed) as well.
    for (const char* file : {"fluid21_appended_raw_zlib.vtu", "fluid21_uint64_binary_zlib.vtu",
                             "fluid21_appended_base64.vtu", "fluid21_bigendian_binary.vtu",
                             "fluid21_ascii_first500.vtu", "../vtk_compressed/fluid21_first500_lz4_appended_raw.vtu",
                             "../vtk_compressed/fluid21_first500_lzma_appended_raw.vtu",
                             "../vtk_compressed/fluid21_first500_lz4_binary.vtu",
                             "../vtk_compressed/fluid21_first500_lzma_appended_base64_uint64.vtu"}) {
        const std::string s = fixtureText(file);
        const std::size_t start = s.find("<AppendedData") != std::string::npos ? appendedStart(s) : 0;
        for (int iter = 0; iter < 60; ++iter) {
            std::string t = s;
            const int flips = 1 + int(rng() % 8);
            for (int k = 0; k < flips; ++k) {
                // Half the mutations in the first 4 KiB (XML, headers), half anywhere.
                const std::size_t range = (iter % 2 == 0) ? std::min<std::size_t>(t.size(), start + 4096) : t.size();
                t[rng() % range] = char(rng());
            }
            const auto r = parseText(t, file);
            ++total;
            if (!r.ok()) {
                ++failed;
                EXPECT_NE(r.error().describe().find(file), std::string::npos);
            } else {
                for (const auto& a : r->attributes) EXPECT_EQ(a.count(), r->size()) << a.name;
            }
        }
    }
    EXPECT_GT(failed, 0);
    EXPECT_EQ(total, 540);
}

}  // namespace
}  // namespace meniscus::io_vtu_test_local
