// VTK XML (.vtu/.vtp) with VTK's LZ4 and LZMA compressors (src/io/vtu.cpp).
//
// Two sources: files VTK 9.1 itself wrote with SetCompressorTypeToLZ4 /
// SetCompressorTypeToLZMA (tests/data/vtk_compressed/, by
// scripts/make_vtk_compressed_fixtures.py), checked against the same particles
// of the uncompressed VTK fixture; and files made here, whose blocks are
// compressed with the real libraries (LZ4_compress_default,
// lzma_easy_buffer_encode) laid out as vtkXMLWriter lays them out, checked
// against the same data uncompressed and zlib-compressed. Corrupt, truncated
// and lying blocks must give an error naming the file, never a crash.
#include <bit>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <lz4.h>
#include <lzma.h>
#include <zlib.h>

#include "meniscus/io.h"
#include "test_util.h"

namespace meniscus::io_vtu_compressed_test_local {
namespace {

using test::readBytes;
using test::testData;
using test::failsNaming;
using test::toBytes;

enum class Comp { None, ZLib, LZ4, LZMA };

const char* compressorAttr(Comp c) {
    switch (c) {
        case Comp::ZLib: return "vtkZLibDataCompressor";
        case Comp::LZ4: return "vtkLZ4DataCompressor";
        case Comp::LZMA: return "vtkLZMADataCompressor";
        case Comp::None: break;
    }
    return "";
}

// One block as VTK's compressor writes it.
std::vector<std::uint8_t> compressBlock(Comp c, const std::uint8_t* p, std::size_t n) {
    std::vector<std::uint8_t> out;
    if (c == Comp::ZLib) {
        uLongf len = compressBound(uLong(n));
        out.resize(len);
        EXPECT_EQ(compress2(out.data(), &len, p, uLong(n), 6), Z_OK);
        out.resize(len);
    } else if (c == Comp::LZ4) {
        out.resize(std::size_t(LZ4_compressBound(int(n))));
        const int len = LZ4_compress_default(reinterpret_cast<const char*>(p), reinterpret_cast<char*>(out.data()),
                                             int(n), int(out.size()));
        EXPECT_GT(len, 0);
        out.resize(std::size_t(len));
    } else if (c == Comp::LZMA) {
        out.resize(lzma_stream_buffer_bound(n));
        std::size_t pos = 0;
        EXPECT_EQ(lzma_easy_buffer_encode(6, LZMA_CHECK_CRC64, nullptr, p, n, out.data(), &pos, out.size()), LZMA_OK);
        out.resize(pos);
    }
    return out;
}
std::vector<std::uint8_t> compressBlock(Comp c, const std::vector<std::uint8_t>& raw) {
    return compressBlock(c, raw.data(), raw.size());
}

template <class T>
void appendLE(std::vector<std::uint8_t>& out, T v) {
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    out.insert(out.end(), b, b + sizeof(T));
}

void appendWord(std::vector<std::uint8_t>& out, std::uint64_t v, bool h64) {
    if (h64)
        appendLE(out, v);
    else
        appendLE(out, std::uint32_t(v));
}

// One array in vtkXMLWriter's binary layout: [nbytes][data] uncompressed, else
// [nblocks][blocksize][lastblocksize][csize...][blocks...].
std::vector<std::uint8_t> encodeArray(Comp c, const std::vector<std::uint8_t>& raw, std::size_t blockSize, bool h64) {
    std::vector<std::uint8_t> out;
    if (c == Comp::None) {
        appendWord(out, raw.size(), h64);
        out.insert(out.end(), raw.begin(), raw.end());
        return out;
    }
    std::vector<std::vector<std::uint8_t>> blocks;
    for (std::size_t off = 0; off < raw.size(); off += blockSize)
        blocks.push_back(compressBlock(c, raw.data() + off, std::min(blockSize, raw.size() - off)));
    appendWord(out, blocks.size(), h64);
    appendWord(out, blockSize, h64);
    appendWord(out, raw.size() % blockSize, h64);
    for (const auto& b : blocks) appendWord(out, b.size(), h64);
    for (const auto& b : blocks) out.insert(out.end(), b.begin(), b.end());
    return out;
}

struct Arrays {
    std::size_t n = 0;
    std::vector<float> positions, density, velocity;
    std::vector<std::int32_t> ids;
};

Arrays sampleArrays(std::size_t n) {
    Arrays a;
    a.n = n;
    for (std::size_t i = 0; i < n; ++i) {
        const float x = float(i % 20) * 0.05f, y = float(i / 400) * 0.05f, z = float(i / 20 % 20) * 0.05f;
        a.positions.insert(a.positions.end(), {x + 1e-4f * float(i % 7), y, z - 3e-5f * float(i % 11)});
        a.velocity.insert(a.velocity.end(), {0.0f, -0.5f * float(i % 13), 0.25f});
        a.density.push_back(1000.0f + float(i % 17) * 0.125f);
        a.ids.push_back(std::int32_t(i * 3 + 1));
    }
    return a;
}

template <class T>
std::vector<std::uint8_t> bytesOf(const std::vector<T>& v) {
    std::vector<std::uint8_t> out(v.size() * sizeof(T));
    if (!out.empty()) std::memcpy(out.data(), v.data(), out.size());
    return out;
}

// A .vtu with raw appended data, as vtkXMLUnstructuredGridWriter writes it.
std::string makeVtu(const Arrays& a, Comp c, std::size_t blockSize, bool h64) {
    const std::vector<std::vector<std::uint8_t>> arrays = {
        encodeArray(c, bytesOf(a.ids), blockSize, h64), encodeArray(c, bytesOf(a.density), blockSize, h64),
        encodeArray(c, bytesOf(a.velocity), blockSize, h64), encodeArray(c, bytesOf(a.positions), blockSize, h64)};
    std::size_t offs[4], off = 0;
    for (int k = 0; k < 4; ++k) offs[k] = off, off += arrays[std::size_t(k)].size();
    std::string s = "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
                    "byte_order=\"LittleEndian\" header_type=\"" +
                    std::string(h64 ? "UInt64" : "UInt32") + "\"";
    if (c != Comp::None) s += std::string(" compressor=\"") + compressorAttr(c) + "\"";
    s += ">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"" + std::to_string(a.n) + "\" NumberOfCells=\"0\">\n" +
         "<PointData>\n<DataArray type=\"Int32\" Name=\"id\" format=\"appended\" offset=\"" + std::to_string(offs[0]) +
         "\"/>\n<DataArray type=\"Float32\" Name=\"density\" format=\"appended\" offset=\"" +
         std::to_string(offs[1]) +
         "\"/>\n<DataArray type=\"Float32\" Name=\"velocity\" NumberOfComponents=\"3\" format=\"appended\" offset=\"" +
         std::to_string(offs[2]) + "\"/>\n</PointData>\n<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" "
                                   "format=\"appended\" offset=\"" +
         std::to_string(offs[3]) + "\"/>\n</Points>\n</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_";
    for (const auto& arr : arrays) s.append(arr.begin(), arr.end());
    s += "\n</AppendedData>\n</VTKFile>\n";
    return s;
}

Result<ParticleSet> parseText(const std::string& text, const std::string& name) {
    const auto bytes = toBytes(text);
    return parseVtu(bytes, name);
}

std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v); }

