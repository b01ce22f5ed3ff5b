// The stage list (src/render/stages.cpp): every stage a frame runs is
// declared there, in the order it runs, and its check refuses what the
// pipeline would.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "meniscus/renderer.h"
#include "render/stages.h"
#include "test_util.h"

namespace stages_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

// The declared name of a timing line ("fluid 1: smooth" -> "smooth").
std::string declaredName(const std::string& timing) {
    const std::size_t colon = timing.find(": ");
    return colon == std::string::npos ? timing : timing.substr(colon + 2);
}

std::size_t declaredAt(const std::string& name) {
    const auto stages = frameStages();
    for (std::size_t i = 0; i < stages.size(); ++i)
        if (stages[i].name == name) return i;
    return stages.size();
}

}  // namespace

TEST(StageList, NamesAreUniqueAndDeclared) {
    std::set<std::string> names;
    for (const StageDecl& s : frameStages()) {
        EXPECT_TRUE(names.insert(s.name).second) << s.name << " declared twice";
        EXPECT_NE(std::string(s.reads), "") << s.name;
        EXPECT_NE(std::string(s.writes), "") << s.name;
        ASSERT_NE(s.runs, nullptr) << s.name;
    }
}

// Every timing line of a frame (the stages that ran) names a declared stage
// that says it runs for these settings, in the declared order.
TEST(StageList, WhatRunsIsDeclaredInItsOrder) {
    const ParticleSet& set = smallFrame21();
    RenderSettings base = autoFramedSettings(set, 96, 64);
    std::vector<RenderSettings> cases(4, base);
    cases[1].noise.enabled = true, cases[1].whitening.enabled = true, cases[1].silhouette.enabled = true;
    cases[2].fluidScale = 0.5f;
    cases[3].raycast.enabled = true, cases[3].spray.enabled = true, cases[3].anisotropy.enabled = true;
    for (std::size_t c = 0; c < cases.size(); ++c) {
        Renderer renderer;
        std::vector<StageTime> timings;
        auto aovs = renderer.render(ParticleView::of(set), cases[c], &timings);
        ASSERT_TRUE(aovs) << aovs.error().describe();
        ASSERT_FALSE(timings.empty());
        std::size_t last = 0;
        for (const StageTime& t : timings) {
            const std::string name = declaredName(t.stage);
            const std::size_t at = declaredAt(name);
            ASSERT_LT(at, frameStages().size()) << "case " << c << ": " << name << " runs but is not declared";
            EXPECT_TRUE(frameStages()[at].runs(StageWhen{cases[c]})) << "case " << c << ": " << name << " ran; its runs() says no";
            EXPECT_GE(at, last) << "case " << c << ": " << name << " ran out of the declared order";
            last = at;
        }
    }
}

// The checks are the pipeline's: a setting a check refuses, the render refuses with the same words.
TEST(StageList, ChecksAreWhatTheRenderRefuses) {
    const ParticleSet& set = smallFrame21();
    RenderSettings s = autoFramedSettings(set, 96, 64);
    EXPECT_TRUE(checkStages(s));
    s.view = View::Silhouette;  // a view of a stage that is off
    const Status refused = checkStages(s);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("silhouette"), std::string::npos) << refused.error().message;
    Renderer renderer;
    auto aovs = renderer.render(ParticleView::of(set), s);
    ASSERT_FALSE(aovs);
    EXPECT_EQ(aovs.error().message, refused.error().message);
    s.view = View::Final;
    s.fluidScale = 0.3f;
    ASSERT_FALSE(checkStages(s));
    EXPECT_NE(checkStages(s).error().message.find("fluidScale"), std::string::npos);
}

// A stage that draws has its CPU driver (the GL one: gl_backend_test), or is
// the host's work alone (the compositor's combination); the host's own
// stages have their host work instead, and the read-back is the Renderer's.
TEST(StageList, EveryImageStageHasItsCpuDriver) {
    for (const StageDecl& s : frameStages()) {
        if (s.scope == StageScope::Host || s.scope == StageScope::Readback) {
            EXPECT_EQ(s.cpu, nullptr) << s.name;
            EXPECT_EQ(s.run, nullptr) << s.name;
            // The host's work is its own stage's: none left in the Renderer's frame.
            EXPECT_EQ(s.host != nullptr, s.scope == StageScope::Host) << s.name;
            continue;
        }
        EXPECT_EQ(s.host, nullptr) << s.name;
        if (!s.cpu) {
            EXPECT_NE(s.run, nullptr) << s.name << " has neither a driver nor host work";
            continue;
        }
        EXPECT_NE(s.cpu->run, nullptr) << s.name;
    }
}

// runStage runs one stage by name (as a test of a stage on its own does),
// and refuses a name that is not in the list.
TEST(StageList, RunStageByName) {
    const ParticleSet& set = smallFrame21();
    const RenderSettings s = autoFramedSettings(set, 48, 32);
    const std::unique_ptr<Backend> cpu = makeCpuBackend();
    FrameSettings f;
    f.camera = s.camera;
    f.radius = s.radiusM;
    ASSERT_TRUE(cpu->beginFrame(set.positions, f));
    ASSERT_TRUE(runStage(*cpu, "scene", {}));
    ASSERT_TRUE(runStage(*cpu, "depth-splat+thickness", {}));
    const Image<float> raw = cpu->readScalar(Slot::RawDepth);
    int covered = 0;
    for (float z : raw.pixels) covered += std::isfinite(z) && z > 0.0f;
    EXPECT_GT(covered, 100);
    const Status unknown = runStage(*cpu, "no-such-stage", {});
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.error().message.find("no-such-stage"), std::string::npos);
}
}  // namespace stages_test_local
