// BGEO reader (src/io/bgeo.cpp) and gzip inflation (src/io/gzip.cpp): real
// SPlisHSPlasH output checked against frame_stats.csv, hand-made files, and a
// malformed-input suite that must fail cleanly with the file name in the error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <sstream>

#include "meniscus/io.h"
#include "test_util.h"

namespace meniscus::io_bgeo_test_local {
namespace {

using test::expectMatchesStats;
using test::readBytes;
using test::repoData;
using test::testData;

// ------------------------------------------------------------------ helpers

void expectIdsArePermutation(const ParticleSet& set) {
    const Attribute* id = set.find(kAttrId);
    ASSERT_NE(id, nullptr);
    ASSERT_EQ(id->type, AttributeType::Int);
    ASSERT_EQ(id->components, 1);
    std::vector<std::int64_t> ids = id->ints;
    ASSERT_EQ(ids.size(), set.size());
    std::sort(ids.begin(), ids.end());
    for (std::size_t i = 0; i < ids.size(); ++i) ASSERT_EQ(ids[i], std::int64_t(i)) << "at sorted position " << i;
}

std::vector<std::uint8_t> inflated(const std::vector<std::uint8_t>& gz) {
    auto r = inflateGzip(gz, "test.gz");
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().describe());
    return r.ok() ? r.value() : std::vector<std::uint8_t>{};
}

std::vector<std::uint8_t> prefix(const std::vector<std::uint8_t>& v, std::size_t n) {
    return {v.begin(), v.begin() + std::ptrdiff_t(std::min(n, v.size()))};
}

// Expects failure with the file name and `word` in the message.
void expectFails(const std::vector<std::uint8_t>& bytes, const std::string& name, const std::string& word,
                 const std::string& context = "") {
    const auto r = parseBgeo(bytes, name);
    ASSERT_FALSE(r.ok()) << context << ": parsed " << r->size() << " particles";
    const std::string text = r.error().describe();
    EXPECT_NE(text.find(name), std::string::npos) << context << ": " << text;
    EXPECT_NE(text.find(word), std::string::npos) << context << ": expected '" << word << "' in: " << text;
}

// Big-endian BGEO writer for hand-made files.
struct BgeoWriter {
    std::vector<std::uint8_t> b;
    void u8(std::uint8_t v) { b.push_back(v); }
    void u16(std::uint16_t v) {
        u8(std::uint8_t(v >> 8));
        u8(std::uint8_t(v));
    }
    void i32(std::int32_t v) {
        const auto u = std::uint32_t(v);
        for (int s = 24; s >= 0; s -= 8) u8(std::uint8_t(u >> s));
    }
    void f32(float f) {
        std::uint32_t u;
        std::memcpy(&u, &f, 4);
        i32(std::int32_t(u));
    }
    void str(const std::string& s) {
        u16(std::uint16_t(s.size()));
        for (char c : s) u8(std::uint8_t(c));
    }
    void header(int nPoints, int nPointAttrib) {
        for (char c : std::string("BgeoV")) u8(std::uint8_t(c));
        i32(5);
        i32(nPoints);
        for (int i = 0; i < 3; ++i) i32(0);  // prims, point groups, prim groups
        i32(nPointAttrib);
        for (int i = 0; i < 3; ++i) i32(0);  // vertex, prim, detail attributes
    }
    void attr(const std::string& name, int size, int type) {
        str(name);
        u16(std::uint16_t(size));
        i32(type);
        for (int i = 0; i < size; ++i) i32(0);
    }
};

// Three points with id (int), v (vector -> velocity), density (float),
// temperature (float x2, an extra attribute) and flags (index with a string table).
std::vector<std::uint8_t> handMadeBgeo() {
    BgeoWriter w;
    w.header(3, 5);
    w.attr("id", 1, 1);
    w.attr("v", 3, 5);
    w.attr("density", 1, 0);
    w.attr("temperature", 2, 0);
    w.str("flags");
    w.u16(1);
    w.i32(4);
    w.i32(2);  // string table: "wet", "spray"
    w.str("wet");
    w.str("spray");
    for (int i = 0; i < 3; ++i) {
        w.f32(float(i) + 0.5f);
        w.f32(-float(i));
        w.f32(float(i) * 0.25f);
        w.f32(1.0f);
        w.i32(100 - i);
        w.f32(1.0f * float(i));
        w.f32(2.0f * float(i));
        w.f32(-3.0f);
        w.f32(1000.0f + float(i));
        w.f32(20.0f + float(i));
        w.f32(-1.0f);
        w.i32(i % 2);
    }
    w.u8(0x00);
    w.u8(0xff);
    return w.b;
}

// ------------------------------------------------------------------ real data

const int kSmallFrames[] = {1, 9, 21, 61};

TEST(BgeoRealData, SmallFramesMatchFrameStats) {
    for (int frame : kSmallFrames) {
        SCOPED_TRACE("frame " + std::to_string(frame));
        const std::string name = "ParticleData_Fluid_" + std::to_string(frame) + ".bgeo";
        const auto bytes = readBytes(testData("splishsplash/partio/" + name));
        const auto r = parseBgeo(bytes, name);
        ASSERT_TRUE(r.ok()) << r.error().describe();
        const ParticleSet& set = r.value();
        EXPECT_EQ(set.size(), 6859u);
        EXPECT_TRUE(set.warnings.empty());
        expectMatchesStats(set, test::frameStatsRow("dambreak_r0.025_small", frame));
        expectIdsArePermutation(set);

        // Small set order: id, density, velocity (all kept, header order).
        ASSERT_EQ(set.attributes.size(), 3u);
        EXPECT_EQ(set.attributes[0].name, "id");
        EXPECT_EQ(set.attributes[1].name, "density");
        EXPECT_EQ(set.attributes[2].name, "velocity");
        const Attribute* vel = set.find(kAttrVelocity);
        ASSERT_NE(vel, nullptr);
        EXPECT_EQ(vel->type, AttributeType::Float);
        EXPECT_EQ(vel->components, 3);
        EXPECT_EQ(vel->count(), set.size());
    }
}

TEST(BgeoRealData, LargeFrame21) {
    const std::string name = "dambreak_r0.01/ParticleData_Fluid_21.bgeo";
    const auto bytes = readBytes(repoData(name));
    const auto r = parseBgeo(bytes, name);
    ASSERT_TRUE(r.ok()) << r.error().describe();
    const ParticleSet& set = r.value();
    EXPECT_EQ(set.size(), 117649u);
    const auto row = test::frameStatsRow("dambreak_r0.01", 21);
    expectMatchesStats(set, row);
    expectIdsArePermutation(set);
    // Large set order: id, velocity, density.
    ASSERT_EQ(set.attributes.size(), 3u);
    EXPECT_EQ(set.attributes[1].name, "velocity");
    EXPECT_EQ(set.attributes[2].name, "density");
}

TEST(BgeoRealData, UncompressedGivesSameData) {
    const auto gz = readBytes(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
    const auto raw = inflated(gz);
    ASSERT_EQ(raw.size(), 247028u);  // 41 header + 61 attribute table + 6859 * 36 + 2 trailer
    const auto a = parseBgeo(gz, "a.bgeo");
    const auto b = parseBgeo(raw, "b.bgeo");
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_EQ(a->size(), b->size());
    EXPECT_EQ(0, std::memcmp(a->positions.data(), b->positions.data(), a->size() * sizeof(glm::vec3)));
    for (std::size_t i = 0; i < a->attributes.size(); ++i) {
        EXPECT_EQ(a->attributes[i].name, b->attributes[i].name);
        const auto& fa = a->attributes[i].floats;
        const auto& fb = b->attributes[i].floats;
        ASSERT_EQ(fa.size(), fb.size());
        if (!fa.empty()) {
            EXPECT_EQ(0, std::memcmp(fa.data(), fb.data(), fa.size() * sizeof(float)));
        }
        EXPECT_EQ(a->attributes[i].ints, b->attributes[i].ints);
    }
}

TEST(BgeoRealData, MissingTrailerIsAccepted) {
    const auto raw = inflated(readBytes(testData("splishsplash/partio/ParticleData_Fluid_1.bgeo")));
    ASSERT_GE(raw.size(), 2u);
    EXPECT_EQ(raw[raw.size() - 2], 0x00);
    EXPECT_EQ(raw[raw.size() - 1], 0xff);
    const auto r = parseBgeo(prefix(raw, raw.size() - 2), "no_trailer.bgeo");
    ASSERT_TRUE(r.ok()) << r.error().describe();
    EXPECT_EQ(r->size(), 6859u);
}

TEST(BgeoRealData, ThroughParseParticles) {
    const auto r = readParticles(testData("splishsplash/partio/ParticleData_Fluid_9.bgeo"));
    ASSERT_TRUE(r.ok()) << r.error().describe();
    EXPECT_EQ(r->size(), 6859u);
}

// ------------------------------------------------------------------ hand-made

void checkHandMade(const ParticleSet& set) {
    ASSERT_EQ(set.size(), 3u);
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(set.positions[i], glm::vec3(float(i) + 0.5f, -float(i), float(i) * 0.25f));
    }
    ASSERT_EQ(set.attributes.size(), 5u);
    const Attribute* id = set.find("id");
    ASSERT_NE(id, nullptr);
    EXPECT_EQ(id->type, AttributeType::Int);
    EXPECT_EQ(id->ints, (std::vector<std::int64_t>{100, 99, 98}));

    const Attribute* vel = set.find("velocity");
    ASSERT_NE(vel, nullptr);
    EXPECT_EQ(set.find("v"), nullptr);
    EXPECT_EQ(vel->type, AttributeType::Float);
    EXPECT_EQ(vel->components, 3);
    EXPECT_EQ(vel->floats, (std::vector<float>{0, 0, -3, 1, 2, -3, 2, 4, -3}));

    const Attribute* rho = set.find("density");
    ASSERT_NE(rho, nullptr);
    EXPECT_EQ(rho->floats, (std::vector<float>{1000, 1001, 1002}));

    const Attribute* temp = set.find("temperature");
    ASSERT_NE(temp, nullptr);
    EXPECT_EQ(temp->type, AttributeType::Float);
    EXPECT_EQ(temp->components, 2);
    EXPECT_EQ(temp->floats, (std::vector<float>{20, -1, 21, -1, 22, -1}));

    const Attribute* flags = set.find("flags");
    ASSERT_NE(flags, nullptr);
    EXPECT_EQ(flags->type, AttributeType::Int);
    EXPECT_EQ(flags->ints, (std::vector<std::int64_t>{0, 1, 0}));
}

TEST(BgeoHandMade, PlainFloatIntVectorIndexAndExtraAttributes) {
    const auto r = parseBgeo(handMadeBgeo(), "hand.bgeo");
    ASSERT_TRUE(r.ok()) << r.error().describe();
    checkHandMade(r.value());
}

TEST(BgeoHandMade, GzipCompressed) {
    const auto r = parseBgeo(test::gzipBytes(handMadeBgeo()), "hand.bgeo.gz");
    ASSERT_TRUE(r.ok()) << r.error().describe();
    checkHandMade(r.value());
}

TEST(BgeoHandMade, ZeroPoints) {
    BgeoWriter w;
    w.header(0, 1);
    w.attr("density", 1, 0);
    const auto r = parseBgeo(w.b, "empty.bgeo");
    ASSERT_TRUE(r.ok()) << r.error().describe();
    EXPECT_EQ(r->size(), 0u);
    // parseParticles rejects an empty set with a clear message.
    const auto p = parseParticles(w.b, "empty.bgeo");
    ASSERT_FALSE(p.ok());
    EXPECT_NE(p.error().describe().find("empty.bgeo"), std::string::npos);
}

TEST(BgeoHandMade, VNotRenamedWhenVelocityExists) {
    BgeoWriter w;
    w.header(1, 2);
    w.attr("velocity", 3, 5);
    w.attr("v", 3, 5);
    for (int i = 0; i < 4 + 6; ++i) w.f32(float(i));
    const auto r = parseBgeo(w.b, "both.bgeo");
    ASSERT_TRUE(r.ok()) << r.error().describe();
    ASSERT_NE(r->find("v"), nullptr);
    EXPECT_EQ(r->find("velocity")->floats, (std::vector<float>{4, 5, 6}));
}

// ------------------------------------------------------------------ malformed

class BgeoMalformed : public ::testing::Test {
protected:
    void SetUp() override {
        gz = readBytes(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
        raw = inflated(gz);
        ASSERT_EQ(raw.size(), 247028u);
    }
    // Fixed header: 'Bgeo', 'V', version and 8 counts; version at bytes 5..8,
    // nPoints 9..12, nPointAttrib 25..28. The attribute table (id, density,
    // velocity) starts at 41: nameLen 41..42, "id", size 45..46, type 47..50.
    static constexpr std::size_t kHeaderEnd = 41;
    static constexpr std::size_t kTableEnd = 41 + 61;
    std::vector<std::uint8_t> gz, raw;
};

TEST_F(BgeoMalformed, TruncatedDecompressed) {
    const std::size_t cuts[] = {0, 3, 10, kHeaderEnd - 1, kHeaderEnd, kTableEnd - 1, kTableEnd,
                                raw.size() / 2, raw.size() - 3};
    for (std::size_t cut : cuts) expectFails(prefix(raw, cut), "cut.bgeo", "truncated", "cut at " + std::to_string(cut));
}

TEST_F(BgeoMalformed, TruncatedPointDataMessage) {
    const auto r = parseBgeo(prefix(raw, kTableEnd + 36 * 100 + 5), "short.bgeo");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().file, "short.bgeo");
    EXPECT_EQ(r.error().message,
              "truncated point data: header says 6859 points of 36 bytes, file has room for only 100");
}

TEST_F(BgeoMalformed, TruncatedGzipStream) {
    const std::size_t cuts[] = {2, 3, 10, 20, gz.size() / 2, gz.size() - 8, gz.size() - 2, gz.size() - 1};
    for (std::size_t cut : cuts) expectFails(prefix(gz, cut), "cut.bgeo", "gzip stream is truncated", "gzip cut at " + std::to_string(cut));
}

TEST_F(BgeoMalformed, GzipGarbage) {
    std::vector<std::uint8_t> junk = {0x1f, 0x8b};
    for (int i = 0; i < 200; ++i) junk.push_back(std::uint8_t(i * 37 + 11));
    expectFails(junk, "junk.bgeo", "gzip");
    expectFails({0x1f, 0x8b}, "junk2.bgeo", "gzip");
}

TEST_F(BgeoMalformed, GzipCorruptedBody) {
    auto bad = gz;
    for (std::size_t i = gz.size() / 2; i < gz.size() / 2 + 64; ++i) bad[i] ^= 0x5a;
    expectFails(bad, "corrupt.bgeo", "gzip");
}

TEST_F(BgeoMalformed, WrongMagic) {
    auto bad = raw;
    bad[0] = 'X';
    expectFails(bad, "magic.bgeo", "magic");
    expectFails(test::toBytes("ply\nformat ascii 1.0\n"), "text.bgeo", "magic");
    std::vector<std::uint8_t> json = {0x7f, 'N', 'S', 'J', 0, 0, 0, 0};
    expectFails(json, "new.bgeo", "not supported");
}

TEST_F(BgeoMalformed, WrongVersion) {
    auto bad = raw;
    bad[8] = 6;  // version int32 at offset 5..8
    expectFails(bad, "v6.bgeo", "version 6");
}

TEST_F(BgeoMalformed, PointCountLargerThanData) {
    auto bad = raw;
    bad[10] = 0x01;  // nPoints 0x00001acb (6859) -> 0x00011acb = 72395
    expectFails(bad, "count.bgeo", "truncated point data: header says 72395 points");
    bad[9] = 0x7f;  // absurd
    expectFails(bad, "count.bgeo", "truncated point data");
}

TEST_F(BgeoMalformed, NegativeCounts) {
    auto bad = raw;
    bad[9] = 0xff;  // nPoints < 0
    expectFails(bad, "neg.bgeo", "point count");
    bad = raw;
    bad[25] = 0xff;  // nPointAttrib < 0
    expectFails(bad, "neg.bgeo", "attribute count");
}

TEST_F(BgeoMalformed, AttributeCountLargerThanTable) {
    auto bad = raw;
    bad[28] = 200;  // nPointAttrib = 200: the table runs into the point data
    const auto r = parseBgeo(bad, "attrs.bgeo");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().describe().find("attrs.bgeo"), std::string::npos);
}