// Same particles, same attributes, bit for bit.
void expectSameSets(const ParticleSet& a, const ParticleSet& b, const std::string& what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    std::size_t bad = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        for (int c = 0; c < 3; ++c) bad += bits(a.positions[i][c]) != bits(b.positions[i][c]);
    EXPECT_EQ(bad, 0u) << what << ": positions differ";
    ASSERT_EQ(a.attributes.size(), b.attributes.size()) << what;
    for (const Attribute& x : a.attributes) {
        const Attribute* y = b.find(x.name);
        ASSERT_TRUE(y) << what << ": no " << x.name;
        EXPECT_EQ(x.type, y->type) << what << " " << x.name;
        EXPECT_EQ(x.components, y->components) << what << " " << x.name;
        EXPECT_EQ(x.ints, y->ints) << what << " " << x.name;
        ASSERT_EQ(x.floats.size(), y->floats.size()) << what << " " << x.name;
        std::size_t diff = 0;
        for (std::size_t k = 0; k < x.floats.size(); ++k) diff += bits(x.floats[k]) != bits(y->floats[k]);
        EXPECT_EQ(diff, 0u) << what << " " << x.name;
    }
}

std::string fixtureText(const std::string& file) {
    const auto b = readBytes(testData("vtk_compressed/" + file));
    return std::string(b.begin(), b.end());
}

std::size_t appendedStart(const std::string& s) {
    const auto tag = s.find("<AppendedData");
    return s.find('_', tag) + 1;
}

