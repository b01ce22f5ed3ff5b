// The command line's environment map options (docs/pipeline.md#environment-map):
// --environment, --environment-rotation, --environment-intensity render, and
// a missing, corrupt or unsupported file is an error naming it.
#include <string>

#include <gtest/gtest.h>

#include "test_util.h"

namespace cli_environment_test_local {

namespace fs = std::filesystem;
using namespace meniscus::test;

TEST(CliEnvironment, RendersWithAMapAndItsOptions) {
    const fs::path dir = tempDir();
    const fs::path in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    const std::string base = "render " + shellQuote(in) + " --width 96 --height 54 -o ";
    const std::string map = shellQuote(testData("environment/sky_128x64.exr"));
    std::string out;
    ASSERT_EQ(runCli(base + shellQuote(dir / "sky.png"), &out), 0) << out;
    ASSERT_EQ(runCli(base + shellQuote(dir / "map.png") + " --environment " + map, &out), 0) << out;
    ASSERT_EQ(runCli(base + shellQuote(dir / "turned.png") + " --environment " + map +
                         " --environment-rotation 90 --environment-intensity 0.5",
                     &out),
              0)
        << out;
    const auto sky = readBytes(dir / "sky.png"), withMap = readBytes(dir / "map.png");
    const auto turned = readBytes(dir / "turned.png");
    ASSERT_FALSE(sky.empty());
    EXPECT_NE(sky, withMap);
    EXPECT_NE(withMap, turned);
}

TEST(CliEnvironment, BadFilesAreErrorsNamingThem) {
    const fs::path dir = tempDir();
    const fs::path in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    const std::string base = "render " + shellQuote(in) + " --width 64 --height 36 -o " + shellQuote(dir / "f.png");
    std::string out;
    EXPECT_NE(runCli(base + " --environment " + shellQuote(dir / "nothere.exr"), &out), 0);
    EXPECT_NE(out.find("nothere.exr"), std::string::npos) << out;
    EXPECT_NE(out.find("--environment"), std::string::npos) << out;
    writeText(dir / "broken.exr", "v/1 but not really an OpenEXR file");
    EXPECT_NE(runCli(base + " --environment " + shellQuote(dir / "broken.exr"), &out), 0);
    EXPECT_NE(out.find("broken.exr"), std::string::npos) << out;
    // A Radiance picture cut short in its header.
    writeText(dir / "sky.hdr", "#?RADIANCE\n");
    EXPECT_NE(runCli(base + " --environment " + shellQuote(dir / "sky.hdr"), &out), 0);
    EXPECT_NE(out.find("sky.hdr"), std::string::npos) << out;
    EXPECT_NE(out.find("header"), std::string::npos) << out;
    EXPECT_NE(runCli(base + " --environment " + shellQuote(testData("environment/sky_128x64.exr")) +
                         " --environment-intensity -1",
                     &out),
              0);
    EXPECT_FALSE(fs::exists(dir / "f.png"));
}

// A Radiance .hdr map renders like an OpenEXR one: a 2 x 1 picture, flat.
TEST(CliEnvironment, RadianceHdrMapsRender) {
    const fs::path dir = tempDir();
    const fs::path in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    writeText(dir / "sky.hdr", std::string("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n") +
                                   std::string("\x40\x60\x80\x81\x40\x60\x80\x81", 8));
    std::string out;
    EXPECT_EQ(runCli("render " + shellQuote(in) + " --width 64 --height 36 --environment " +
                         shellQuote(dir / "sky.hdr") + " -o " + shellQuote(dir / "f.png"),
                     &out),
              0)
        << out;
    EXPECT_TRUE(fs::exists(dir / "f.png"));
}

// A scene file's `environment` key is a path relative to the scene file and
// gives the picture of the same --environment option.
TEST(CliEnvironment, SceneFileKeyIsRelativeToTheFile) {
    const fs::path dir = dirWithFrame("scene_environment");
    fs::create_directories(dir / "maps");
    fs::copy_file(testData("environment/sky_128x64.exr"), dir / "maps" / "sky.exr",
                  fs::copy_options::overwrite_existing);
    writeText(dir / "scene.json", R"({
      "particles": "f.bgeo", "output": "a.png", "radius": 0.01,
      "camera": {"eye": [2.6, 0.4, 3.2], "target": [0, 0.35, 0]},
      "render": {"width": 96, "height": 54, "backend": "cpu", "background": "floor",
                 "environment": "maps/sky.exr", "environment_rotation": 45}
    })");
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "scene.json"), &out), 0) << out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "b.png") +
                         " --radius 0.01 --eye 2.6,0.4,3.2 --target 0,0.35,0 --width 96 --height 54 --backend cpu "
                         "--background floor --environment-rotation 45 --environment " +
                         shellQuote(dir / "maps" / "sky.exr"),
                     &out),
              0)
        << out;
    EXPECT_EQ(readBytes(dir / "a.png"), readBytes(dir / "b.png"));
}
}  // namespace cli_environment_test_local
