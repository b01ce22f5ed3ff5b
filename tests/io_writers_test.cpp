// Particle writers (writeParticles, src/io/*_writer.cpp): every format round
// trips through our readers bit for bit (positions and every attribute, by
// name and type), real SPlisHSPlasH frames included; the BGEO writer writes
// the very bytes partio wrote for SPlisHSPlasH; bad sets and unwritable paths
// fail naming the file and leave nothing behind. With VTK's python module
// present, VTK's own readers (ParaView's) open every file we write.
//
// Zero particles: writeParticles writes a valid empty file (a simulation's
// frame before its emitter starts, or after a drain took everything), which
// the format's parser reads as an empty set and readParticles refuses, as it
// refuses every file without particles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>

#include "meniscus/io.h"
#include "test_util.h"

namespace meniscus::io_writers_test_local {
namespace {

namespace fs = std::filesystem;
using test::readBytes;
using test::tempDir;
using test::testData;

const std::vector<std::string> kExtensions = {".bgeo", ".bgeo.gz", ".vtk", ".vtu", ".vtp", ".ply"};

Attribute floats(const std::string& name, int components, std::vector<float> v) {
    Attribute a;
    a.name = name;
    a.components = components;
    a.floats = std::move(v);
    return a;
}

Attribute ints(const std::string& name, int components, std::vector<std::int64_t> v) {
    Attribute a;
    a.name = name;
    a.type = AttributeType::Int;
    a.components = components;
    a.ints = std::move(v);
    return a;
}

// n particles with the canonical attributes and others of 1, 2, 3 and 6
// components; values of every magnitude and sign, NaN and infinities in an
// attribute (only positions must be finite), int32 extremes.
ParticleSet sampleSet(std::size_t n, unsigned seed = 7) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    ParticleSet set;
    std::vector<float> vel, rho, temp, uv, stress;
    std::vector<std::int64_t> id, cell;
    for (std::size_t i = 0; i < n; ++i) {
        set.positions.emplace_back(u(rng) * 4.0f, u(rng) * 1e-7f, std::ldexp(u(rng), int(i % 60) - 30));
        for (int c = 0; c < 3; ++c) vel.push_back(u(rng) * 10.0f);
        rho.push_back(1000.0f + 50.0f * u(rng));
        const float specials[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                                  -std::numeric_limits<float>::infinity(), -0.0f,
                                  std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::max()};
        temp.push_back(i % 7 < 6 ? specials[i % 7] : u(rng));
        uv.push_back(u(rng));
        uv.push_back(float(i));
        for (int c = 0; c < 6; ++c) stress.push_back(u(rng) * 1e5f);
        const std::int64_t extremes[] = {std::numeric_limits<std::int32_t>::min(),
                                         std::numeric_limits<std::int32_t>::max(), -1, 0};
        id.push_back(std::int64_t(n - i) * 3);
        for (int c = 0; c < 3; ++c) cell.push_back(i % 5 == 0 ? extremes[(i / 5 + std::size_t(c)) % 4] : std::int64_t(i) * c);
    }
    set.attributes.push_back(ints(std::string(kAttrId), 1, id));
    set.attributes.push_back(floats(std::string(kAttrVelocity), 3, vel));
    set.attributes.push_back(floats(std::string(kAttrDensity), 1, rho));
    set.attributes.push_back(floats("temperature", 1, temp));
    set.attributes.push_back(floats("uv", 2, uv));
    set.attributes.push_back(ints("cell", 3, cell));
    set.attributes.push_back(floats("stress", 6, stress));
    return set;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Positions and every attribute (found by name) bit for bit, nothing more or less.
void expectSameSet(const ParticleSet& want, const ParticleSet& got, const std::string& context) {
    ASSERT_EQ(got.size(), want.size()) << context;
    for (std::size_t i = 0; i < want.size(); ++i)
        for (int k = 0; k < 3; ++k)
            ASSERT_TRUE(sameBits(got.positions[i][k], want.positions[i][k]))
                << context << ": particle " << i << " axis " << k << ": " << got.positions[i][k] << " vs "
                << want.positions[i][k];
    ASSERT_EQ(got.attributes.size(), want.attributes.size()) << context;
    for (const Attribute& w : want.attributes) {
        const Attribute* g = got.find(w.name);
        ASSERT_NE(g, nullptr) << context << ": attribute '" << w.name << "' missing";
        ASSERT_EQ(int(g->type), int(w.type)) << context << ": " << w.name;
        ASSERT_EQ(g->components, w.components) << context << ": " << w.name;
        ASSERT_EQ(g->ints, w.ints) << context << ": " << w.name;
        ASSERT_EQ(g->floats.size(), w.floats.size()) << context << ": " << w.name;
        for (std::size_t i = 0; i < w.floats.size(); ++i)
            ASSERT_TRUE(sameBits(g->floats[i], w.floats[i]))
                << context << ": " << w.name << " value " << i << ": " << g->floats[i] << " vs " << w.floats[i];
    }
}

ParticleSet writeAndRead(const ParticleSet& set, const fs::path& path) {
    const Status st = writeParticles(path, set);
    EXPECT_TRUE(st.ok()) << (st.ok() ? "" : st.error().describe());
    auto r = readParticles(path);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().describe());
    if (!r) return {};
    EXPECT_TRUE(r->warnings.empty()) << path << ": " << r->warnings.front();
    return std::move(*r);
}

std::vector<std::string> filesIn(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// ------------------------------------------------------------------ round trips

class EveryFormat : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryFormat, RoundTripsEveryAttributeBitForBit) {
    const ParticleSet set = sampleSet(1500);
    const fs::path path = tempDir() / ("sample" + GetParam());
    expectSameSet(set, writeAndRead(set, path), path.string());
    EXPECT_EQ(filesIn(path.parent_path()), std::vector<std::string>{path.filename().string()})
        << "the temporary file is gone";
}

TEST_P(EveryFormat, OneParticleAndNoAttributes) {
    const fs::path dir = tempDir();
    ParticleSet one = sampleSet(1);
    expectSameSet(one, writeAndRead(one, dir / ("one" + GetParam())), "one particle");
    ParticleSet bare;
    bare.positions = {{0.5f, -2.0f, 3.25f}, {1e-30f, 1e30f, -0.0f}};
    expectSameSet(bare, writeAndRead(bare, dir / ("bare" + GetParam())), "no attributes");
}

TEST_P(EveryFormat, ZeroParticlesGiveAValidEmptyFile) {
    ParticleSet empty = sampleSet(0);
    const fs::path path = tempDir() / ("empty" + GetParam());
    ASSERT_TRUE(writeParticles(path, empty).ok());
    const auto bytes = readBytes(path);
    const std::string name = path.string();
    const ParticleFormat f = formatFromName(name);
    auto parsed = f == ParticleFormat::Bgeo        ? parseBgeo(bytes, name)
                  : f == ParticleFormat::VtkLegacy ? parseVtkLegacy(bytes, name)
                  : f == ParticleFormat::Vtu       ? parseVtu(bytes, name)
                                                   : parsePly(bytes, name);
    ASSERT_TRUE(parsed.ok()) << parsed.error().describe();
    EXPECT_EQ(parsed->size(), 0u);
    // readParticles refuses empty files, ours included.
    const auto r = readParticles(path);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().describe().find("no particles"), std::string::npos) << r.error().describe();
}

