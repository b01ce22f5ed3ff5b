// End-to-end tests of `meniscus whitewater`: the real small dam-break frames
// 19-23 (data/demo, SPlisHSPlasH, 15 fps) to a numbered diffuse sequence, with
// the frame rate estimated and the limits automatic; the same bytes for any
// --threads; a fluid without velocities and bad options fail with nothing written.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "meniscus/whitewater.h"
#include "test_util.h"

namespace cli_whitewater_test_local {

namespace fs = std::filesystem;
using namespace meniscus::test;

namespace {

fs::path realSequence(const fs::path& dir) {
    fs::create_directories(dir / "in");
    for (int k = 19; k <= 23; ++k) {
        const std::string name = "ParticleData_Fluid_" + std::to_string(k) + ".bgeo";
        fs::copy_file(repoData("demo/" + name), dir / "in" / name);
    }
    return dir / "in";
}

}  // namespace

TEST(CliWhitewater, RealSequenceToNumberedDiffuseFiles) {
    const fs::path dir = tempDir();
    const fs::path in = realSequence(dir);
    std::string out;
    ASSERT_EQ(runCli("whitewater " + shellQuote(in) + " -o " + shellQuote(dir / "out" / "diffuse_%04d.bgeo"), &out), 0) << out;
    EXPECT_NE(out.find("frames per second, estimated"), std::string::npos) << out;
    EXPECT_NE(out.find("automatic limits"), std::string::npos) << out;
    EXPECT_NE(out.find("wrote"), std::string::npos) << out;  // one line per frame off a terminal
    for (int k = 19; k <= 23; ++k) ASSERT_TRUE(fs::exists(dir / "out" / ("diffuse_00" + std::to_string(k) + ".bgeo")));
    auto last = meniscus::readParticles(dir / "out" / "diffuse_0023.bgeo");
    ASSERT_TRUE(last.ok()) << last.error().describe();
    EXPECT_GT(last->size(), 500u);
    EXPECT_NE(last->find(meniscus::sim::kAttrDiffuseType), nullptr);
    // The first frame has none yet: what it makes appears from the next on.
    auto first = meniscus::readParticles(dir / "out" / "diffuse_0019.bgeo", meniscus::ParticleFormat::Auto, true);
    ASSERT_TRUE(first.ok());
    EXPECT_EQ(first->size(), 0u);
}

TEST(CliWhitewater, SameFilesForAnyThreadCount) {
    const fs::path dir = tempDir();
    const fs::path in = realSequence(dir);
    std::string out;
    const std::string common = " --fps 15 --limits 1,10,0.5,5,1,14";
    ASSERT_EQ(runCli("--threads 1 whitewater " + shellQuote(in) + " -o " + shellQuote(dir / "a_%04d.bgeo") + common, &out), 0) << out;
    ASSERT_EQ(runCli("whitewater " + shellQuote(in) + " -o " + shellQuote(dir / "b_%04d.bgeo") + common + " --threads 2", &out), 0)
        << out;
    EXPECT_EQ(out.find("automatic"), std::string::npos) << out;  // limits given: no measuring pass
    for (int k = 19; k <= 23; ++k) {
        const std::string n = "_00" + std::to_string(k) + ".bgeo";
        EXPECT_TRUE(readBytes(dir / ("a" + n)) == readBytes(dir / ("b" + n))) << n;
    }
}

TEST(CliWhitewater, BadInputFailsWithNothingWritten) {
    const fs::path dir = tempDir();
    // A fluid without velocities (the mesher's test frames have them; a PLY of positions has not).
    fs::create_directories(dir / "novel");
    for (int k : {1, 2}) writeText(dir / "novel" / ("f_" + std::to_string(k) + ".xyz"), "0 0 0\n0.05 0 0\n0 0.05 0\n");
    std::string out;
    EXPECT_EQ(runCli("whitewater " + shellQuote(dir / "novel") + " -o " + shellQuote(dir / "d_%04d.bgeo") + " --radius 0.025", &out), 1)
        << out;
    EXPECT_NE(out.find("no velocity attribute"), std::string::npos) << out;
    EXPECT_NE(out.find("f_1.xyz"), std::string::npos) << out;  // names the file
    EXPECT_FALSE(fs::exists(dir / "d_0001.bgeo"));
    const fs::path in = realSequence(dir);
    EXPECT_EQ(runCli("whitewater " + shellQuote(in) + " -o " + shellQuote(dir / "d_%04d.bgeo") + " --limits 1,2,3", &out), 2) << out;
    EXPECT_EQ(runCli("whitewater " + shellQuote(in) + " -o " + shellQuote(dir / "d_%04d.bgeo") + " --limits 5,1,1,2,1,2", &out), 2)
        << out;
    EXPECT_NE(out.find("trappedAir"), std::string::npos) << out;
    // The option table's ranges and counts are usage errors, naming the option.
    const std::string run = "whitewater " + shellQuote(in) + " -o " + shellQuote(dir / "d_%04d.bgeo");
    EXPECT_EQ(runCli(run + " --drag 2", &out), 2) << out;
    EXPECT_NE(out.find("--drag"), std::string::npos) << out;
    EXPECT_EQ(runCli(run + " --lifetime 3", &out), 2) << out;
    EXPECT_EQ(runCli(run + " --box 1,0,0,0,1,1", &out), 2) << out;
    EXPECT_NE(out.find("--box: each minimum must be below its maximum"), std::string::npos) << out;
    EXPECT_EQ(runCli("whitewater " + shellQuote(in) + " -o " + shellQuote(dir / "d.bgeo"), &out), 1) << out;  // no pattern
    EXPECT_FALSE(fs::exists(dir / "d_0019.bgeo"));
}

// `render --diffuse`: the whitewater drawn as a layer, its frame found by the
// input frame's number; the EXR carries its cover; a missing file is named.
TEST(CliWhitewater, RenderDrawsTheDiffuseLayer) {
    const fs::path dir = tempDir();
    const fs::path in = realSequence(dir);
    std::string out;
    ASSERT_EQ(runCli("whitewater " + shellQuote(in) + " -o " + shellQuote(dir / "d_%04d.bgeo") + " --fps 15", &out), 0) << out;
    const fs::path frame = in / "ParticleData_Fluid_23.bgeo";
    const std::string size = " --width 160 --height 90 --backend cpu";
    ASSERT_EQ(runCli("render " + shellQuote(frame) + " -o " + shellQuote(dir / "plain.png") + size, &out), 0) << out;
    ASSERT_EQ(runCli("render " + shellQuote(frame) + " -o " + shellQuote(dir / "ww.png") + size + " --diffuse " +
                         shellQuote(dir / "d_%04d.bgeo"),
                     &out),
              0)
        << out;
    EXPECT_FALSE(readBytes(dir / "plain.png") == readBytes(dir / "ww.png"));
    ASSERT_EQ(runCli("render " + shellQuote(frame) + " -o " + shellQuote(dir / "ww.exr") + size + " --diffuse " +
                         shellQuote(dir / "d_0023.bgeo"),
                     &out),
              0)
        << out;
    const auto exr = readBytes(dir / "ww.exr");
    EXPECT_NE(std::string(exr.begin(), exr.end()).find("spray"), std::string::npos);  // the cover channel
    EXPECT_EQ(runCli("render " + shellQuote(frame) + " -o " + shellQuote(dir / "x.png") + size + " --diffuse " +
                         shellQuote(dir / "missing_%04d.bgeo"),
                     &out),
              1)
        << out;
    EXPECT_NE(out.find("missing_0023.bgeo"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "x.png"));
}
}  // namespace cli_whitewater_test_local