TEST_F(BgeoMalformed, NameLengthBeyondData) {
    auto bad = prefix(raw, 200);
    bad[41] = 0xff;
    bad[42] = 0xff;
    expectFails(bad, "name.bgeo", "truncated attribute table");
}

TEST_F(BgeoMalformed, UnknownAndStringTypes) {
    auto bad = raw;
    bad[50] = 9;  // type of "id"
    expectFails(bad, "type.bgeo", "unknown Houdini type 9");
    bad[50] = 2;
    expectFails(bad, "type.bgeo", "string");
}

TEST_F(BgeoMalformed, IndexStringTableTruncated) {
    BgeoWriter w;
    w.header(1, 1);
    w.str("flags");
    w.u16(1);
    w.i32(4);
    w.i32(1000000);  // claims a million strings
    w.str("a");
    expectFails(w.b, "index.bgeo", "truncated");
}

TEST_F(BgeoMalformed, EveryPrefixFailsCleanly) {
    // Every cut inside the header and table, then a stride through the points.
    for (std::size_t cut = 0; cut < kTableEnd + 40; ++cut) {
        const auto r = parseBgeo(prefix(raw, cut), "p.bgeo");
        ASSERT_FALSE(r.ok()) << "cut " << cut;
        ASSERT_NE(r.error().describe().find("p.bgeo"), std::string::npos);
    }
    for (std::size_t cut = kTableEnd; cut < raw.size() - 2; cut += 997) ASSERT_FALSE(parseBgeo(prefix(raw, cut), "p.bgeo").ok());
    for (std::size_t cut = 0; cut < gz.size(); cut += 1009) ASSERT_FALSE(parseBgeo(prefix(gz, cut), "p.bgeo").ok());
}