// ---------------------------------------------------------------- made here with the real libraries

TEST(VtuCompressed, HandMadeLz4AndLzmaReadAsUncompressedAndZlib) {
    const Arrays a = sampleArrays(2000);
    for (bool h64 : {false, true}) {
        const auto plain = parseText(makeVtu(a, Comp::None, 4096, h64), "plain.vtu");
        ASSERT_TRUE(plain.ok()) << plain.error().describe();
        ASSERT_EQ(plain->size(), a.n);
        EXPECT_EQ(bits(plain->positions[1999].x), bits(a.positions[3 * 1999]));
        const Attribute* id = plain->find(kAttrId);
        ASSERT_TRUE(id);
        EXPECT_EQ(id->ints[1999], 3 * 1999 + 1);
        ASSERT_TRUE(plain->find(kAttrVelocity) && plain->find(kAttrDensity));
        for (Comp c : {Comp::ZLib, Comp::LZ4, Comp::LZMA})
            for (std::size_t bs : {std::size_t(4096), std::size_t(1000), std::size_t(1) << 16}) {
                const std::string what = std::string(compressorAttr(c)) + " blocks " + std::to_string(bs) +
                                         (h64 ? " UInt64" : " UInt32");
                const std::string text = makeVtu(a, c, bs, h64);
                EXPECT_LT(text.size(), makeVtu(a, Comp::None, bs, h64).size()) << what;
                const auto r = parseText(text, "c.vtu");
                ASSERT_TRUE(r.ok()) << what << ": " << r.error().describe();
                expectSameSets(*plain, *r, what);
            }
    }
}

// ---------------------------------------------------------------- written by VTK itself

class VtkCompressedFixture : public ::testing::TestWithParam<const char*> {};

TEST_P(VtkCompressedFixture, MatchesTheUncompressedVtkFile) {
    const std::string file = GetParam();
    // The reference: VTK's uncompressed writing of the whole frame, first 500 particles.
    const auto refBytes = readBytes(testData("vtu/fluid21_binary.vtu"));
    auto ref = parseVtu(refBytes, "fluid21_binary.vtu");
    ASSERT_TRUE(ref.ok()) << ref.error().describe();
    ref->positions.resize(500);
    for (Attribute& x : ref->attributes) {
        x.floats.resize(std::min(x.floats.size(), std::size_t(500 * x.components)));
        x.ints.resize(std::min(x.ints.size(), std::size_t(500 * x.components)));
    }
    const std::string text = fixtureText(file);
    const std::string lz4 = "compressor=\"vtkLZ4DataCompressor\"", lzma = "compressor=\"vtkLZMADataCompressor\"";
    ASSERT_NE(text.find(file.find("lz4") != std::string::npos ? lz4 : lzma), std::string::npos) << file;
    const auto r = parseText(text, file);
    ASSERT_TRUE(r.ok()) << r.error().describe();
    EXPECT_TRUE(r->warnings.empty());
    expectSameSets(*ref, *r, file);
}

INSTANTIATE_TEST_SUITE_P(
    Vtk91, VtkCompressedFixture,
    ::testing::Values("fluid21_first500_lz4_appended_raw.vtu", "fluid21_first500_lz4_binary.vtu",
                      "fluid21_first500_lz4_appended_base64_uint64.vtu", "fluid21_first500_lz4_polydata.vtp",
                      "fluid21_first500_lzma_appended_raw.vtu", "fluid21_first500_lzma_binary.vtu",
                      "fluid21_first500_lzma_appended_base64_uint64.vtu", "fluid21_first500_lzma_polydata.vtp"),
    [](const auto& info) {
        std::string s = info.param;
        for (char& c : s)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
        return s;
    });

TEST(VtuCompressed, ReadParticlesTakesTheVtkFiles) {
    for (const char* f : {"fluid21_first500_lz4_appended_raw.vtu", "fluid21_first500_lzma_binary.vtu"}) {
        const auto r = readParticles(testData(std::string("vtk_compressed/") + f));
        ASSERT_TRUE(r.ok()) << r.error().describe();
        EXPECT_EQ(r->size(), 500u);
    }
}

// ---------------------------------------------------------------- malformed

const char* kFixtures[] = {"fluid21_first500_lz4_appended_raw.vtu", "fluid21_first500_lzma_appended_raw.vtu"};

std::string blockWord(const std::string& file) { return file.find("lzma") != std::string::npos ? "LZMA block" : "LZ4 block"; }

