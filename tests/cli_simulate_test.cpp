// End-to-end tests of `meniscus simulate`: a scene to a numbered sequence the
// readers take back with id, velocity and density; the same files for any
// --threads; --resume; bad scenes and outputs fail cleanly.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "test_util.h"

namespace cli_simulate_test_local {

namespace fs = std::filesystem;
using namespace meniscus::test;

namespace {

}  // namespace

TEST(CliSimulate, SceneToASequenceTheReadersTakeBack) {
    const fs::path dir = tempDir();
    const fs::path scene = writeSmallScene(dir);
    std::string out;
    ASSERT_EQ(runCli("simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "out/f_%04d.bgeo"), &out), 0) << out;
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
    // The frames' times beside them (ParaView's collection): the scene's 50 fps.
    auto pvd = meniscus::readPvd(dir / "out/f.pvd");
    ASSERT_TRUE(pvd.ok()) << pvd.error().describe() << out;
    ASSERT_EQ(pvd->files.size(), 6u);
    EXPECT_EQ(pvd->files[5], dir / "out/f_0005.bgeo");
    auto rate = meniscus::frameRateOfInput(dir / "out/f.pvd");
    ASSERT_TRUE(rate.ok() && rate->has_value());
    EXPECT_NEAR(rate->value(), 50.0, 1e-6);
    // A folder of frames is still read as the frames alone.
    auto folder = meniscus::expandSequence((dir / "out").string());
    ASSERT_TRUE(folder.ok()) << folder.error().describe();
    EXPECT_EQ(folder->size(), 6u);
    // The other formats.
    for (const char* ext : {"vtk", "vtu", "ply"}) {
        ASSERT_EQ(runCli("simulate " + shellQuote(scene) + " -o " + shellQuote(dir / (std::string("g_%02d.") + ext)) + " --duration 0.02", &out), 0) << out;
        auto set = meniscus::readParticles(dir / (std::string("g_01.") + ext));
        ASSERT_TRUE(set.ok()) << set.error().describe();
        EXPECT_NE(set->find(meniscus::kAttrVelocity), nullptr) << ext;
    }
}

TEST(CliSimulate, SameFilesForAnyThreadCountAndResumeContinues) {
    const fs::path dir = tempDir();
    const fs::path scene = writeSmallScene(dir);
    std::string out;
    ASSERT_EQ(runCli("--threads 1 simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "a/f_%04d.bgeo"), &out), 0) << out;
    ASSERT_EQ(runCli("--threads 2 simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "b/f_%04d.bgeo"), &out), 0) << out;
    EXPECT_TRUE(readBytes(dir / "a/f_0005.bgeo") == readBytes(dir / "b/f_0005.bgeo"));
    // Frames 3..5 lost, and the solver's checkpoint is of frame 5: --resume
    // says it cannot use it and writes 3..5 from frame 2's particles.
    fs::remove(dir / "b/f_0003.bgeo"), fs::remove(dir / "b/f_0004.bgeo"), fs::remove(dir / "b/f_0005.bgeo");
    ASSERT_EQ(runCli("simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "b/f_%04d.bgeo") + " --resume", &out), 0) << out;
    EXPECT_NE(out.find("resuming after"), std::string::npos) << out;
    EXPECT_NE(out.find((dir / "b/.f.checkpoint").string() + ": not a usable checkpoint: it is of frame 5, after the last frame file (2)"),
              std::string::npos)
        << out;
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
    EXPECT_EQ(runCli("simulate " + shellQuote(dir / "typo.json") + " -o " + shellQuote(dir / "f_%04d.bgeo"), &out), 2);
    EXPECT_NE(out.find("typo.json"), std::string::npos) << out;
    EXPECT_NE(out.find("raduis"), std::string::npos) << out;
    EXPECT_EQ(runCli("simulate " + shellQuote(dir / "missing.json") + " -o " + shellQuote(dir / "f_%04d.bgeo"), &out), 1);
    const fs::path scene = writeSmallScene(dir);
    EXPECT_EQ(runCli("simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "nonumber.bgeo"), &out), 1);
    EXPECT_NE(out.find("frame number"), std::string::npos) << out;
    EXPECT_EQ(runCli("simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "f_%04d.png"), &out), 1);
    EXPECT_EQ(runCli("simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "f_%04d.bgeo") + " --solver magic", &out), 2);
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir)) files += e.path().extension() != ".json";
    EXPECT_EQ(files, 0u) << "nothing written";
}

// --render: one image per frame with the frame's number, all seen by one
// camera (framed on the tank, logged once): a pixel of empty tank far from
// the fluid is the same in every image, while the fluid's pixels change as
// the column falls. --resume renders the missing pictures and on from the
// resumed frame.
TEST(CliSimulate, RenderWritesAnImagePerFrameFromOneCamera) {
    const fs::path dir = tempDir();
    const fs::path scene = writeSmallScene(dir);
    std::string out;
    const std::string args = "simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "f/f_%04d.bgeo") + " --render " +
                             shellQuote(dir / "img/i_%04d.png") + " --width 96 --height 72 --shadows off";
    ASSERT_EQ(runCli(args, &out), 0) << out;  // (the falling column's shadow would sweep the empty tank)
    EXPECT_NE(out.find("one camera for all"), std::string::npos) << out;
    EXPECT_NE(out.find("and " + (dir / "img/i_0005.png").string()), std::string::npos) << out;
    std::vector<PngData> images;
    for (int k = 0; k <= 5; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "img/i_%04d.png", k);
        images.push_back(readPng(dir / name));
        ASSERT_EQ(images.back().width, 96) << name;
        ASSERT_EQ(images.back().height, 72) << name;
    }
    EXPECT_FALSE(fs::exists(dir / "img/i_0006.png"));
    // The column (x < 0.2 of the 0.4 m tank) starts on the left: the image's
    // right eighth is empty tank in every frame: the same pixels.
    const auto pixel = [](const PngData& png, int x, int y) {
        const std::size_t channels = PNG_IMAGE_PIXEL_CHANNELS(png.format);
        const std::size_t at = (std::size_t(y) * std::size_t(png.width) + std::size_t(x)) * channels;
        return std::vector<std::uint8_t>(png.bytes.begin() + std::ptrdiff_t(at),
                                         png.bytes.begin() + std::ptrdiff_t(at + channels));
    };
    for (std::size_t k = 1; k < images.size(); ++k)
        for (int y = 0; y < 72; ++y)
            for (int x = 84; x < 96; ++x)
                ASSERT_EQ(pixel(images[k], x, y), pixel(images[0], x, y)) << "frame " << k << ": the camera moved";
    std::size_t changed = 0;
    ASSERT_EQ(images[0].bytes.size(), images[5].bytes.size());
    for (std::size_t i = 0; i < images[0].bytes.size(); ++i) changed += images[0].bytes[i] != images[5].bytes[i];
    EXPECT_GT(changed, 100u) << "the fluid moved between frame 0 and frame 5";

    // Interrupted after frame 2, frame 1's picture lost: --resume renders the
    // missing picture from frame 1's particles (the same bytes), and writes
    // and renders frames 3..5.
    const auto picture1 = readBytes(dir / "img/i_0001.png");
    const auto time0 = fs::last_write_time(dir / "img/i_0000.png");
    for (int k = 3; k <= 5; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "f/f_%04d.bgeo", k);
        fs::remove(dir / name);
        std::snprintf(name, sizeof name, "img/i_%04d.png", k);
        fs::remove(dir / name);
    }
    fs::remove(dir / "img/i_0001.png");
    ASSERT_EQ(runCli(args + " --resume", &out), 0) << out;
    EXPECT_TRUE(fs::exists(dir / "img/i_0005.png"));
    EXPECT_TRUE(readBytes(dir / "img/i_0001.png") == picture1) << "the missing picture, as the whole run drew it";
    EXPECT_EQ(fs::last_write_time(dir / "img/i_0000.png"), time0) << "complete pictures are not rendered again";
    EXPECT_NE(out.find("rendered the missing " + (dir / "img/i_0001.png").string()), std::string::npos) << out;
}

// `render` takes a simulation scene as its input, directly or as a render
// scene file's "particles": it simulates the scene and writes the same images
// `simulate --render` does, frame for frame (the same camera on the tank, the
// same radius); a movie has a frame per simulated frame at the scene's fps.
TEST(CliSimulate, RenderTakesASimulationSceneAsItsParticles) {
    const fs::path dir = tempDir();
    const fs::path scene = writeSmallScene(dir);
    std::string out;
    const std::string size = " --width 64 --height 48 --backend cpu";
    ASSERT_EQ(runCli("simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "f/f_%04d.bgeo") + " --render " +
                         shellQuote(dir / "sim/i_%04d.png") + size,
                     &out),
              0)
        << out;
    fs::create_directories(dir / "ren");
    fs::create_directories(dir / "look");
    ASSERT_EQ(runCli("render " + shellQuote(scene) + " -o " + shellQuote(dir / "ren/i_%02d.png") + size, &out), 0)
        << out;
    EXPECT_NE(out.find("simulating"), std::string::npos) << out;
    for (int k = 0; k <= 5; ++k) {
        char a[32], b[32];
        std::snprintf(a, sizeof a, "sim/i_%04d.png", k);
        std::snprintf(b, sizeof b, "ren/i_%02d.png", k);
        const PngData x = readPng(dir / a), y = readPng(dir / b);
        ASSERT_FALSE(x.bytes.empty()) << a;
        EXPECT_EQ(x.bytes, y.bytes) << b << " differs from " << a;
    }
    EXPECT_FALSE(fs::exists(dir / "ren/i_06.png"));
    // --duration: how long the simulation runs (a frame every 1/fps), as
    // simulate's; particle files refuse it.
    ASSERT_EQ(runCli("render " + shellQuote(scene) + " -o " + shellQuote(dir / "dur/d_%02d.png") + " --duration 0.04" +
                         size,
                     &out),
              0)
        << out;
    EXPECT_EQ(readPng(dir / "dur/d_02.png").bytes, readPng(dir / "sim/i_0002.png").bytes);
    EXPECT_FALSE(fs::exists(dir / "dur/d_03.png"));
    EXPECT_EQ(runCli("render " + shellQuote(dir / "f/f_0001.bgeo") + " -o " + shellQuote(dir / "x.png") +
                         " --duration 1" + size,
                     &out),
              2);
    EXPECT_NE(out.find("--duration: sets how long a simulation scene runs"), std::string::npos) << out;

    // The same through a render scene file naming the simulation as its particles.
    writeText(dir / "look.json", R"({"particles": "small.json", "render": {"width": 64, "height": 48,
                                     "backend": "cpu"}, "output": "look/l_%02d.png"})");
    ASSERT_EQ(runCli("render " + shellQuote(dir / "look.json"), &out), 0) << out;
    EXPECT_EQ(readPng(dir / "look/l_05.png").bytes, readPng(dir / "sim/i_0005.png").bytes);
    // Not a simulation: the scene reader's error, naming the file.
    writeText(dir / "bad.json", R"({"domain": {"min": [0, 0, 0]}})");
    EXPECT_NE(runCli("render " + shellQuote(dir / "bad.json") + " -o " + shellQuote(dir / "x.png"), &out), 0);
    EXPECT_NE(out.find("bad.json"), std::string::npos) << out;
    // --select picks particles of files: with a simulation it is an error, not ignored.
    EXPECT_EQ(runCli("render " + shellQuote(scene) + " -o " + shellQuote(dir / "s_%02d.png") + " --select 'density>0'" + size,
                     &out),
              2);
    EXPECT_NE(out.find("--select"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "s_00.png"));
}

// A bad --render pattern is an error before anything is simulated or written.
TEST(CliSimulate, BadRenderPatternsFailBeforeSimulating) {
    const fs::path dir = tempDir();
    const fs::path scene = writeSmallScene(dir);
    std::string out;
    for (const char* bad : {"img/i.png", "img/i_%04d.jpg"}) {
        EXPECT_EQ(runCli("simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "f/f_%04d.bgeo") + " --render " +
                             shellQuote(dir / bad),
                         &out),
                  1)
            << bad;
        EXPECT_NE(out.find(bad), std::string::npos) << out;
    }
    EXPECT_FALSE(fs::exists(dir / "f")) << "nothing simulated";
    EXPECT_FALSE(fs::exists(dir / "img"));
}

// An emitter scene's first frame has no particles: --resume from it (a run
// interrupted at once) reads the empty frame back and goes on emitting, to
// the same frames as a straight run (nothing to warm-start at t = 0).
TEST(CliSimulate, ResumeFromAnEmptyFrame) {
    const fs::path dir = tempDir();
    const fs::path scene = dir / "nozzle.json";
    std::ofstream(scene) << R"({
  "version": 1, "name": "nozzle", "duration": 0.06, "fps": 50,
  "params": { "radius": 0.01 },
  "domain": { "min": [0, 0, 0], "max": [0.3, 0.3, 0.3] },
  "emitters": [ { "position": [0.15, 0.25, 0.15], "direction": [0, -1, 0], "radius": 0.03, "speed": 1.0 } ]
})";
    std::string out;
    ASSERT_EQ(runCli("simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "a/f_%04d.bgeo"), &out), 0) << out;
    ASSERT_EQ(runCli("simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "b/f_%04d.bgeo") + " --duration 0", &out), 0)
        << out;
    ASSERT_TRUE(fs::exists(dir / "b/f_0000.bgeo"));
    ASSERT_FALSE(meniscus::readParticles(dir / "b/f_0000.bgeo").ok()) << "the frame is empty";
    // Without the solver's checkpoint (tested below), from the particle file.
    ASSERT_TRUE(fs::remove(dir / "b/.f.checkpoint"));
    ASSERT_EQ(runCli("simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "b/f_%04d.bgeo") + " --resume", &out), 0) << out;
    EXPECT_NE(out.find("resuming after"), std::string::npos) << out;
    auto resumed = meniscus::readParticles(dir / "b/f_0003.bgeo");
    auto straight = meniscus::readParticles(dir / "a/f_0003.bgeo");
    ASSERT_TRUE(resumed.ok()) << resumed.error().describe();
    ASSERT_TRUE(straight.ok()) << straight.error().describe();
    EXPECT_GT(straight->size(), 0u);
    EXPECT_EQ(resumed->size(), straight->size());
    EXPECT_TRUE(readBytes(dir / "a/f_0003.bgeo") == readBytes(dir / "b/f_0003.bgeo"));
}

// A nozzle, a drain and a lifetime (ids, ages, the emitter's clock, removals,
// z-order re-sorts and DFSPH's warm start all carry over): stopped by
// --duration after frame 3, --resume with the scene's duration goes on from
// the solver's checkpoint (.f.checkpoint) and every frame has the bytes of a
// run never stopped. A damaged checkpoint is said, naming it, and resume
// falls back to the last particle file.
TEST(CliSimulate, ResumeFromTheCheckpointIsExactWithAnEmitter) {
    const fs::path dir = tempDir();
    const fs::path scene = dir / "nozzle.json";
    std::ofstream(scene) << R"({
  "version": 1, "name": "nozzle", "duration": 0.16, "fps": 50,
  "params": { "radius": 0.01, "lifetime": 0.1 },
  "domain": { "min": [0, 0, 0], "max": [0.3, 0.3, 0.3] },
  "fluid": [ { "box": { "min": [0, 0, 0], "max": [0.3, 0.05, 0.3] } } ],
  "emitters": [ { "position": [0.15, 0.25, 0.15], "direction": [0, -1, 0], "radius": 0.03, "speed": 1.0 } ],
  "drains": [ { "box": { "min": [0, 0, 0], "max": [0.05, 0.3, 0.05] } } ]
})";
    const auto run = [&](const std::string& where, const std::string& more) {
        return "simulate " + shellQuote(scene) + " -o " + shellQuote(dir / where / "f_%04d.bgeo") + more;
    };
    std::string out;
    ASSERT_EQ(runCli(run("a", ""), &out), 0) << out;
    ASSERT_EQ(runCli(run("b", " --duration 0.06"), &out), 0) << out;
    ASSERT_TRUE(fs::exists(dir / "b/.f.checkpoint"));
    ASSERT_FALSE(fs::exists(dir / "b/f_0004.bgeo"));
    ASSERT_EQ(runCli(run("b", " --resume"), &out), 0) << out;
    EXPECT_NE(out.find("resuming exactly after frame 3"), std::string::npos) << out;
    for (int k = 0; k <= 8; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "f_%04d.bgeo", k);
        EXPECT_TRUE(readBytes(dir / "a" / name) == readBytes(dir / "b" / name)) << name << " differs";
    }
    EXPECT_TRUE(readBytes(dir / "a/f.pvd") == readBytes(dir / "b/f.pvd"));
    // A checkpoint cut short: said, and the run goes on from the particle file.
    ASSERT_EQ(runCli(run("c", " --duration 0.06"), &out), 0) << out;
    const auto whole = readBytes(dir / "c/.f.checkpoint");
    writeBytes(dir / "c/.f.checkpoint", std::vector<std::uint8_t>(whole.begin(), whole.begin() + std::ptrdiff_t(whole.size() / 2)));
    ASSERT_EQ(runCli(run("c", " --resume"), &out), 0) << out;
    EXPECT_NE(out.find("warning: " + (dir / "c/.f.checkpoint").string() + ": not a usable checkpoint"), std::string::npos) << out;
    EXPECT_NE(out.find("resuming after " + (dir / "c/f_0003.bgeo").string()), std::string::npos) << out;
    EXPECT_TRUE(fs::exists(dir / "c/f_0008.bgeo"));
}
}  // namespace cli_simulate_test_local
