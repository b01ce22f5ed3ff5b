// The command line's backdrop options (docs/compositing.md): a render's own
// EXR (R, G, B, A and its Z) as the backdrop of another render by the same
// camera, the depth conventions, a scene file's key, and the errors: a
// backdrop of another size is a usage error (exit 2) naming both sizes, a
// missing or broken file an error naming it (exit 1), and no output either
// way.
#include <string>

#include <gtest/gtest.h>

#include "test_util.h"

namespace cli_backdrop_test_local {

namespace fs = std::filesystem;
using namespace meniscus::test;

namespace {

const std::string kCamera = " --eye 2.6,1.2,3.2 --target 0,0.3,0 --fov 40";

}  // namespace

TEST(CliBackdrop, ARendersEXRIsABackdrop) {
    const fs::path dir = tempDir() / "cli_backdrop";
    fs::create_directories(dir);
    const fs::path in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    const std::string base = "render " + shellQuote(in) + " --width 96 --height 54" + kCamera;
    std::string out;
    ASSERT_EQ(runCli(base + " -o " + shellQuote(dir / "set.exr"), &out), 0) << out;
    ASSERT_EQ(runCli(base + " -o " + shellQuote(dir / "plain.png"), &out), 0) << out;
    ASSERT_EQ(runCli(base + " --backdrop " + shellQuote(dir / "set.exr") + " -o " + shellQuote(dir / "over.png"), &out),
              0)
        << out;
    ASSERT_EQ(runCli(base + " --backdrop " + shellQuote(dir / "set.exr") + " --backdrop-depth-kind ray -o " +
                         shellQuote(dir / "ray.png"),
                     &out),
              0)
        << out;
    const auto plain = readPng(dir / "plain.png"), over = readPng(dir / "over.png");
    ASSERT_EQ(over.width, 96);
    EXPECT_NE(plain.bytes, over.bytes);  // the set's picture (liquid and all) behind the liquid
    // The separate depth file: the EXR's Z read from a file of its own.
    ASSERT_EQ(runCli(base + " --backdrop " + shellQuote(dir / "plain.png") + " --backdrop-depth " +
                         shellQuote(dir / "set.exr") + " -o " + shellQuote(dir / "two.png"),
                     &out),
              0)
        << out;
    EXPECT_TRUE(fs::exists(dir / "two.png"));
}

TEST(CliBackdrop, ErrorsNameTheFileOrTheSizes) {
    const fs::path dir = tempDir() / "cli_backdrop_errors";
    fs::create_directories(dir);
    const fs::path in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    const std::string base = "render " + shellQuote(in) + kCamera;
    std::string out;
    ASSERT_EQ(runCli(base + " --width 64 --height 36 -o " + shellQuote(dir / "set.exr"), &out), 0) << out;
    const std::string target = " -o " + shellQuote(dir / "f.png");
    EXPECT_EQ(runCli(base + " --width 96 --height 54 --backdrop " + shellQuote(dir / "set.exr") + target, &out), 2);
    EXPECT_NE(out.find("64x36 pixels and the picture 96x54"), std::string::npos) << out;
    EXPECT_NE(out.find("--width 64 --height 36"), std::string::npos) << out;
    EXPECT_EQ(runCli(base + " --width 64 --height 36 --backdrop " + shellQuote(dir / "nothere.exr") + target, &out), 1);
    EXPECT_NE(out.find("nothere.exr"), std::string::npos) << out;
    writeText(dir / "broken.exr", "not an OpenEXR file");
    EXPECT_EQ(runCli(base + " --width 64 --height 36 --backdrop " + shellQuote(dir / "broken.exr") + target, &out), 1);
    EXPECT_NE(out.find("broken.exr"), std::string::npos) << out;
    EXPECT_EQ(runCli(base + " --width 64 --height 36 --backdrop " + shellQuote(dir / "set.exr") +
                         " --backdrop-depth-kind window:5,1" + target,
                     &out),
              2);
    EXPECT_NE(out.find("window:NEAR,FAR"), std::string::npos) << out;
    EXPECT_EQ(runCli(base + " --width 64 --height 36 --backdrop-depth " + shellQuote(dir / "set.exr") + target, &out),
              2);
    EXPECT_NE(out.find("--backdrop"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "f.png"));
}

// A scene file's `backdrop` key is a path relative to the scene file.
TEST(CliBackdrop, SceneFileKeyIsRelativeToTheFile) {
    const fs::path dir = dirWithFrame("scene_backdrop");
    fs::create_directories(dir / "set");
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "f.bgeo") + " --width 64 --height 36" + kCamera + " -o " +
                         shellQuote(dir / "set" / "set.exr"),
                     &out),
              0)
        << out;
    writeText(dir / "scene.json", R"({
      "particles": "f.bgeo", "output": "a.png", "width": 64, "height": 36,
      "camera": {"eye": [2.6, 1.2, 3.2], "target": [0, 0.3, 0], "fov": 40},
      "backdrop": "set/set.exr", "backdrop_depth_kind": "linear"})");
    ASSERT_EQ(runCli("render " + shellQuote(dir / "scene.json"), &out), 0) << out;
    EXPECT_TRUE(fs::exists(dir / "a.png"));
}
}  // namespace cli_backdrop_test_local
