// Hostile particle files and outputs on the command line:
//  - a particle file is checked from its first bytes (its magic, header or
//    first line) before the rest is read, and a file larger than a particle
//    file may be is refused unread: a huge file of zeros with any particle
//    extension is refused quickly, in little memory, naming the file (exit 1);
//  - an output that is a link to a device or a FIFO is refused (exit 2) and
//    the device or FIFO stays as it was (docs/usage.md#errors).
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include <sys/stat.h>

#include <gtest/gtest.h>

#include "test_util.h"

namespace cli_hostile_files_test_local {

namespace fs = std::filesystem;
using namespace meniscus;
using namespace meniscus::test;

namespace {

bool has(const std::string& out, const std::string& what) { return out.find(what) != std::string::npos; }

// The CLI with `args` in at most about 1 GB of address space: reading a
// file of several GB whole would fail here (bad_alloc, a crash), not refuse it.
// Under AddressSanitizer, which reserves terabytes of address space for its
// shadow memory at start (so no `ulimit -v` lets it run), the bound is its own:
// any single allocation over 1000 MB aborts the process.
#if defined(__SANITIZE_ADDRESS__)
#define MENISCUS_TEST_ASAN_BUILD 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MENISCUS_TEST_ASAN_BUILD 1
#endif
#endif
int runCliSmall(const std::string& args, std::string* out) {
#ifdef MENISCUS_TEST_ASAN_BUILD
    return runCommand("ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}max_allocation_size_mb=1000\" " + cliPath() + " " + args,
                      out);
#else
    return runCommand("ulimit -v 1000000; " + cliPath() + " " + args, out);
#endif
}

}  // namespace

// Regression: `meniscus render x.bgeo` on a 3 GB file of zeros read all of it
// into memory (13 s, 3.2 GB) to say "bad magic". Every particle extension is
// now refused from its first bytes.
TEST(CliHostileFiles, HugeFilesOfZerosAreRefusedFromTheirFirstBytes) {
    const fs::path dir = tempDir() / "hostile_zeros";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::pair<const char*, const char*> cases[] = {
        {"bgeo", "not a BGEO file (bad magic"},  {"bgeo.gz", "not a BGEO file (bad magic"},
        {"vtk", "bad magic: not a legacy VTK file"},{"vtu", "not a VTKFile"},
        {"vtp", "not a VTKFile"},                {"ply", "not a PLY file"},
        {"csv", "not a text file"},              {"xyz", "not a text file"},
        {"h5part", "not an HDF5 file"},          {"hdf5", "not an HDF5 file"},
        {"npz", "not a readable .npz (zip) archive"},              {"pvd", "not a ParaView collection"},
    };
    for (const auto& [ext, message] : cases) {
        const fs::path file = dir / (std::string("x.") + ext);
        { std::ofstream touch(file); }
        fs::resize_file(file, std::uintmax_t(3) << 30);  // sparse: 3 GiB of zeros, no disk
        std::string out;
        EXPECT_EQ(runCliSmall("info " + shellQuote(file), &out), 1) << ext << ": " << out;
        EXPECT_TRUE(has(out, file.string() + ": " + message)) << ext << ": " << out;
        EXPECT_FALSE(has(out, "memory")) << ext << ": " << out;
        fs::remove(file);
    }
}

// A file with the right magic but larger than any particle file may be
// (4 GiB, what a .bgeo.gz may inflate to) is refused from its size, unread.
TEST(CliHostileFiles, ParticleFileOverTheLimitIsRefusedUnread) {
    const fs::path dir = tempDir() / "hostile_over_limit";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path file = dir / "x.bgeo";
    writeText(file, "Bgeo");
    fs::resize_file(file, std::uintmax_t(5) << 30);  // sparse
    std::string out;
    EXPECT_EQ(runCliSmall("info " + shellQuote(file), &out), 1) << out;
    EXPECT_TRUE(has(out, file.string() + ": 5368709120 bytes, more than the limit of 4294967296 bytes")) << out;
    fs::remove(file);
}

// Regression: an output that was a symbolic link to a device was replaced by
// a regular file (as root, `-o` through a link to /dev/null replaced
// /dev/null). Refused now before anything is written, as the command line's
// mistake (exit 2); the device or FIFO stays.
TEST(CliHostileFiles, OutputLinkedToADeviceOrAFifoIsRefused) {
    const fs::path dir = dirWithFrame("hostile_output_link");
    ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
    fs::create_symlink(dir / "fifo", dir / "o.png");
    const std::string render = "render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "o.png") +
                               " --width 32 --height 24 --backend cpu";
    std::string out;
    // A FIFO first: where it is refused, so is a device, and /dev/null below
    // is never at risk on a build that does not refuse.
    ASSERT_EQ(runCli(render, &out), 2) << out;
    ASSERT_TRUE(has(out, (dir / "o.png").string() + ": is a link to a named pipe (FIFO), not a file; choose "
                                                    "another output"))
        << out;
    ASSERT_TRUE(fs::is_fifo(dir / "fifo"));
    ASSERT_TRUE(fs::is_symlink(fs::symlink_status(dir / "o.png")));
    fs::remove(dir / "o.png");
    ASSERT_TRUE(fs::is_character_file(fs::symlink_status("/dev/null")));
    fs::create_symlink("/dev/null", dir / "o.png");
    EXPECT_EQ(runCli(render, &out), 2) << out;
    EXPECT_TRUE(has(out, (dir / "o.png").string() + ": is a link to a device, not a file; choose another output"))
        << out;
    EXPECT_TRUE(fs::is_character_file(fs::symlink_status("/dev/null")));
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "o.png")));
    // A link to a regular file is written through: the link stays.
    fs::remove(dir / "o.png");
    fs::create_symlink("real.png", dir / "o.png");
    EXPECT_EQ(runCli(render, &out), 0) << out;
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "o.png")));
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(dir / "real.png")));
}

