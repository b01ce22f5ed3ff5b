// End-to-end tests of `meniscus mesh`: a real frame to PLY and OBJ, a
// sequence to numbered files, the same bytes for any --threads, bad input and
// bad options fail cleanly with nothing written.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "test_util.h"

namespace fs = std::filesystem;
using namespace meniscus::test;

namespace {

std::string quote(const fs::path& p) { return "'" + p.string() + "'"; }
int runCli(const std::string& args, std::string* out = nullptr) { return runCommand(cliPath() + " " + args, out); }
const fs::path kFrame = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");

}  // namespace

TEST(CliMesh, RealFrameToPlyAndObj) {
    const fs::path dir = tempDir();
    std::string out;
    ASSERT_EQ(runCli("mesh " + quote(kFrame) + " -o " + quote(dir / "f.ply") + " --stats", &out), 0) << out;
    EXPECT_NE(out.find("wrote"), std::string::npos) << out;
    EXPECT_NE(out.find("peak"), std::string::npos) << out;  // --stats
    auto back = meniscus::readParticles(dir / "f.ply");  // the vertices, through our own PLY reader
    ASSERT_TRUE(back.ok()) << back.error().describe();
    EXPECT_GT(back->size(), 10000u);
    ASSERT_EQ(runCli("mesh " + quote(kFrame) + " -o " + quote(dir / "f.obj") + " --field thesis --cube-size 1", &out), 0)
        << out;
    const auto obj = readBytes(dir / "f.obj");
    EXPECT_NE(std::string(obj.begin(), obj.begin() + 200).find("# written by meniscus"), std::string::npos);
}

TEST(CliMesh, SameFileForAnyThreadCount) {
    const fs::path dir = tempDir();
    std::string out;
    ASSERT_EQ(runCli("mesh " + quote(kFrame) + " -o " + quote(dir / "one.ply") + " --threads 1", &out), 0) << out;
    ASSERT_EQ(runCli("--threads 3 mesh " + quote(kFrame) + " -o " + quote(dir / "three.ply"), &out), 0) << out;
    EXPECT_TRUE(readBytes(dir / "one.ply") == readBytes(dir / "three.ply"));
}

TEST(CliMesh, SequenceToNumberedFiles) {
    const fs::path dir = tempDir();
    fs::create_directories(dir / "in");
    for (int k : {9, 21}) {
        const std::string name = "ParticleData_Fluid_" + std::to_string(k) + ".bgeo";
        fs::copy_file(testData("splishsplash/partio/" + name), dir / "in" / name);
    }
    std::string out;
    ASSERT_EQ(runCli("mesh " + quote(dir / "in") + " -o " + quote(dir / "m_%04d.ply") + " --cube-size 1", &out), 0)
        << out;
    EXPECT_TRUE(fs::exists(dir / "m_0009.ply"));
    EXPECT_TRUE(fs::exists(dir / "m_0021.ply"));
    // Not on a terminal: one log line per frame.
    EXPECT_NE(out.find("m_0009.ply"), std::string::npos) << out;
    EXPECT_NE(out.find("m_0021.ply"), std::string::npos) << out;
    // Two frames into one name is refused before anything is written.
    EXPECT_NE(runCli("mesh " + quote(dir / "in") + " -o " + quote(dir / "one.ply"), &out), 0);
    EXPECT_NE(out.find("pattern"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "one.ply"));
}

TEST(CliMesh, BadInputAndOptionsFailCleanly) {
    const fs::path dir = tempDir();
    std::string out;
    EXPECT_EQ(runCli("mesh " + quote(kFrame) + " -o " + quote(dir / "x.stl"), &out), 1);
    EXPECT_NE(out.find("x.stl"), std::string::npos) << out;
    EXPECT_EQ(runCli("mesh " + quote(dir / "missing.bgeo") + " -o " + quote(dir / "x.ply"), &out), 1);
    EXPECT_NE(out.find("missing.bgeo"), std::string::npos) << out;
    EXPECT_EQ(runCli("mesh " + quote(kFrame) + " -o " + quote(dir / "x.ply") + " --cube-size 0", &out), 1);
    EXPECT_NE(out.find("cube size"), std::string::npos) << out;
    EXPECT_EQ(runCli("mesh " + quote(kFrame) + " -o " + quote(dir / "x.ply") + " --field metaballs", &out), 2);
    // A truncated file: the reader's error, naming it.
    const auto bytes = readBytes(kFrame);
    writeBytes(dir / "cut.bgeo", std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + long(bytes.size() / 2)));
    EXPECT_EQ(runCli("mesh " + quote(dir / "cut.bgeo") + " -o " + quote(dir / "x.ply"), &out), 1);
    EXPECT_NE(out.find("cut.bgeo"), std::string::npos) << out;
    fs::remove(dir / "cut.bgeo");
    EXPECT_TRUE(fs::is_empty(dir)) << "nothing written";
    EXPECT_EQ(runCli("mesh --help", &out), 0);
    for (const char* unit : {"particle radii", "metres", "fraction"}) EXPECT_NE(out.find(unit), std::string::npos) << unit;
}