TEST_P(EveryFormat, SameSetSameBytes) {
    // A simulation's frames are bit-identical run to run only if the writer is.
    const ParticleSet set = sampleSet(300);
    const fs::path dir = tempDir();
    ASSERT_TRUE(writeParticles(dir / ("a" + GetParam()), set).ok());
    ASSERT_TRUE(writeParticles(dir / ("b" + GetParam()), set).ok());
    EXPECT_EQ(readBytes(dir / ("a" + GetParam())), readBytes(dir / ("b" + GetParam())));
}

TEST_P(EveryFormat, RealSplishsplashFrameRoundTrips) {
    const auto frame = readParticles(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
    ASSERT_TRUE(frame.ok()) << frame.error().describe();
    ASSERT_EQ(frame->size(), 6859u);
    const fs::path path = tempDir() / ("fluid21" + GetParam());
    expectSameSet(*frame, writeAndRead(*frame, path), path.string());
}

INSTANTIATE_TEST_SUITE_P(Writers, EveryFormat, ::testing::ValuesIn(kExtensions), [](const auto& info) {
    std::string s = info.param.substr(1);
    std::replace(s.begin(), s.end(), '.', '_');
    return s;
});

TEST(BgeoWriter, WritesTheBytesPartioWroteForSplishsplash) {
    // SPlisHSPlasH's frames were written by partio (gzip-compressed). Read and
    // written again, plain (.bgeo) and compressed (.bgeo.gz): the same bytes
    // once inflated, header, attribute table (id int, density float, velocity
    // vector), records with w = 1 and the 00 ff trailer alike.
    for (const char* frame : {"ParticleData_Fluid_1", "ParticleData_Fluid_21"}) {
        const fs::path original = testData(std::string("splishsplash/partio/") + frame + ".bgeo");
        const auto set = readParticles(original);
        ASSERT_TRUE(set.ok()) << set.error().describe();
        const auto want = inflateGzip(readBytes(original), original.string());
        ASSERT_TRUE(want.ok());
        const fs::path dir = tempDir();
        ASSERT_TRUE(writeParticles(dir / (std::string(frame) + ".bgeo"), *set).ok());
        ASSERT_TRUE(writeParticles(dir / (std::string(frame) + ".bgeo.gz"), *set).ok());
        const auto plain = readBytes(dir / (std::string(frame) + ".bgeo"));
        const auto gz = readBytes(dir / (std::string(frame) + ".bgeo.gz"));
        ASSERT_GE(gz.size(), 2u);
        EXPECT_TRUE(gz[0] == 0x1f && gz[1] == 0x8b) << ".bgeo.gz is gzip data";
        const auto inflated = inflateGzip(gz, "ours.bgeo.gz");
        ASSERT_TRUE(inflated.ok());
        EXPECT_EQ(plain.size(), want->size()) << frame;
        EXPECT_TRUE(plain == *want) << frame << ": .bgeo bytes differ from partio's";
        EXPECT_TRUE(*inflated == *want) << frame << ": inflated .bgeo.gz bytes differ from partio's";
    }
}

TEST(BgeoWriter, LargeRealFrame) {
    // The r = 0.01 dam break: 117,649 particles (the benchmark's scene).
    const auto frame = readParticles(test::repoData("dambreak_r0.01/ParticleData_Fluid_21.bgeo"));
    ASSERT_TRUE(frame.ok()) << frame.error().describe();
    ASSERT_EQ(frame->size(), 117649u);
    const fs::path path = tempDir() / "big.bgeo";
    expectSameSet(*frame, writeAndRead(*frame, path), path.string());
}

// ------------------------------------------------------------------ what each format holds

std::string headerText(const fs::path& path, std::size_t n) {
    const auto b = readBytes(path);
    return std::string(b.begin(), b.begin() + std::ptrdiff_t(std::min(n, b.size())));
}

TEST(VtkLegacyWriter, BinaryPolydataWithVerticesDensityVelocityAndField) {
    const fs::path path = tempDir() / "f.vtk";
    ASSERT_TRUE(writeParticles(path, sampleSet(4)).ok());
    const auto b = readBytes(path);
    const std::string all(b.begin(), b.end());
    EXPECT_EQ(all.rfind("# vtk DataFile Version 4.2\n", 0), 0u);
    for (const char* line : {"\nBINARY\nDATASET POLYDATA\nPOINTS 4 float\n", "\nVERTICES 4 8\n", "\nPOINT_DATA 4\n",
                             "\nVECTORS velocity float\n", "\nSCALARS density float 1\nLOOKUP_TABLE default\n",
                             "\nFIELD FieldData 5\nid 1 4 int\n", "\ntemperature 1 4 float\n", "\nuv 2 4 float\n",
                             "\ncell 3 4 int\n", "\nstress 6 4 float\n"})
        EXPECT_NE(all.find(line), std::string::npos) << "missing: " << line;
    // One SCALARS and one VECTORS: VTK's reader keeps only the first of each.
    EXPECT_EQ(all.find("SCALARS"), all.rfind("SCALARS"));
}

TEST(VtkLegacyWriter, NamesWithSpacesAndPercentRoundTrip) {
    ParticleSet set;
    set.positions = {{1, 2, 3}};
    set.attributes.push_back(floats("wet area %", 1, {0.25f}));
    const fs::path path = tempDir() / "names.vtk";
    const ParticleSet back = writeAndRead(set, path);
    expectSameSet(set, back, "names");
    EXPECT_NE(headerText(path, 4096).find("\nwet%20area%20%25 1 1 float\n"), std::string::npos);
}

TEST(VtuWriter, UnstructuredGridOrPolyDataByExtension) {
    const fs::path dir = tempDir();
    ASSERT_TRUE(writeParticles(dir / "f.vtu", sampleSet(3)).ok());
    ASSERT_TRUE(writeParticles(dir / "f.vtp", sampleSet(3)).ok());
    const std::string vtu = headerText(dir / "f.vtu", 4096), vtp = headerText(dir / "f.vtp", 4096);
    EXPECT_NE(vtu.find("type=\"UnstructuredGrid\""), std::string::npos);
    EXPECT_NE(vtu.find("NumberOfCells=\"3\""), std::string::npos);
    EXPECT_NE(vtu.find("Name=\"types\""), std::string::npos);
    EXPECT_NE(vtp.find("type=\"PolyData\""), std::string::npos);
    EXPECT_NE(vtp.find("NumberOfVerts=\"3\""), std::string::npos);
    EXPECT_NE(vtu.find("<AppendedData encoding=\"raw\">"), std::string::npos);
    EXPECT_NE(vtu.find("<PointData Scalars=\"density\" Vectors=\"velocity\">"), std::string::npos);
}

TEST(VtuWriter, XmlSpecialCharactersInNames) {
    ParticleSet set;
    set.positions = {{1, 2, 3}, {4, 5, 6}};
    set.attributes.push_back(floats("a<b>&\"c'", 1, {1.0f, 2.0f}));
    expectSameSet(set, writeAndRead(set, tempDir() / "x.vtu"), "xml names");
}

TEST(PlyWriter, HeaderNamesThePropertiesOurReaderMapsBack) {
    const fs::path path = tempDir() / "f.ply";
    ASSERT_TRUE(writeParticles(path, sampleSet(2)).ok());
    const std::string h = headerText(path, 4096);
    const std::string want =
        "ply\nformat binary_little_endian 1.0\ncomment particles written by meniscus\nelement vertex 2\n"
        "property float x\nproperty float y\nproperty float z\nproperty int id\nproperty float vx\n"
        "property float vy\nproperty float vz\nproperty float density\nproperty float temperature\n"
        "property float uv_0\nproperty float uv_1\nproperty int cell_0\nproperty int cell_1\nproperty int cell_2\n"
        "property float stress_0\n";
    EXPECT_EQ(h.substr(0, want.size()), want);
}

// ------------------------------------------------------------------ refusals

// `set` is refused for every format with `word` in an error naming the file,
// and nothing is written; a file already there is left as it was.
void expectRefused(const ParticleSet& set, const std::string& word, const std::vector<std::string>& exts = kExtensions) {
    const fs::path dir = tempDir();
    for (const std::string& ext : exts) {
        const fs::path path = dir / ("bad" + ext);
        const Status st = writeParticles(path, set);
        ASSERT_FALSE(st.ok()) << ext;
        EXPECT_EQ(st.error().file, path.string());
        EXPECT_NE(st.error().message.find(word), std::string::npos) << ext << ": " << st.error().describe();
        EXPECT_FALSE(fs::exists(path)) << ext;
    }
    EXPECT_TRUE(filesIn(dir).empty()) << "no partial or temporary file";
}

TEST(WriterRefuses, NonFinitePositions) {
    for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        ParticleSet set = sampleSet(10);
        set.positions[7].y = bad;
        expectRefused(set, "particle 7 has a non-finite position");
    }
}

