// Moving cameras in `meniscus render`: --turntable over
// --frames N of one file, --orbit at a rate in degrees per second of sequence
// time, camera.path in a scene file; each frame is exactly the still render
// from that frame's camera, with the floor-only background a moving camera
// gets; bad paths and option mixes are errors naming what is wrong.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "meniscus/camera_path.h"
#include "test_util.h"

namespace cli_camera_path_test_local {

namespace fs = std::filesystem;
using namespace meniscus;
using namespace meniscus::test;

namespace {

// `render DIR/f.bgeo -o DIR/OUT` small and on the CPU, with `more` options.
std::string render(const fs::path& dir, const std::string& out, const std::string& more) {
    return "render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / out) + " --width 96 --height 64 --backend cpu " +
           more;
}

// x,y,z that reads back as the same floats.
std::string text(const glm::vec3& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g", double(v.x), double(v.y), double(v.z));
    return buf;
}

std::vector<std::uint8_t> pixels(const fs::path& p) { return readPng(p).bytes; }

const glm::vec3 kEye{2.5f, 2.1f, 2.9f}, kTarget{0.43f, 0.45f, 0.0f};
const std::string kCamera = "--eye 2.5,2.1,2.9 --target 0.43,0.45,0";

}  // namespace

TEST(CliCameraPath, TurntableOfOneFileWritesTurningFramesStartingFromTheStill) {
    const fs::path dir = dirWithFrame("cam_turntable");
    std::string out;
    ASSERT_EQ(runCli(render(dir, "t_%02d.png", "--turntable --frames 4"), &out), 0) << out;
    EXPECT_NE(out.find("floor"), std::string::npos) << out;  // says which background it took
    std::vector<std::vector<std::uint8_t>> frames;
    for (const char* name : {"t_00.png", "t_01.png", "t_02.png", "t_03.png"}) {
        ASSERT_TRUE(fs::exists(dir / name)) << name << "\n" << out;
        frames.push_back(pixels(dir / name));
    }
    EXPECT_FALSE(fs::exists(dir / "t_04.png"));
    for (std::size_t a = 0; a < frames.size(); ++a)
        for (std::size_t b = a + 1; b < frames.size(); ++b) EXPECT_NE(frames[a], frames[b]) << a << " vs " << b;
    // Frame 0 is the automatic camera's still, on the floor-only background.
    ASSERT_EQ(runCli(render(dir, "floor.png", "--background floor"), &out), 0) << out;
    EXPECT_EQ(frames[0], pixels(dir / "floor.png"));
    // ... which is not the default studio's look.
    ASSERT_EQ(runCli(render(dir, "studio.png", ""), &out), 0) << out;
    EXPECT_NE(frames[0], pixels(dir / "studio.png"));
}

TEST(CliCameraPath, OrbitFrameIsTheStillFromTheTurnedEye) {
    // 90 deg/s at 2 fps: frame 1 (0.5 s) is the camera turned by 45 degrees.
    const fs::path dir = dirWithFrame("cam_orbit");
    std::string out;
    ASSERT_EQ(runCli(render(dir, "o_%d.png", kCamera + " --orbit 90 --fps 2 --frames 2"), &out), 0) << out;
    const glm::vec3 turned = turnAboutVertical(kEye, kTarget, 45.0);
    ASSERT_EQ(runCli(render(dir, "still.png", "--eye " + text(turned) + " --target 0.43,0.45,0 --background floor"),
                     &out),
              0)
        << out;
    EXPECT_EQ(pixels(dir / "o_1.png"), pixels(dir / "still.png"));
    EXPECT_NE(pixels(dir / "o_0.png"), pixels(dir / "still.png"));
}

TEST(CliCameraPath, AnExplicitStudioKeepsItsWallsWhereTheFirstFrameSeesThem) {
    const fs::path dir = dirWithFrame("cam_studio");
    std::string out;
    ASSERT_EQ(runCli(render(dir, "s_%d.png", kCamera + " --turntable --frames 4 --background studio"), &out), 0) << out;
    // Frame 0: the default still, walls and all.
    ASSERT_EQ(runCli(render(dir, "still0.png", kCamera), &out), 0) << out;
    EXPECT_EQ(pixels(dir / "s_0.png"), pixels(dir / "still0.png"));
    // Frame 2 looks from the other side: a still from there puts the walls
    // behind the box as seen from there; the run keeps frame 0's.
    const std::string opposite = "--eye " + text(turnAboutVertical(kEye, kTarget, 180.0)) + " --target 0.43,0.45,0";
    ASSERT_EQ(runCli(render(dir, "still2.png", opposite), &out), 0) << out;
    EXPECT_NE(pixels(dir / "s_2.png"), pixels(dir / "still2.png"));
}

TEST(CliCameraPath, SceneFileCameraPathPassesThroughItsKeys) {
    const fs::path dir = dirWithFrame("cam_scene_path");
    std::ofstream(dir / "scene.json")
        << R"({"particles": "f.bgeo", "output": "p_%d.png", "backend": "cpu",)"
           R"( "render": {"width": 96, "height": 64, "fps": 1, "frames": 3},)"
           R"( "camera": {"path": [{"time": 0, "eye": [2.5, 2.1, 2.9], "target": [0.43, 0.45, 0], "fov": 40},)"
           R"( {"time": 2, "eye": [-1.5, 1.2, 2.5], "target": [0.4, 0.3, 0], "fov": 30}]}})";
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "scene.json"), &out), 0) << out;
    ASSERT_EQ(runCli(render(dir, "k0.png", kCamera + " --fov 40 --background floor"), &out), 0) << out;
    ASSERT_EQ(runCli(render(dir, "k1.png", "--eye -1.5,1.2,2.5 --target 0.4,0.3,0 --fov 30 --background floor"), &out),
              0)
        << out;
    EXPECT_EQ(pixels(dir / "p_0.png"), pixels(dir / "k0.png"));
    EXPECT_EQ(pixels(dir / "p_2.png"), pixels(dir / "k1.png"));  // 2 s at 1 fps: the last key
    EXPECT_NE(pixels(dir / "p_1.png"), pixels(dir / "k0.png"));  // between them, somewhere else
    EXPECT_NE(pixels(dir / "p_1.png"), pixels(dir / "k1.png"));
    // The same path as a file given on the command line.
    std::ofstream(dir / "path.json")
        << R"([{"time": 0, "eye": [2.5, 2.1, 2.9], "target": [0.43, 0.45, 0], "fov": 40},)"
           R"( {"time": 2, "eye": [-1.5, 1.2, 2.5], "target": [0.4, 0.3, 0], "fov": 30}])";
    ASSERT_EQ(runCli(render(dir, "c_%d.png", "--camera-path " + shellQuote(dir / "path.json") + " --fps 1 --frames 3"), &out),
              0)
        << out;
    EXPECT_EQ(pixels(dir / "c_1.png"), pixels(dir / "p_1.png"));
}

