// End-to-end tests of `meniscus simulate`: a scene to a numbered sequence the
// readers take back with id, velocity and density; the same files for any
// --threads; --resume; bad scenes and outputs fail cleanly.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "test_util.h"

namespace fs = std::filesystem;
using namespace meniscus::test;

namespace {

std::string quote(const fs::path& p) { return "'" + p.string() + "'"; }
int runCli(const std::string& args, std::string* out = nullptr) { return runCommand(cliPath() + " " + args, out); }

// A small dam break: 9 x 14 x 5 particles (free faces 2r inside, walls r), 0.1 s.
fs::path writeScene(const fs::path& dir) {
    const fs::path p = dir / "small.json";
    std::ofstream(p) << R"({
  "version": 1, "name": "small", "duration": 0.1, "fps": 50,
  "params": { "radius": 0.01 },
  "domain": { "min": [0, 0, 0], "max": [0.4, 0.4, 0.1] },
  "fluid": [ { "box": { "min": [0, 0, 0], "max": [0.2, 0.3, 0.1] } } ]
})";
    return p;
}

}  // namespace

TEST(CliSimulate, SceneToASequenceTheReadersTakeBack) {
    const fs::path dir = tempDir();
    const fs::path scene = writeScene(dir);
    std::string out;
    ASSERT_EQ(runCli("simulate " + quote(scene) + " -o " + quote(dir / "out/f_%04d.bgeo"), &out), 0) << out;
    for (int k = 0; k <= 5; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "out/f_%04d.bgeo", k);
        auto set = meniscus::readParticles(dir / name);
        ASSERT_TRUE(set.ok()) << set.error().describe();
        EXPECT_EQ(set->size(), 9u * 14u * 5u);
        ASSERT_NE(set->find(meniscus::kAttrId), nullptr);
        ASSERT_NE(set->find(meniscus::kAttrVelocity), nullptr);
        ASSERT_NE(set->find(meniscus::kAttrDensity), nullptr);
    }
    EXPECT_FALSE(fs::exists(dir / "out/f_0006.bgeo"));
    EXPECT_NE(out.find("wrote"), std::string::npos) << out;  // not a terminal: a line per frame
    // The other formats.
    for (const char* ext : {"vtk", "vtu", "ply"}) {
        ASSERT_EQ(runCli("simulate " + quote(scene) + " -o " + quote(dir / (std::string("g_%02d.") + ext)) + " --duration 0.02", &out), 0) << out;
        auto set = meniscus::readParticles(dir / (std::string("g_01.") + ext));
        ASSERT_TRUE(set.ok()) << set.error().describe();
        EXPECT_NE(set->find(meniscus::kAttrVelocity), nullptr) << ext;
    }
}

TEST(CliSimulate, SameFilesForAnyThreadCountAndResumeContinues) {
    const fs::path dir = tempDir();
    const fs::path scene = writeScene(dir);
    std::string out;
    ASSERT_EQ(runCli("--threads 1 simulate " + quote(scene) + " -o " + quote(dir / "a/f_%04d.bgeo"), &out), 0) << out;
    ASSERT_EQ(runCli("--threads 2 simulate " + quote(scene) + " -o " + quote(dir / "b/f_%04d.bgeo"), &out), 0) << out;
    EXPECT_TRUE(readBytes(dir / "a/f_0005.bgeo") == readBytes(dir / "b/f_0005.bgeo"));
    // Interrupted after frame 2: --resume writes 3..5 from frame 2's particles.
    fs::remove(dir / "b/f_0003.bgeo"), fs::remove(dir / "b/f_0004.bgeo"), fs::remove(dir / "b/f_0005.bgeo");
    ASSERT_EQ(runCli("simulate " + quote(scene) + " -o " + quote(dir / "b/f_%04d.bgeo") + " --resume", &out), 0) << out;
    EXPECT_NE(out.find("resuming after"), std::string::npos) << out;
    EXPECT_EQ(out.find("f_0001.bgeo"), std::string::npos) << "frames before the resume point are not rewritten";
    auto resumed = meniscus::readParticles(dir / "b/f_0005.bgeo");
    auto straight = meniscus::readParticles(dir / "a/f_0005.bgeo");
    ASSERT_TRUE(resumed.ok() && straight.ok());
    ASSERT_EQ(resumed->size(), straight->size());
    // Not bit-identical (the solver's warm start is not in the file), but the same flow.
    double gap = 0.0;
    for (std::size_t i = 0; i < resumed->size(); ++i) gap = std::max(gap, double(glm::length(resumed->positions[i] - straight->positions[i])));
    EXPECT_LT(gap, 0.01) << "m";
}

TEST(CliSimulate, BadScenesAndOutputsFailCleanly) {
    const fs::path dir = tempDir();
    std::string out;
    std::ofstream(dir / "typo.json") << R"({"version": 1, "domain": {"min": [0,0,0], "max": [1,1,1]}, "fluid": [], "raduis": 0.01})";
    EXPECT_EQ(runCli("simulate " + quote(dir / "typo.json") + " -o " + quote(dir / "f_%04d.bgeo"), &out), 1);
    EXPECT_NE(out.find("typo.json"), std::string::npos) << out;
    EXPECT_NE(out.find("raduis"), std::string::npos) << out;
    EXPECT_EQ(runCli("simulate " + quote(dir / "missing.json") + " -o " + quote(dir / "f_%04d.bgeo"), &out), 1);
    const fs::path scene = writeScene(dir);
    EXPECT_EQ(runCli("simulate " + quote(scene) + " -o " + quote(dir / "nonumber.bgeo"), &out), 1);
    EXPECT_NE(out.find("frame number"), std::string::npos) << out;
    EXPECT_EQ(runCli("simulate " + quote(scene) + " -o " + quote(dir / "f_%04d.png"), &out), 1);
    EXPECT_EQ(runCli("simulate " + quote(scene) + " -o " + quote(dir / "f_%04d.bgeo") + " --solver magic", &out), 2);
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir)) files += e.path().extension() != ".json";
    EXPECT_EQ(files, 0u) << "nothing written";
}
