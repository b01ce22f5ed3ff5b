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

// A backdrop sequence (a run of # in the name, as Blender names an
// animation's frames): frame i of the render is drawn over file
// --backdrop-first + i, exactly as over that file alone; a missing file fails
// its frame, naming the file and the frame.
TEST(CliBackdrop, ASequenceGivesEachFrameItsOwnPicture) {
    const fs::path dir = tempDir() / "cli_backdrop_sequence";
    fs::create_directories(dir);
    const fs::path in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    const std::string base = "render " + shellQuote(in) + " --width 64 --height 36" + kCamera;
    std::string out;
    // Two pictures of the set: the studio, and the floor alone under another light.
    ASSERT_EQ(runCli(base + " -o " + shellQuote(dir / "set_0001.exr"), &out), 0) << out;
    ASSERT_EQ(runCli(base + " --background floor --light -1,2,-1 -o " + shellQuote(dir / "set_0002.exr"), &out), 0)
        << out;
    for (const char* n : {"0001", "0002"})
        ASSERT_EQ(runCli(base + " --backdrop " + shellQuote(dir / ("set_" + std::string(n) + ".exr")) + " -o " +
                             shellQuote(dir / ("alone_" + std::string(n) + ".png")),
                         &out),
                  0)
            << out;
    const std::string sequence = " --backdrop " + shellQuote(dir / "set_####.exr");
    ASSERT_EQ(runCli(base + sequence + " --frames 2 -o " + shellQuote(dir / "seq_%d.png"), &out), 0) << out;
    const auto first = readPng(dir / "seq_0.png"), second = readPng(dir / "seq_1.png");
    EXPECT_EQ(first.bytes, readPng(dir / "alone_0001.png").bytes);
    EXPECT_EQ(second.bytes, readPng(dir / "alone_0002.png").bytes);
    EXPECT_NE(first.bytes, second.bytes);
    // --backdrop-first: the sequence starts at another file.
    ASSERT_EQ(runCli(base + sequence + " --backdrop-first 2 -o " + shellQuote(dir / "from2.png"), &out), 0) << out;
    EXPECT_EQ(readPng(dir / "from2.png").bytes, second.bytes);
    // A third frame has no picture: its frame fails, naming the file.
    EXPECT_EQ(runCli(base + sequence + " --frames 3 -o " + shellQuote(dir / "three_%d.png"), &out), 1);
    EXPECT_NE(out.find("set_0003.exr"), std::string::npos) << out;
    EXPECT_NE(out.find("frame 3 of the sequence"), std::string::npos) << out;
    EXPECT_NE(out.find("--on-error skip"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "three_2.png"));
    // The first file is checked before any frame is drawn.
    EXPECT_EQ(runCli(base + sequence + " --backdrop-first 5 -o " + shellQuote(dir / "none.png"), &out), 1);
    EXPECT_NE(out.find("set_0005.exr"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "none.png"));
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