TEST(VtuCompressedMalformed, CorruptFirstBlock) {
    for (const char* file : kFixtures) {
        std::string s = fixtureText(file);
        const std::size_t start = appendedStart(s);
        std::uint32_t nblocks = 0;
        std::memcpy(&nblocks, s.data() + start, 4);
        ASSERT_GT(nblocks, 0u);
        const std::size_t blockStart = start + 4 * (3 + nblocks);
        // LZ4 has no checksum: garbage must be caught by its structure (0xff
        // tokens claim literal runs beyond the block); LZMA by its CRC too.
        for (std::size_t k = 0; k < 24; ++k) s[blockStart + k] = char(0xff);
        EXPECT_TRUE(failsNaming(parseText(s, file), file, {blockWord(file).c_str()})) << file;
        std::string t = fixtureText(file);
        for (std::size_t k = 20; k < 40; ++k) t[blockStart + k] = char(t[blockStart + k] ^ 0x5a);
        if (std::string(file).find("lzma") != std::string::npos) {
            EXPECT_TRUE(failsNaming(parseText(t, file), file, {"LZMA block"})) << file;
        } else {
            (void)parseText(t, file);  // may decode to other values: no crash is all LZ4 can promise
        }
    }
}

TEST(VtuCompressedMalformed, BlockCutShort) {
    for (const char* file : kFixtures) {
        std::string s = fixtureText(file);
        const std::size_t start = appendedStart(s);
        std::uint32_t csize = 0;
        std::memcpy(&csize, s.data() + start + 12, 4);
        for (std::uint32_t cut : {1u, 5u, csize / 2, csize - 1}) {
            std::string t = s;
            const std::uint32_t shorter = csize - cut;
            std::memcpy(t.data() + start + 12, &shorter, 4);
            EXPECT_TRUE(failsNaming(parseText(t, file), file, {blockWord(file).c_str()})) << file << " cut " << cut;
        }
    }
}

TEST(VtuCompressedMalformed, EveryFixtureTruncatedFails) {
    for (const char* file :
         {"fluid21_first500_lz4_appended_raw.vtu", "fluid21_first500_lz4_binary.vtu",
          "fluid21_first500_lz4_appended_base64_uint64.vtu", "fluid21_first500_lzma_appended_raw.vtu",
          "fluid21_first500_lzma_binary.vtu", "fluid21_first500_lzma_appended_base64_uint64.vtu"}) {
        const std::string s = fixtureText(file);
        for (double frac : {0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.999}) {
            const std::string t = s.substr(0, std::size_t(double(s.size()) * frac));
            EXPECT_TRUE(failsNaming(parseText(t, file), file, {"truncated", "XML", "missing", "mismatch"}))
                << file << " cut at " << frac;
        }
        // Cut inside the appended data, the closing tags put back. (Cells are
        // not read, and VTK writes them after the points: the cuts are before.)
        if (s.find("<AppendedData") == std::string::npos) continue;
        const std::size_t start = appendedStart(s);
        for (std::size_t cut : {start + 2, start + 20, start + 200, start + (s.size() - start) / 2}) {
            const std::string t = s.substr(0, cut) + "\n  </AppendedData>\n</VTKFile>\n";
            EXPECT_TRUE(failsNaming(parseText(t, file), file, {"truncated", "block", "beyond"}))
                << file << " cut at " << cut;
        }
    }
}

// Points as one inline (base64) array whose header says `claimed` bytes in one
// block holding `block`.
std::string singleBlockFile(Comp c, const std::vector<std::uint8_t>& block, std::uint64_t claimed,
                            std::uint64_t npoints) {
    std::vector<std::uint8_t> bin;
    appendLE(bin, std::uint32_t(1));
    appendLE(bin, std::uint32_t(claimed));
    appendLE(bin, std::uint32_t(0));
    appendLE(bin, std::uint32_t(block.size()));
    bin.insert(bin.end(), block.begin(), block.end());
    static const char* al = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string b64;
    for (std::size_t i = 0; i < bin.size(); i += 3) {
        const std::uint32_t v = std::uint32_t(bin[i]) << 16 |
                                (i + 1 < bin.size() ? std::uint32_t(bin[i + 1]) << 8 : 0) |
                                (i + 2 < bin.size() ? bin[i + 2] : 0);
        b64 += al[v >> 18 & 63];
        b64 += al[v >> 12 & 63];
        b64 += i + 1 < bin.size() ? al[v >> 6 & 63] : '=';
        b64 += i + 2 < bin.size() ? al[v & 63] : '=';
    }
    return std::string("<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\" compressor=\"") +
           compressorAttr(c) + "\"><PolyData><Piece NumberOfPoints=\"" + std::to_string(npoints) +
           "\"><Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"binary\">" + b64 +
           "</DataArray></Points></Piece></PolyData></VTKFile>";
}

