// The CLI's own parts that the viewer is built on, without a window: its look
// held as `render`'s options (reparsed, the changes printed, saved as a scene
// file and read back) and its frame reader on a worker thread.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <set>
#include <thread>

#include <nlohmann/json.hpp>

#include "frame_prefetch.h"
#include "scene_save.h"
#include "test_util.h"
#include "view_ui.h"

namespace cli_parts_test_local {

using namespace meniscus;
using namespace meniscus::app;
using namespace meniscus::test;

// Every option of the library's tables has a text, the flags true or false.
TEST(SceneSave, EveryOptionHasItsText) {
    const RenderJob options;  // named: GCC 12 warns (falsely) of an uninitialised string in a temporary
    const auto texts = optionTexts(options);
    ASSERT_GT(texts.size(), 40u);
    std::set<std::string> names;
    for (const auto& [name, text] : texts) {
        EXPECT_NE(text, "?") << name << ": a flag scene_save.cpp does not know";
        names.insert(name);
    }
    for (const char* name : {"--filter", "--iterations", "--material", "--opacity", "--noise", "--anisotropy", "--light"})
        EXPECT_TRUE(names.count(name)) << name;
}

// The panels' values are checked as the command line checks them: what it
// accepts is kept as it is, what it refuses is an error naming the option.
TEST(SceneSave, ReparsedIsWhatTheCommandLineReads) {
    RenderJob o;
    o.iterations = 3;
    o.stages.noise.enabled = true;
    o.opacity = 0.123456789f;
    o.fluidColor = glm::vec3(0.1f, 0.2f, 0.3f);
    o.anisotropy = "off";
    o.filter = "bilateral";
    auto r = reparsed(o);
    ASSERT_TRUE(r) << r.error().describe();
    EXPECT_EQ(r->iterations, 3);
    EXPECT_TRUE(r->stages.noise.enabled);
    EXPECT_FALSE(r->stages.whitening.enabled);
    EXPECT_EQ(r->opacity, 0.123456789f);  // typed: nothing goes through text
    EXPECT_EQ(r->fluidColor, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_EQ(r->anisotropy, "off");
    EXPECT_EQ(r->filter, "bilateral");
    EXPECT_TRUE(std::isnan(r->ior));  // not given: still the preset's

    RenderJob bad;
    bad.opacity = 2.0f;
    auto refused = reparsed(bad);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("--opacity"), std::string::npos) << refused.error().message;
}

TEST(SceneSave, ChangedOptionsAreCommandLineWords) {
    RenderJob a, b;
    b.iterations = 3;
    b.stages.noise.enabled = true;
    b.material = "milk";
    const auto changed = changedOptions(a, b);
    EXPECT_EQ(changed, (std::vector<std::string>{"--iterations 3", "--material milk", "--noise"}));
    EXPECT_EQ(changedOptions(b, a), (std::vector<std::string>{"--iterations -1", "--material water", "--noise=false"}));
    EXPECT_TRUE(changedOptions(a, a).empty());
}

// Saved and read back: the same options, the camera's eye and target (in the
// data's frame, here z-up), the particles relative to the file.
TEST(SceneSave, ASavedSceneReadsBackAsTheSameOptions) {
    const auto dir = tempDir();
    std::filesystem::create_directories(dir / "data");
    std::filesystem::copy_file(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"), dir / "data" / "f.bgeo");
    const std::string frame = (dir / "data" / "f.bgeo").string();
    RenderJob o;
    o.input = frame;
    o.up = {0.0f, 0.0f, 1.0f};
    o.iterations = 2;
    o.stages.spray.enabled = true;
    o.material = "milk";
    o.opacity = 0.25f;
    o.select = "density>500 && velocity.y<0";
    Camera cam;
    cam.eye = {1.0f, 2.0f, 3.0f};
    cam.target = {0.5f, 0.25f, -0.5f};
    cam.fovYDegrees = 35.0f;
    cam.width = 320;
    cam.height = 200;
    const std::string path = (dir / "sub" / "scene.json").string();
    std::filesystem::create_directories(dir / "sub");
    ASSERT_TRUE(saveSceneFile(path, o, cam));
    std::ifstream in(path);
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["particles"], "../data/f.bgeo") << "relative to the scene file";
    EXPECT_EQ(j["render"]["iterations"], 2);
    EXPECT_EQ(j["render"]["spray"], true);
    EXPECT_FALSE(j["render"].contains("filter")) << "defaults are left out: " << j.dump();

    auto back = loadSceneFile(path);
    ASSERT_TRUE(back) << back.error().describe();
    EXPECT_EQ(std::filesystem::weakly_canonical(back->input), std::filesystem::weakly_canonical(frame));
    EXPECT_EQ(back->iterations, 2);
    EXPECT_TRUE(back->stages.spray.enabled);
    EXPECT_EQ(back->material, "milk");
    EXPECT_EQ(back->opacity, 0.25f);
    EXPECT_EQ(back->select, "density>500 && velocity.y<0") << "the selection is part of the scene";
    EXPECT_EQ(back->width, 320);
    EXPECT_EQ(back->height, 200);
    EXPECT_EQ(back->fov, 35.0f);
    // z-up data: the renderer's (x, y, z) is the data's (x, -z, y).
    ASSERT_TRUE(back->eye && back->target);
    const glm::vec3 e = *back->eye, t = *back->target;
    EXPECT_NEAR(e[0], 1.0f, 1e-5f);
    EXPECT_NEAR(e[1], -3.0f, 1e-5f);
    EXPECT_NEAR(e[2], 2.0f, 1e-5f);
    EXPECT_NEAR(t[1], 0.5f, 1e-5f);
    EXPECT_NEAR(t[2], 0.25f, 1e-5f);
    auto up = upRotation(back->up);
    ASSERT_TRUE(up);
    const glm::vec3 eyeBack = up->apply(glm::vec3(e[0], e[1], e[2]));
    EXPECT_NEAR(glm::distance(eyeBack, cam.eye), 0.0f, 1e-5f);

    // Sharing no more than the root with the scene file's folder: absolute.
    o.input = "/nonexistent_top/f.bgeo";
    ASSERT_TRUE(saveSceneFile(path, o, cam));
    std::ifstream again(path);
    EXPECT_EQ(nlohmann::json::parse(again)["particles"], "/nonexistent_top/f.bgeo");

    const RenderJob options;  // named, as above
    EXPECT_FALSE(saveSceneFile((dir / "demo.json").string(), options, cam)) << "the demo frame has no file";
    EXPECT_FALSE(std::filesystem::exists(dir / "demo.json"));
}

TEST(SceneSave, ABadSceneFileIsAnErrorNamingTheKey) {
    const auto dir = tempDir();
    writeText(dir / "bad.json", R"({"particles": "x.bgeo", "render": {"iterations": -4}})");
    auto r = loadSceneFile((dir / "bad.json").string());
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().describe().find("render.iterations"), std::string::npos) << r.error().describe();
}