TEST_F(BgeoMalformed, RandomByteFlipsNeverCrash) {
    std::mt19937 rng(12345);
    for (int trial = 0; trial < 300; ++trial) {
        auto bad = prefix(raw, 2000);
        const int flips = 1 + int(rng() % 4);
        for (int f = 0; f < flips; ++f) bad[rng() % 120] = std::uint8_t(rng());
        const auto r = parseBgeo(bad, "fuzz.bgeo");
        if (!r.ok()) {
            EXPECT_NE(r.error().describe().find("fuzz.bgeo"), std::string::npos);
        }
    }
    for (int trial = 0; trial < 100; ++trial) {
        auto bad = gz;
        bad[2 + rng() % (gz.size() - 2)] ^= std::uint8_t(1u << (rng() % 8));
        const auto r = parseBgeo(bad, "fuzz.bgeo");
        if (!r.ok()) {
            EXPECT_NE(r.error().describe().find("fuzz.bgeo"), std::string::npos);
        }
    }
}

// Regression: decompression bombs. A header's point count is
// refused before anything is inflated when deflate (at most 1032:1) cannot
// produce that many bytes from the file...
TEST(BgeoBomb, PointCountBeyondWhatTheCompressedBytesCanHold) {
    BgeoWriter w;
    w.header(2000000000, 0);  // 2e9 points of 16 bytes = 32 GB from a few bytes
    const auto r = parseBgeo(test::gzipBytes(w.b), "claims.bgeo");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().file, "claims.bgeo");
    EXPECT_NE(r.error().message.find("truncated point data: header says 2000000000 points"), std::string::npos)
        << r.error().message;
}

