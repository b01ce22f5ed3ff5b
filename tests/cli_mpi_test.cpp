// Sort-last and frame-parallel rendering under mpirun, with OpenMPI as on the
// CI machine (--oversubscribe: more processes than cores; --allow-run-as-root:
// CI runs as root). Every picture is compared byte for byte with the plain
// one-process run of the same command: PNG and EXR (every AOV) of a real
// SPlisHSPlasH frame split over 1 to 4 processes, a process with no particles,
// part files (%r) fewer than the processes, frames split over processes; a
// process that cannot read its part ends the job with that error and no image.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "test_util.h"

namespace cli_mpi_test_local {

namespace fs = std::filesystem;
using namespace meniscus;
using namespace meniscus::test;

namespace {

int runMpi(int processes, const std::string& args, std::string* out) {
    return runCommand(std::string(MENISCUS_MPIEXEC) + " --oversubscribe --allow-run-as-root -n " +
                          std::to_string(processes) + " " + cliPath() + " " + args,
                      out);
}

fs::path freshDir(const std::string& name) {
    const fs::path dir = tempDir() / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

const fs::path kFrame = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");

std::string render(const fs::path& in, const fs::path& out, const std::string& more = "") {
    return "render " + shellQuote(in) + " -o " + shellQuote(out) + " --width 120 --height 90 --backend cpu " + more;
}

std::vector<std::string> names(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

// The frame written as `parts` part files part_r0.bgeo, ... of contiguous index ranges.
void writeParts(const fs::path& dir, int parts) {
    auto set = readParticles(kFrame);
    ASSERT_TRUE(set) << set.error().describe();
    const std::size_t n = set->size();
    for (int p = 0; p < parts; ++p) {
        ParticleSet part;
        const std::size_t b = n * std::size_t(p) / std::size_t(parts), e = n * std::size_t(p + 1) / std::size_t(parts);
        part.positions.assign(set->positions.begin() + std::ptrdiff_t(b), set->positions.begin() + std::ptrdiff_t(e));
        for (const Attribute& a : set->attributes) {
            Attribute c = a;
            const std::size_t k = std::size_t(a.components);
            if (a.type == AttributeType::Float) c.floats.assign(a.floats.begin() + std::ptrdiff_t(b * k), a.floats.begin() + std::ptrdiff_t(e * k));
            else c.ints.assign(a.ints.begin() + std::ptrdiff_t(b * k), a.ints.begin() + std::ptrdiff_t(e * k));
            part.attributes.push_back(std::move(c));
        }
        ASSERT_TRUE(writeParticles(dir / ("part_r" + std::to_string(p) + ".bgeo"), part));
    }
}

// `in` rendered with `more` to `name` (in `dir`) by one process without
// mpirun and by `processes` under it: the same bytes.
void expectSameAsOneProcess(const fs::path& dir, const fs::path& in, int processes, const std::string& more,
                            const std::string& name) {
    std::string out;
    ASSERT_EQ(runCli(render(in, dir / ("one_" + name), more), &out), 0) << out;
    ASSERT_EQ(runMpi(processes, render(in, dir / ("mpi_" + name), more), &out), 0) << out;
    EXPECT_EQ(readBytes(dir / ("mpi_" + name)), readBytes(dir / ("one_" + name))) << processes << " processes";
}

}  // namespace

TEST(CliMpi, SortLastPngAndExrAreTheOneProcessRunsForOneToFourProcesses) {
    const fs::path dir = freshDir("mpi_sort_last");
    std::string out;
    ASSERT_EQ(runCli(render(kFrame, dir / "one.png"), &out), 0) << out;
    ASSERT_EQ(runCli(render(kFrame, dir / "one.exr"), &out), 0) << out;
    for (int k = 1; k <= 4; ++k) {
        const std::string tag = std::to_string(k);
        ASSERT_EQ(runMpi(k, render(kFrame, dir / ("k" + tag + ".png")), &out), 0) << out;
        ASSERT_EQ(runMpi(k, render(kFrame, dir / ("k" + tag + ".exr")), &out), 0) << out;
        if (k > 1) {
            EXPECT_NE(out.find(tag + " processes, split by particles"), std::string::npos) << out;
        }
        EXPECT_EQ(readBytes(dir / ("k" + tag + ".png")), readBytes(dir / "one.png")) << "K = " << k;
        EXPECT_EQ(readBytes(dir / ("k" + tag + ".exr")), readBytes(dir / "one.exr")) << "K = " << k;
    }
}

TEST(CliMpi, SortLastWithReducedResolutionSpheresAndAnotherFilter) {
    expectSameAsOneProcess(freshDir("mpi_sort_last_options"), kFrame, 3,
                           "--fluid-scale 0.5 --filter curvature-flow --silhouette --anisotropy off", "f.exr");
}

TEST(CliMpi, AProcessWithNoParticles) {
    // Two particles over three processes: the first has none.
    const fs::path dir = freshDir("mpi_empty_rank");
    writeText(dir / "two.xyz", "0 0 0\n0.012 0.004 0\n");
    expectSameAsOneProcess(dir, dir / "two.xyz", 3, "--radius 0.01", "f.png");
}

TEST(CliMpi, PartFilesOnePerRankGiveTheWholeFramesPicture) {
    const fs::path dir = freshDir("mpi_parts");
    writeParts(dir, 3);
    std::string out;
    // The whole frame in one file, framed the same way: --eye/--target keep
    // the camera off the sampling (which samples each part on its own).
    // Spheres: a process holds only its parts, not every particle's neighbours.
    const std::string cam = "--eye 0.9,0.7,1.4 --target 0.2,0.2,0.3 --radius 0.01 --anisotropy off";
    ASSERT_EQ(runCli(render(kFrame, dir / "whole.exr", cam), &out), 0) << out;
    // The parts on one process (no mpirun), and on 2 (uneven: 2 + 1 parts), 3 and 4 (one with none).
    ASSERT_EQ(runCli(render(dir / "part_r%r.bgeo", dir / "one.exr", cam), &out), 0) << out;
    EXPECT_NE(out.find("3 parts of"), std::string::npos) << out;
    EXPECT_EQ(readBytes(dir / "one.exr"), readBytes(dir / "whole.exr"));
    for (int k = 2; k <= 4; ++k) {
        const std::string name = "k" + std::to_string(k) + ".exr";
        ASSERT_EQ(runMpi(k, render(dir / "part_r%r.bgeo", dir / name, cam), &out), 0) << out;
        EXPECT_EQ(readBytes(dir / name), readBytes(dir / "one.exr")) << "K = " << k;
    }
    // The automatic camera (samples of every part) is the same for any K too.
    ASSERT_EQ(runCli(render(dir / "part_r%r.bgeo", dir / "auto1.png", "--anisotropy off"), &out), 0) << out;
    ASSERT_EQ(runMpi(2, render(dir / "part_r%r.bgeo", dir / "auto2.png", "--anisotropy off"), &out), 0) << out;
    EXPECT_EQ(readBytes(dir / "auto2.png"), readBytes(dir / "auto1.png"));
    // The anisotropic kernels (on by default) need every neighbour: refused with part files.
    EXPECT_NE(runCli(render(dir / "part_r%r.bgeo", dir / "aniso.png"), &out), 0) << out;
    EXPECT_NE(out.find("--anisotropy off"), std::string::npos) << out;
}

TEST(CliMpi, FramesSplitOverProcessesAreTheSerialRunsFrames) {
    const fs::path dir = freshDir("mpi_frames");
    fs::create_directories(dir / "in");
    fs::create_directories(dir / "serial");
    fs::create_directories(dir / "mpi");
    fs::create_directories(dir / "mpi_particles");
    for (const char* n : {"1", "9", "21", "61"})
        fs::copy_file(testData(std::string("splishsplash/partio/ParticleData_Fluid_") + n + ".bgeo"),
                      dir / "in" / (std::string("ParticleData_Fluid_") + n + ".bgeo"));
    std::string out;
    ASSERT_EQ(runCli(render(dir / "in", dir / "serial" / "f_%02d.png"), &out), 0) << out;
    ASSERT_EQ(runMpi(3, render(dir / "in", dir / "mpi" / "f_%02d.png"), &out), 0) << out;
    EXPECT_NE(out.find("3 processes, split by frames"), std::string::npos) << out;
    // Each frame's particles over the processes instead.
    ASSERT_EQ(runMpi(2, render(dir / "in", dir / "mpi_particles" / "f_%02d.png", "--split particles"), &out), 0) << out;
    ASSERT_EQ(names(dir / "serial").size(), 4u);
    for (const fs::path& d : {dir / "mpi", dir / "mpi_particles"}) {
        ASSERT_EQ(names(d), names(dir / "serial")) << d;
        for (const std::string& n : names(dir / "serial"))
            EXPECT_EQ(readBytes(d / n), readBytes(dir / "serial" / n)) << d / n;
    }
}

TEST(CliMpi, AProcessThatCannotReadItsPartEndsTheJobWithNoImage) {
    const fs::path dir = freshDir("mpi_bad_part");
    writeParts(dir, 2);
    writeText(dir / "part_r1.bgeo", "not a bgeo file");
    fs::create_directories(dir / "out");
    std::string out;
    EXPECT_NE(runMpi(2, render(dir / "part_r%r.bgeo", dir / "out" / "f.png", "--anisotropy off"), &out), 0) << out;
    EXPECT_NE(out.find("part_r1.bgeo"), std::string::npos) << out;
    EXPECT_TRUE(names(dir / "out").empty()) << out;
    // A sequence split by frames: the process with the bad frame ends the job too.
    fs::create_directories(dir / "seq");
    fs::create_directories(dir / "seq_out");
    fs::copy_file(kFrame, dir / "seq" / "f_1.bgeo");
    writeText(dir / "seq" / "f_2.bgeo", "not a bgeo file");
    EXPECT_NE(runMpi(2, render(dir / "seq" / "f_%d.bgeo", dir / "seq_out" / "o_%d.png"), &out), 0) << out;
    EXPECT_NE(out.find("f_2.bgeo"), std::string::npos) << out;
}

TEST(CliMpi, SortLastWithNoiseWhiteningAndSpray) {
    // Every process reads the whole frame: the root splats the noise and the
    // whitening of every particle and draws every drop after the composite.
    expectSameAsOneProcess(freshDir("mpi_noise_spray"), kFrame, 3, "--noise --whiten --spray", "f.exr");
}

TEST(CliMpi, WhatSortLastCannotCompositeIsRefused) {
    const fs::path dir = freshDir("mpi_refused");
    writeParts(dir, 2);
    std::string out;
    // Part files: no process holds every particle.
    EXPECT_NE(runMpi(2, render(dir / "part_r%r.bgeo", dir / "n.png", "--anisotropy off --noise"), &out), 0) << out;
    EXPECT_NE(out.find("--noise: needs every particle"), std::string::npos) << out;
    for (int p = 0; p < 2; ++p) fs::remove(dir / ("part_r" + std::to_string(p) + ".bgeo"));
    EXPECT_NE(runMpi(2, render(kFrame, dir / "m.mp4", "--split frames --frames 4"), &out), 0) << out;
    EXPECT_NE(out.find("movie"), std::string::npos) << out;
    EXPECT_NE(runMpi(2, render(kFrame, dir / "s_%d.png", "--shard 0/2 --frames 2"), &out), 0) << out;
    EXPECT_NE(out.find("--shard"), std::string::npos) << out;
    EXPECT_TRUE(names(dir).empty()) << out;
}
}  // namespace cli_mpi_test_local