TEST(CliCameraPath, BadPathsAndOptionMixesAreErrorsThatSayWhere) {
    const fs::path dir = dirWithFrame("cam_errors");
    auto scene = [&](const std::string& path) {
        std::ofstream(dir / "scene.json") << R"({"particles": "f.bgeo", "output": "p_%d.png", "frames": 2,)"
                                          << R"( "camera": {"path": )" << path << "}}";
        std::string out;
        EXPECT_EQ(runCli("render " + shellQuote(dir / "scene.json"), &out), 2) << out;  // the file's values
        return out;
    };
    std::string out = scene(R"([{"time": 1, "eye": [1, 1, 1], "target": [0, 0, 0]},)"
                            R"( {"time": 0.5, "eye": [2, 1, 1], "target": [0, 0, 0]}])");
    EXPECT_NE(out.find((dir / "scene.json").string() + ": camera.path: "), std::string::npos) << out;
    EXPECT_NE(out.find("key 2: time"), std::string::npos) << out;
    out = scene(R"([{"time": 0, "eyes": [1, 1, 1], "target": [0, 0, 0]}])");
    EXPECT_NE(out.find("camera.path"), std::string::npos) << out;
    EXPECT_NE(out.find("unknown field \"eyes\""), std::string::npos) << out;
    out = scene(R"([{"time": 0, "target": [0, 0, 0]}])");
    EXPECT_NE(out.find("key 1: needs \"eye\""), std::string::npos) << out;
    out = scene("[]");
    EXPECT_NE(out.find("camera.path"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "p_0.png"));

    EXPECT_EQ(runCli(render(dir, "x.png", "--turntable"), &out), 2) << out;  // one frame: nothing to turn over
    EXPECT_NE(out.find("--frames"), std::string::npos) << out;
    EXPECT_EQ(runCli(render(dir, "x_%d.png", "--turntable --orbit 10 --frames 2"), &out), 2) << out;
    EXPECT_NE(out.find("--orbit and --turntable"), std::string::npos) << out;
    EXPECT_EQ(runCli(render(dir, "x_%d.png", kCamera + " --camera-path " + shellQuote(dir / "none.json") + " --frames 2"),
                     &out),
              1)
        << out;
    EXPECT_NE(out.find("--camera-path"), std::string::npos) << out;
    // --frames repeats one file; a sequence renders its own frames.
    fs::copy_file(dir / "f.bgeo", dir / "g_1.bgeo");
    fs::copy_file(dir / "f.bgeo", dir / "g_2.bgeo");
    EXPECT_EQ(runCli("render " + shellQuote(dir / "g_*.bgeo") + " -o " + shellQuote(dir / "y_%d.png") + " --frames 5", &out), 2)
        << out;
    EXPECT_NE(out.find("--frames"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "x_0.png"));
    EXPECT_FALSE(fs::exists(dir / "y_1.png"));
}
}  // namespace cli_camera_path_test_local
