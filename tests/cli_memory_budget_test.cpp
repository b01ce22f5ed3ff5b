// The memory budget at the command line (include/meniscus/memory_budget.h):
// what a reliability run found growing until the kernel killed it is now
// refused at once, exit 1, with both figures and the option that lowers the
// need. Each runs under MENISCUS_MEMORY_LIMIT (the CLI's cap on the budget;
// prlimit and ulimit -v cannot be used under AddressSanitizer), mostly 8 GB,
// the container the run was made in; the inputs with huge point counts are
// written here, a megabyte or so each.
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <zlib.h>

#include "test_util.h"

namespace cli_memory_budget_test_local {

namespace fs = std::filesystem;
using namespace meniscus;
using namespace meniscus::test;

namespace {

bool has(const std::string& out, const std::string& what) { return out.find(what) != std::string::npos; }

constexpr const char* k8GB = "8000000000";

// The CLI under a budget of `limit` bytes; its exit code, and how long it ran.
int runUnder(const char* limit, const std::string& args, std::string* out, double* seconds = nullptr) {
    const auto t0 = std::chrono::steady_clock::now();
    const int rc = runCommand(std::string("MENISCUS_MEMORY_LIMIT=") + limit + " " + cliPath() + " " + args, out);
    if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return rc;
}

void putBE32(std::vector<std::uint8_t>& v, std::uint32_t x) {
    for (int s = 24; s >= 0; s -= 8) v.push_back(std::uint8_t(x >> s));
}
void putLE(std::vector<std::uint8_t>& v, std::uint64_t x, int bytes) {
    for (int k = 0; k < bytes; ++k) v.push_back(std::uint8_t(x >> (8 * k)));
}

// Raw deflate of `data`, ended by a full flush (byte-aligned, no history):
// such pieces concatenate into one valid deflate stream.
std::vector<std::uint8_t> deflatePiece(z_stream& zs, const std::vector<std::uint8_t>& data, int flush) {
    std::vector<std::uint8_t> out(deflateBound(&zs, uLong(data.size())) + 64);
    zs.next_in = const_cast<Bytef*>(data.data());
    zs.avail_in = uInt(data.size());
    zs.next_out = out.data();
    zs.avail_out = uInt(out.size());
    EXPECT_NE(deflate(&zs, flush), Z_STREAM_ERROR);
    out.resize(out.size() - zs.avail_out);
    return out;
}

// A gzip classic BGEO honestly holding 2^26 (67 million) points at the
// origin, P only: its 1 GiB of records are 1024 copies of one deflated MiB of
// zeros, so the file is about a megabyte and is written in a moment.
void writeHugeBgeoGz(const fs::path& path) {
    constexpr std::uint32_t kPoints = 1u << 26;
    std::vector<std::uint8_t> header = {'B', 'g', 'e', 'o', 'V'};
    for (std::uint32_t v : {5u, kPoints, 0u, 0u, 0u, 0u, 0u, 0u, 0u}) putBE32(header, v);
    const std::vector<std::uint8_t> zeros(1 << 20, 0), trailer = {0x00, 0xff};
    z_stream zs{};
    ASSERT_EQ(deflateInit2(&zs, 9, Z_DEFLATED, -15, 9, Z_DEFAULT_STRATEGY), Z_OK);
    std::vector<std::uint8_t> file = {0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3};
    const auto head = deflatePiece(zs, header, Z_FULL_FLUSH);
    const auto mib = deflatePiece(zs, zeros, Z_FULL_FLUSH);
    const auto tail = deflatePiece(zs, trailer, Z_FINISH);
    deflateEnd(&zs);
    file.insert(file.end(), head.begin(), head.end());
    uLong crc = crc32(0, header.data(), uInt(header.size()));
    const uLong crcMib = crc32(0, zeros.data(), uInt(zeros.size()));
    const std::uint64_t mibs = std::uint64_t(kPoints) * 16 / zeros.size();
    for (std::uint64_t k = 0; k < mibs; ++k) {
        file.insert(file.end(), mib.begin(), mib.end());
        crc = crc32_combine(crc, crcMib, z_off_t(zeros.size()));
    }
    file.insert(file.end(), tail.begin(), tail.end());
    crc = crc32_combine(crc, crc32(0, trailer.data(), uInt(trailer.size())), z_off_t(trailer.size()));
    putLE(file, crc, 4);
    putLE(file, header.size() + mibs * zeros.size() + trailer.size(), 4);  // ISIZE: mod 2^32
    writeBytes(path, file);
}

// A zlib-compressed .vtu whose Points hold 1365 blocks of 65536 points
// (89 million, 1 GB of float32): one deflated block of zeros, repeated.
void writeHugeVtu(const fs::path& path, std::uint64_t* points) {
    constexpr std::uint64_t kBlockPoints = 65536, kBlocks = 1365, kBlockBytes = 12 * kBlockPoints;
    const std::vector<std::uint8_t> zeros(kBlockBytes, 0);
    uLongf len = compressBound(uLong(zeros.size()));
    std::vector<std::uint8_t> block(len);
    ASSERT_EQ(compress2(block.data(), &len, zeros.data(), uLong(zeros.size()), 9), Z_OK);
    block.resize(len);
    std::vector<std::uint8_t> data;
    for (std::uint64_t v : {kBlocks, kBlockBytes, kBlockBytes}) putLE(data, v, 8);
    for (std::uint64_t k = 0; k < kBlocks; ++k) putLE(data, block.size(), 8);
    for (std::uint64_t k = 0; k < kBlocks; ++k) data.insert(data.end(), block.begin(), block.end());
    *points = kBlocks * kBlockPoints;
    std::string s = "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
                    "byte_order=\"LittleEndian\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n"
                    "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" +
                    std::to_string(*points) +
                    "\" NumberOfCells=\"0\">\n<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" "
                    "format=\"appended\" offset=\"0\"/>\n</Points>\n</Piece>\n</UnstructuredGrid>\n"
                    "<AppendedData encoding=\"raw\">\n_";
    s.append(data.begin(), data.end());
    s += "\n</AppendedData>\n</VTKFile>\n";
    writeText(path, s);
}

}  // namespace

// Frame 21 of the dam break (117,649 particles) meshed at --cube-size 0.05
// grew past 7.2 GB and was killed; the estimate (about 13 GB) refuses it.
TEST(CliMemoryBudget, MeshAtATinyCubeSizeIsRefused) {
    const fs::path dir = tempDir();
    const fs::path frame = repoData("dambreak_r0.01/ParticleData_Fluid_21.bgeo");
    std::string out;
    double seconds = 0;
    EXPECT_EQ(runUnder(k8GB,
                       "mesh " + shellQuote(frame) + " -o " + shellQuote(dir / "m.ply") + " --cube-size 0.05", &out,
                       &seconds),
              1)
        << out;
    EXPECT_TRUE(has(out, "ParticleData_Fluid_21.bgeo: meshing 117649 particles at a cube size of 0.05 radii")) << out;
    EXPECT_TRUE(has(out, "GB; this process may use 8.0 GB (MENISCUS_MEMORY_LIMIT)")) << out;
    EXPECT_TRUE(has(out, "raise --cube-size")) << out;
    EXPECT_LT(seconds, 30.0) << "refused only after " << seconds << " s";
    EXPECT_FALSE(fs::exists(dir / "m.ply"));
    // The default cube size fits the same budget (the small frame: quick).
    const fs::path small = dirWithFrame("budget_mesh");
    EXPECT_EQ(runUnder(k8GB, "mesh " + shellQuote(small / "f.bgeo") + " -o " + shellQuote(small / "m.ply"), &out), 0)
        << out;
    EXPECT_TRUE(fs::exists(small / "m.ply"));
}

// 150 bytes of scene: a 1 m cube of fluid at r = 1 mm (125 million
// particles, under the 2^28 cap) reached 7.4 GB before it was killed; an
// emitter of 9 million particles a layer, 5.4 GB.
TEST(CliMemoryBudget, SimulationsTooLargeAreRefusedBeforeMakingParticles) {
    const fs::path dir = tempDir();
    writeText(dir / "cube.json", R"({"version": 1, "params": {"radius": 0.001}, "domain": {"min": [0,0,0], "max": [1,1,1]},
 "fluid": [{"box": {"min": [0,0,0], "max": [1,1,1]}}]})");
    std::string out;
    double seconds = 0;
    EXPECT_EQ(runUnder(k8GB, "simulate " + shellQuote(dir / "cube.json") + " -o " + shellQuote(dir / "f_%04d.bgeo"),
                       &out, &seconds),
              1)
        << out;
    EXPECT_TRUE(has(out, "cube.json: simulating 1.2")) << out;  // 499^3 or so
    EXPECT_TRUE(has(out, "e+08 particles at radius 0.001 m needs about")) << out;
    EXPECT_TRUE(has(out, "this process may use 8.0 GB (MENISCUS_MEMORY_LIMIT)")) << out;
    EXPECT_TRUE(has(out, "use a larger radius")) << out;
    EXPECT_LT(seconds, 30.0);
    EXPECT_FALSE(fs::exists(dir / "f_0000.bgeo"));