TEST(WriterRefuses, AttributeWithTheWrongCount) {
    ParticleSet set = sampleSet(10);
    set.find("uv")->floats.pop_back();
    expectRefused(set, "attribute 'uv' has 19 values, but 10 particles of 2 components need 20");
    ParticleSet more = sampleSet(10);
    more.find(kAttrId)->ints.push_back(1);
    expectRefused(more, "attribute 'id' has 11 values");
    ParticleSet none = sampleSet(10);
    none.find("temperature")->components = 0;
    expectRefused(none, "has 0 components");
}

TEST(WriterRefuses, DuplicateOrEmptyNamesAndMistypedCanonicalAttributes) {
    ParticleSet dup = sampleSet(3);
    dup.attributes.push_back(dup.attributes[3]);
    expectRefused(dup, "two attributes are named 'temperature'");
    ParticleSet unnamed = sampleSet(3);
    unnamed.attributes[4].name.clear();
    expectRefused(unnamed, "attribute 5 has no name");
    ParticleSet floatId = sampleSet(3);
    floatId.attributes[0] = floats(std::string(kAttrId), 1, {1, 2, 3});
    expectRefused(floatId, "'id' must be Int x 1");
    ParticleSet flatVelocity = sampleSet(3);
    flatVelocity.attributes[1] = floats(std::string(kAttrVelocity), 1, {1, 2, 3});
    expectRefused(flatVelocity, "'velocity' must be Float x 3");
}