// ... and a stream that goes on inflating past what the header needs (points
// plus 16 MiB + one byte per point for groups and primitives) is refused
// after inflating no more than that, holding none of it.
TEST(BgeoBomb, InflatingFarPastTheHeadersNeedIsRefused) {
    BgeoWriter w;
    w.header(2, 0);
    for (int i = 0; i < 8; ++i) w.f32(1.0f);
    std::vector<std::uint8_t> bomb = w.b;
    bomb.resize(bomb.size() + (std::size_t(40) << 20), 0);  // 40 MiB of zeros after the points
    const auto gz = test::gzipBytes(bomb);
    ASSERT_LT(gz.size(), std::size_t(1) << 20);
    const auto r = parseBgeo(gz, "bomb.bgeo");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().file, "bomb.bgeo");
    EXPECT_NE(r.error().message.find("decompression bomb"), std::string::npos) << r.error().message;
    // The same points with an honest tail (the 00 ff trailer) read fine.
    w.u8(0x00);
    w.u8(0xff);
    const auto ok = parseBgeo(test::gzipBytes(w.b), "ok.bgeo");
    ASSERT_TRUE(ok.ok()) << ok.error().describe();
    EXPECT_EQ(ok->size(), 2u);
}

// A large honest file streams into its arrays: every point decoded, across chunks.
TEST(BgeoBomb, ManyPointsStreamAcrossChunks) {
    BgeoWriter w;
    const int n = 200000;  // 3.2 MB of records: several 1 MiB chunks
    w.header(n, 0);
    for (int i = 0; i < n; ++i) {
        w.f32(float(i));
        w.f32(0.5f);
        w.f32(-float(i));
        w.f32(1.0f);
    }
    const auto r = parseBgeo(test::gzipBytes(w.b), "many.bgeo");
    ASSERT_TRUE(r.ok()) << r.error().describe();
    ASSERT_EQ(r->size(), std::size_t(n));
    for (int i : {0, 65535, 65536, n - 1}) EXPECT_EQ(r->positions[std::size_t(i)], glm::vec3(float(i), 0.5f, -float(i)));
}

TEST(Gzip, RoundTripAndZlibHeader) {
    std::vector<std::uint8_t> data(100000);
    std::iota(data.begin(), data.end(), 0);
    const auto r = inflateGzip(test::gzipBytes(data), "x.gz");
    ASSERT_TRUE(r.ok()) << r.error().describe();
    EXPECT_EQ(r.value(), data);
    // Two concatenated members inflate to both payloads, as gunzip does.
    auto two = test::gzipBytes(data);
    const auto second = test::gzipBytes({1, 2, 3});
    two.insert(two.end(), second.begin(), second.end());
    const auto r2 = inflateGzip(two, "two.gz");
    ASSERT_TRUE(r2.ok()) << r2.error().describe();
    EXPECT_EQ(r2->size(), data.size() + 3);
    const auto empty = inflateGzip({}, "empty.gz");
    ASSERT_FALSE(empty.ok());
    EXPECT_NE(empty.error().describe().find("empty.gz"), std::string::npos);
    EXPECT_NE(empty.error().message.find("truncated"), std::string::npos);
}

}  // namespace
}  // namespace meniscus::io_bgeo_test_local