    // rate x 2r / speed = 9e6 particles a layer.
    writeText(dir / "nozzle.json", R"({"version": 1, "params": {"radius": 0.001}, "domain": {"min": [0,0,0], "max": [1,1,1]},
 "emitters": [{"position": [0.5,0.9,0.5], "direction": [0,-1,0], "speed": 1, "rate": 4.5e9}]})");
    EXPECT_EQ(runUnder(k8GB, "simulate " + shellQuote(dir / "nozzle.json") + " -o " + shellQuote(dir / "n_%04d.bgeo"),
                       &out, &seconds),
              1)
        << out;
    EXPECT_TRUE(has(out, "nozzle.json: simulating")) << out;
    EXPECT_TRUE(has(out, "fewer emitted particles")) << out;
    EXPECT_LT(seconds, 30.0);

    // The small dam break runs under the same budget.
    const fs::path scene = writeSmallScene(dir);
    EXPECT_EQ(runUnder(k8GB, "simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "s_%04d.bgeo") +
                                 " --duration 0.02",
                       &out),
              0)
        << out;
    EXPECT_TRUE(fs::exists(dir / "s_0001.bgeo")) << out;
}

// A 1 MB gzip BGEO honestly holding 67 million points: the reader refuses
// its arrays under a budget they do not fit (once a streaming pass has shown
// the points are there: a count is never trusted before its bytes); with room
// for them, the renderer's own per-particle arrays are refused before the
// stages run. A zlib .vtu of 89 million points is refused before its blocks
// are inflated (their sizes in its header are checked against the data).
TEST(CliMemoryBudget, HugeCompressedParticleFilesAreRefused) {
    const fs::path dir = tempDir();
    writeHugeBgeoGz(dir / "huge.bgeo.gz");
    ASSERT_LT(fs::file_size(dir / "huge.bgeo.gz"), 2u << 20);
    std::string out;
    double seconds = 0;
    const std::string render = "render " + shellQuote(dir / "huge.bgeo.gz") + " -o " + shellQuote(dir / "o.png") +
                               " --width 64 --height 48 --backend cpu --radius 0.01";
    EXPECT_EQ(runUnder("500000000", render, &out, &seconds), 1) << out;
    EXPECT_TRUE(has(out, "huge.bgeo.gz: holding its 67108864 points (12 bytes each while reading) needs about 805 MB"))
        << out;
    EXPECT_TRUE(has(out, "this process may use 500 MB (MENISCUS_MEMORY_LIMIT)")) << out;
    EXPECT_LT(seconds, 30.0) << "refused only after " << seconds << " s";
    EXPECT_EQ(runUnder(k8GB, render, &out, &seconds), 1) << out;
    EXPECT_TRUE(has(out, "rendering 67108864 particles")) << out;
    EXPECT_TRUE(has(out, "this process may use 8.0 GB (MENISCUS_MEMORY_LIMIT)")) << out;
    EXPECT_FALSE(fs::exists(dir / "o.png"));

    std::uint64_t points = 0;
    writeHugeVtu(dir / "huge.vtu", &points);
    ASSERT_LT(fs::file_size(dir / "huge.vtu"), 2u << 20);
    EXPECT_EQ(runUnder("1000000000",
                       "render " + shellQuote(dir / "huge.vtu") + " -o " + shellQuote(dir / "v.png") +
                           " --width 64 --height 48 --backend cpu --radius 0.01",
                       &out, &seconds),
              1)
        << out;
    EXPECT_TRUE(has(out, "huge.vtu: holding its " + std::to_string(points) + " points")) << out;
    EXPECT_LT(seconds, 10.0) << "refused only after " << seconds << " s";
    EXPECT_FALSE(fs::exists(dir / "v.png"));
}