// A write the system refuses (a full disk; here the process's file-size limit,
// `ulimit -f`, which makes write() fail with EFBIG once SIGXFSZ is ignored,
// the same path as ENOSPC without needing a small disk) is an error in the
// system's words naming the output ("File too large", not libpng's bare
// "Write Error"), exit 1, and leaves neither the output nor a temporary
// behind: pictures (PNG, EXR), particle files and meshes.
TEST(CliHostileFiles, AFailedWriteSaysWhyAndLeavesNothing) {
    const fs::path dir = dirWithFrame("hostile_failed_write");
    const std::string in = shellQuote(dir / "f.bgeo");
    // 16 KiB: the particle file is read; none of these outputs fits.
    const std::pair<std::string, std::string> runs[] = {
        {"o.png", "render " + in + " -o " + shellQuote(dir / "o.png") + " --width 640 --height 480 --backend cpu"},
        {"o.exr", "render " + in + " -o " + shellQuote(dir / "o.exr") + " --width 640 --height 480 --backend cpu"},
        {"c.vtu", "convert " + in + " " + shellQuote(dir / "c.vtu")},
        {"m.obj", "mesh " + in + " -o " + shellQuote(dir / "m.obj")},
    };
    for (const auto& [name, args] : runs) {
        SCOPED_TRACE(name);
        std::string out;
        EXPECT_EQ(runCommand("trap '' XFSZ; ulimit -f 16; " + cliPath() + " " + args, &out), 1) << out;
        EXPECT_TRUE(has(out, (dir / name).string() + ": ")) << out;
        EXPECT_TRUE(has(out, "File too large")) << out;
        EXPECT_FALSE(has(out, "Write Error")) << out;
        EXPECT_FALSE(fs::exists(dir / name));
    }
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
}
}  // namespace cli_hostile_files_test_local