TEST(VtuCompressedMalformed, BlocksDecodingToOtherSizes) {
    std::vector<std::uint8_t> raw240(240), raw60(60);
    for (std::size_t i = 0; i < raw240.size(); ++i) raw240[i] = std::uint8_t(i * 7);
    for (std::size_t i = 0; i < raw60.size(); ++i) raw60[i] = std::uint8_t(i * 5);
    for (Comp c : {Comp::LZ4, Comp::LZMA}) {
        const std::string name = c == Comp::LZ4 ? "lz4.vtp" : "lzma.vtp";
        const char* word = c == Comp::LZ4 ? "LZ4 block" : "LZMA block";
        // 10 points = 120 bytes claimed; the block holds 240 or 60.
        EXPECT_TRUE(failsNaming(parseText(singleBlockFile(c, compressBlock(c, raw240), 120, 10), name), name, {word}));
        EXPECT_TRUE(failsNaming(parseText(singleBlockFile(c, compressBlock(c, raw60), 120, 10), name), name, {word}));
        // Valid: exactly 120 bytes.
        std::vector<std::uint8_t> raw120(raw240.begin(), raw240.begin() + 120);
        const auto ok = parseText(singleBlockFile(c, compressBlock(c, raw120), 120, 10), name);
        ASSERT_TRUE(ok.ok()) << ok.error().describe();
        EXPECT_EQ(ok->size(), 10u);
        // Not a stream of this compressor at all.
        EXPECT_TRUE(failsNaming(parseText(singleBlockFile(c, compressBlock(Comp::ZLib, raw120), 120, 10), name), name,
                              {word}));
    }
    // Bytes after the end of the .xz stream.
    std::vector<std::uint8_t> raw120(raw240.begin(), raw240.begin() + 120);
    auto xz = compressBlock(Comp::LZMA, raw120);
    xz.insert(xz.end(), {1, 2, 3});
    EXPECT_TRUE(failsNaming(parseText(singleBlockFile(Comp::LZMA, xz, 120, 10), "tail.vtp"), "tail.vtp",
                          {"after the end"}));
}

// A header claiming far more than its compressed bytes can hold is refused
// before anything that size is allocated.
TEST(VtuCompressedMalformed, ImpossibleRatioRefusedBeforeAllocating) {
    const std::vector<std::uint8_t> junk(100, 0x11);
    const std::uint64_t claimed = 1200000000;  // 100 000 000 points
    for (Comp c : {Comp::LZ4, Comp::LZMA}) {
        const std::string name = c == Comp::LZ4 ? "bomb_lz4.vtp" : "bomb_lzma.vtp";
        EXPECT_TRUE(failsNaming(parseText(singleBlockFile(c, junk, claimed, claimed / 12), name), name,
                              {"cannot hold"}));
    }
    // Within LZMA's bound but not what the stream holds: fails without
    // allocating the claimed size (the output grows only as data decodes).
    std::vector<std::uint8_t> zeros(1 << 20, 0);
    const auto xz = compressBlock(Comp::LZMA, zeros);
    const std::uint64_t big = std::uint64_t(xz.size()) * 60000 / 12 * 12;
    EXPECT_TRUE(failsNaming(parseText(singleBlockFile(Comp::LZMA, xz, big, big / 12), "big.vtp"), "big.vtp",
                          {"decodes to"}));
}

TEST(VtuCompressedMalformed, UnknownCompressorNamed) {
    std::string s = fixtureText("fluid21_first500_lz4_binary.vtu");
    s.replace(s.find("vtkLZ4DataCompressor"), 20, "vtkZstdDataCompressor");
    EXPECT_TRUE(failsNaming(parseText(s, "zstd.vtu"), "zstd.vtu", {"unsupported compressor"}));
}

// Random corruption of these files: VtuMalformed.RandomCorruptionNeverCrashes (io_vtu_test.cpp).

}  // namespace
}  // namespace meniscus::io_vtu_compressed_test_local