TEST(WriterRefuses, IntValuesBeyondInt32) {
    ParticleSet set = sampleSet(5);
    set.find(kAttrId)->ints[3] = std::int64_t(1) << 31;
    expectRefused(set, "attribute 'id' of particle 3 is 2147483648");
    ParticleSet low = sampleSet(5);
    low.find("cell")->ints[4] = std::int64_t(std::numeric_limits<std::int32_t>::min()) - 1;
    expectRefused(low, "attribute 'cell' of particle 1 is -2147483649");
}

TEST(WriterRefuses, NamesAFormatCannotHold) {
    ParticleSet spaced = sampleSet(2);
    spaced.attributes[3].name = "wet area";
    expectRefused(spaced, "PLY property names cannot hold spaces", {".ply"});
    ParticleSet clash = sampleSet(2);
    clash.attributes[3].name = "vx";
    expectRefused(clash, "would be written as PLY property 'vx'", {".ply"});
    ParticleSet p = sampleSet(2);
    p.attributes[3].name = "P";
    expectRefused(p, "clash with the position", {".bgeo", ".bgeo.gz"});
}

TEST(WriterRefuses, UnknownOrUnwritableFormats) {
    const ParticleSet set = sampleSet(2);
    expectRefused(set, "name the file .bgeo", {".txt", ".csv", ".xyz", ".dat", ""});
    expectRefused(set, "ASCII Houdini .geo is not written", {".geo"});
}