// The reader gives each frame as Frames::load does, reads ahead of the one
// wanted, and forgets frames behind it.
TEST(FramePrefetch, ReadsAheadTheFramesLoadGives) {
    auto frames = openFrames((testData("splishsplash/partio") / "ParticleData_Fluid_*.bgeo").string(), nullptr);
    ASSERT_TRUE(frames);
    ASSERT_EQ(frames->count(), 4u);
    std::vector<ParticleSet> direct;
    for (std::size_t i = 0; i < 4; ++i) direct.push_back(*frames->load(i));
    std::atomic<int> ready{0};
    FramePrefetch prefetch(*frames, [&] { ++ready; }, 2);
    const FramePrefetch::Loaded f2 = prefetch.wait(2);
    ASSERT_TRUE(f2.set) << f2.error;
    EXPECT_EQ(f2.set->positions, direct[2].positions);
    // Frames 3 and 0 (wrapping) come next without being asked for.
    for (std::size_t i : {std::size_t(3), std::size_t(0)}) {
        for (int t = 0; t < 2000 && !prefetch.get(i); ++t) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        auto f = prefetch.get(i);
        ASSERT_TRUE(f) << "frame " << i << " was not read ahead";
        EXPECT_EQ(f->set->positions, direct[i].positions);
    }
    EXPECT_FALSE(prefetch.get(1)) << "frame 1 is behind the window";
    EXPECT_GE(ready.load(), 3);
    EXPECT_EQ(prefetch.wait(1).set->positions, direct[1].positions);
}