// Under an 8 GB cgroup a 12000 x 12000 frame passed the check (of physical
// memory) and died at 6.3 GB; the budget is the process's own now.
TEST(CliMemoryBudget, FramesAreCheckedAgainstTheProcessBudget) {
    const fs::path dir = dirWithFrame("budget_frame");
    std::string out;
    EXPECT_EQ(runUnder(k8GB,
                       "render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "o.png") +
                           " --width 12000 --height 12000 --backend cpu",
                       &out),
              1)
        << out;
    // 64 bytes a pixel for a PNG (frame_memory.cpp).
    EXPECT_TRUE(has(out, "a 12000x12000 frame needs about 9.2 GB; this process may use 8.0 GB (MENISCUS_MEMORY_LIMIT), "
                         "and this at most half of it; choose a smaller --width/--height"))
        << out;
    EXPECT_FALSE(fs::exists(dir / "o.png"));
    EXPECT_EQ(runUnder(k8GB,
                       "render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "o.png") +
                           " --width 320 --height 240 --backend cpu",
                       &out),
              0)
        << out;
    EXPECT_TRUE(fs::exists(dir / "o.png"));
    // A cap that is not a number of bytes is the command line's error.
    EXPECT_EQ(runUnder("8G", "info " + shellQuote(dir / "f.bgeo"), &out), 2) << out;
    EXPECT_TRUE(has(out, "MENISCUS_MEMORY_LIMIT=8G: a positive number of bytes is needed")) << out;
}
}  // namespace cli_memory_budget_test_local