TEST(WriterRefuses, MissingFolderLeavesNothing) {
    const fs::path dir = tempDir();
    const fs::path path = dir / "no_such_folder" / "f.bgeo";
    const Status st = writeParticles(path, sampleSet(3));
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().file, path.string());
    EXPECT_NE(st.error().message.find("cannot open for writing"), std::string::npos) << st.error().describe();
    EXPECT_TRUE(filesIn(dir).empty());
}

TEST(WriterRefuses, AFailedWriteKeepsTheFileThatWasThere) {
    const fs::path path = tempDir() / "frame.vtu";
    ASSERT_TRUE(writeParticles(path, sampleSet(20)).ok());
    const auto before = readBytes(path);
    ParticleSet bad = sampleSet(20);
    bad.positions[0].x = std::numeric_limits<float>::quiet_NaN();
    EXPECT_FALSE(writeParticles(path, bad).ok());
    EXPECT_EQ(readBytes(path), before);
    EXPECT_EQ(filesIn(path.parent_path()), std::vector<std::string>{"frame.vtu"});
}

// ------------------------------------------------------------------ VTK's own readers

// FNV-1a over bytes, as scripts/check_particles_vtk.py computes it.
std::uint64_t fnv(const void* p, std::size_t n, std::uint64_t h = 0xcbf29ce484222325ull) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
    return h;
}