TEST(FramePrefetch, AFrameThatCannotBeReadIsAnErrorNotACrash) {
    const auto dir = tempDir();
    std::filesystem::copy_file(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"), dir / "f_0001.bgeo");
    writeText(dir / "f_0002.bgeo", "not a bgeo file");
    auto frames = openFrames((dir / "f_*.bgeo").string(), nullptr);
    ASSERT_TRUE(frames);
    FramePrefetch prefetch(*frames, nullptr);
    EXPECT_TRUE(prefetch.wait(0).set);
    const FramePrefetch::Loaded bad = prefetch.wait(1);
    EXPECT_FALSE(bad.set);
    EXPECT_NE(bad.error.find("f_0002.bgeo"), std::string::npos) << bad.error;
}

// `meniscus render`'s use: no wrapping, the caller's first frame not read
// again, each frame taken (the same particles and errors as Frames gives)
// with at most `ahead` frames read beside it, none past the last.
TEST(FramePrefetch, TakesASequenceOnceInOrder) {
    const auto dir = tempDir();
    for (int i : {1, 2, 4})
        std::filesystem::copy_file(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"),
                                   dir / ("f_000" + std::to_string(i) + ".bgeo"));
    writeText(dir / "f_0003.bgeo", "not a bgeo file");
    auto frames = openFrames((dir / "f_*.bgeo").string(), nullptr);
    ASSERT_TRUE(frames);
    ASSERT_EQ(frames->count(), 4u);
    const ParticleSet direct = *frames->loadChecked(1);
    const Error bad = frames->loadChecked(2).error();
    std::atomic<int> reads{0};
    FramePrefetch prefetch(*frames, [&] { ++reads; }, 1, nullptr, 0, false);
    auto f1 = prefetch.take(1);  // frame 0 is the caller's: not read
    ASSERT_TRUE(f1) << f1.error().describe();
    EXPECT_EQ(f1->positions, direct.positions);
    for (int t = 0; t < 2000 && !prefetch.get(2); ++t) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    EXPECT_TRUE(prefetch.get(2)) << "frame 2 was not read ahead";
    EXPECT_FALSE(prefetch.get(1)) << "frame 1 was taken: not kept, not read again";
    EXPECT_FALSE(prefetch.get(3)) << "more than one frame ahead";
    auto f2 = prefetch.take(2);
    ASSERT_FALSE(f2);
    EXPECT_EQ(f2.error().describe(), bad.describe());
    EXPECT_EQ(f2.error().usage, bad.usage);
    EXPECT_TRUE(prefetch.take(3));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    EXPECT_EQ(reads.load(), 3) << "frames 1, 2, 3: not frame 0, nor any frame twice or past the end";
}

// The viewer's timeline counts as the files do: SPlisHSPlasH's frames are
// numbered from 1, so the third file of a sequence reads "3 (3 of 60)", and a
// file with no number shows its place alone.
TEST(ViewerTimeline, NumbersFramesAsTheFilesDo) {
    EXPECT_EQ(timelineLabel(2, 60, 3), "3 (3 of 60)");
    EXPECT_EQ(timelineLabel(0, 5, 21), "21 (1 of 5)");
    EXPECT_EQ(timelineLabel(4, 5, -1), "5 of 5");
    EXPECT_EQ(timelineLabel(0, 2, 0), "0 (1 of 2)");
    EXPECT_EQ(timelineLabel(1, 3, frameNumberOf("out/ParticleData_Fluid_21.bgeo")), "21 (2 of 3)");
}
}  // namespace cli_parts_test_local