TEST(WriterParaView, VtksOwnReadersOpenEveryFile) {
    if (test::runCommand("/usr/bin/python3 -c 'import vtk' 2>/dev/null") != 0)
        GTEST_SKIP() << "python3-vtk9 not installed";
    const ParticleSet set = sampleSet(500);
    const fs::path dir = tempDir();
    std::string files;
    for (const char* ext : {".vtk", ".vtu", ".vtp", ".ply"}) {
        ASSERT_TRUE(writeParticles(dir / (std::string("f") + ext), set).ok());
        files += " " + (dir / (std::string("f") + ext)).string();
    }
    for (const char* ext : {".vtk", ".vtu", ".vtp", ".ply"}) {
        ASSERT_TRUE(writeParticles(dir / (std::string("empty") + ext), ParticleSet{}).ok());
        files += " " + (dir / (std::string("empty") + ext)).string();
    }
    std::string out;
    const fs::path script = fs::path(MENISCUS_TEST_DATA).parent_path().parent_path() / "scripts" /
                            "check_particles_vtk.py";
    const int rc = test::runCommand("/usr/bin/python3 " + script.string() + files, &out);
    ASSERT_EQ(rc, 0) << out;

    // What VTK read, hashed as stored: float32 / int32 little-endian; the
    // arrays in any order.
    std::vector<std::string> arrays;
    for (const Attribute& a : set.attributes) {
        std::vector<std::int32_t> narrow(a.ints.begin(), a.ints.end());
        const std::uint64_t h = a.type == AttributeType::Int ? fnv(narrow.data(), narrow.size() * 4)
                                                             : fnv(a.floats.data(), a.floats.size() * 4);
        std::ostringstream token;
        token << a.name << ":" << a.components << ":" << std::hex << h;
        arrays.push_back(token.str());
    }
    std::ostringstream pHash;
    pHash << std::hex << fnv(set.positions.data(), set.positions.size() * 12);
    auto lineOf = [&](const fs::path& file) {
        const std::size_t at = out.find(file.string() + " ");
        return at == std::string::npos ? std::string() : out.substr(at, out.find('\n', at) - at);
    };
    for (const char* ext : {".vtk", ".vtu", ".vtp"}) {
        const fs::path file = dir / (std::string("f") + ext);
        const std::string line = lineOf(file) + " ";
        EXPECT_EQ(line.rfind(file.string() + " points=500 cells=500 P=" + pHash.str() + " ", 0), 0u) << out;
        for (const std::string& a : arrays) EXPECT_NE(line.find(" " + a + " "), std::string::npos) << a << "\n" << line;
        EXPECT_EQ(std::count(line.begin(), line.end(), ':'), 2 * std::ptrdiff_t(arrays.size())) << line;
    }
    // VTK's PLY reader (ParaView's) reads the positions only (no custom
    // properties, and no cells for a file without faces).
    EXPECT_EQ(lineOf(dir / "f.ply"), (dir / "f.ply").string() + " points=500 cells=0 P=" + pHash.str()) << out;
    for (const char* ext : {".vtk", ".vtu", ".vtp", ".ply"}) {
        const fs::path empty = dir / (std::string("empty") + ext);
        EXPECT_EQ(lineOf(empty), empty.string() + " points=0 cells=0") << out;
    }
}

}  // namespace
}  // namespace meniscus::io_writers_test_local
