// The option table (include/meniscus/options.h): every row complete, typed
// values set and refused as the faces need, the policies said once.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "meniscus/options.h"
#include "meniscus/particles.h"
#include "meniscus/sim.h"

namespace options_test_local {

using namespace meniscus;

TEST(OptionTable, EveryRowIsCompleteAndNamedOnce) {
    std::set<std::string> names;
    RenderOptions o;
    for (const RenderOptionSpec& s : renderOptionTable()) {
        EXPECT_TRUE(names.insert(s.name).second) << s.name << " twice";
        EXPECT_FALSE(s.help.empty()) << s.name;
        EXPECT_NE(std::string(optionGroupTitle(s.group)), "") << s.name;
        EXPECT_EQ(s.name.find('_'), std::string::npos) << s.name << ": the CLI spelling uses '-'";
        ASSERT_NE(s.field, nullptr) << s.name;
        // Each default is one its own checks accept (a sentinel needs noDefault or no limits).
        EXPECT_TRUE(checkOption(s, o)) << s.name;
        if (s.flag) {
            EXPECT_TRUE(std::holds_alternative<bool*>(s.field(o))) << s.name;
        }
    }
    MesherOptions m;
    for (const MesherOptionSpec& s : mesherOptionTable()) {
        EXPECT_TRUE(names.insert(s.name).second) << s.name << " in both tables";
        EXPECT_TRUE(checkOption(s, m)) << s.name;
    }
    for (const char* name : {"width", "filter", "iterations", "material", "noise", "anisotropy", "light", "surface",
                             "cube-size", "iso", "h-per-spacing", "fluid-scale"})
        EXPECT_TRUE(names.count(name)) << name;
}

// Each row's field is the one its name says: setting it by name changes that field alone.
TEST(OptionTable, RowsLandInTheirFields) {
    RenderOptions o;
    ASSERT_TRUE(setRenderOption(o, "noise_bump", 0.75));
    EXPECT_EQ(o.stages.noise.bump, 0.75f);
    ASSERT_TRUE(setRenderOption(o, "anisotropy-neighbours", std::int64_t(12)));
    EXPECT_EQ(o.anisotropyParams.minNeighbours, 12);
    ASSERT_TRUE(setRenderOption(o, "cube_size", 1.5));
    EXPECT_EQ(o.mesher.cubeSize, 1.5f);
    ASSERT_TRUE(setRenderOption(o, "up", glm::vec3(0, 0, 1)));
    EXPECT_EQ(o.up, glm::vec3(0, 0, 1));
    ASSERT_TRUE(setRenderOption(o, "light", std::string("1,2,3")));  // the text a hand-written file may hold
    EXPECT_EQ(o.light, std::optional<glm::vec3>(glm::vec3(1, 2, 3)));
    ASSERT_TRUE(setRenderOption(o, "eye", glm::vec3(1, 2, 3)));
    ASSERT_TRUE(o.eye.has_value());
    EXPECT_EQ(*o.eye, glm::vec3(1, 2, 3));
    ASSERT_TRUE(setRenderOption(o, "anisotropy", false));  // on/off takes a bool too
    EXPECT_EQ(o.anisotropy, "off");
    ASSERT_TRUE(setRenderOption(o, "noise", true));
    EXPECT_TRUE(o.stages.noise.enabled);
    ASSERT_TRUE(setRenderOption(o, "iterations", 3.0));  // a whole float is a whole number
    EXPECT_EQ(o.iterations, 3);
    // Everything else is still its default.
    RenderOptions fresh;
    EXPECT_EQ(o.width, fresh.width);
    EXPECT_EQ(o.stages.noise.frequency, fresh.stages.noise.frequency);
    EXPECT_EQ(o.mesher.iso, fresh.mesher.iso);
}

TEST(OptionTable, WrongValuesAreRefusedNamingTheOption) {
    RenderOptions o;
    const auto refused = [&](const char* name, const OptionValue& v, const char* says) {
        const RenderOptions before = o;
        const Status st = setRenderOption(o, name, v);
        ASSERT_FALSE(st) << name;
        EXPECT_NE(st.error().message.find(says), std::string::npos) << st.error().message;
        EXPECT_NE(st.error().message.find("--"), std::string::npos) << st.error().message;
        EXPECT_EQ(o.width, before.width);  // unchanged on an error
    };
    refused("width", std::int64_t(0), "in [1, 16384]");
    refused("width", 2.5, "whole number");
    refused("noise", std::int64_t(1), "true or false");
    refused("opacity", 2.0, "in [0, 1]");
    refused("filter", std::string("blur"), "expected one of");
    refused("anisotropy", std::string("yes"), "expected on or off");
    refused("eye", 1.0, "three numbers");
    refused("fluid-color", glm::vec3(2, 0, 0), "in [0, 1]");
    refused("h-per-spacing", 0.0, "positive");
    refused("field", std::string("vdb"), "sph or thesis");
    const Status unknown = setRenderOption(o, "colour", 1.0);
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.error().message.find("noise_bump"), std::string::npos) << "lists the names";
}

TEST(OptionTable, DefaultTextsAreTheFieldsDefaults) {
    EXPECT_EQ(defaultText(*findRenderOption("width")), std::to_string(defaults::kWidth));
    EXPECT_EQ(defaultText(*findRenderOption("up")), "0,1,0");
    EXPECT_EQ(defaultText(*findRenderOption("iterations")), "");  // a sentinel, not shown
    EXPECT_EQ(defaultText(*findRenderOption("noise")), "false");
    EXPECT_EQ(defaultText(*findMesherOption("cube_size")), "0.5");
    EXPECT_EQ(keywordName("noise-bump"), "noise_bump");
    EXPECT_EQ(findRenderOption("noise_bump"), findRenderOption("noise-bump"));
}

// Blender's frame names: the last run of '#' is the frame number, padded to
// the run's length (longer numbers keep every digit).
TEST(BackdropSequence, TheLastRunOfHashesIsTheFrameNumber) {
    EXPECT_EQ(backdropFrameName("set_####.exr", 7), "set_0007.exr");
    EXPECT_EQ(backdropFrameName("a#/set_##.exr", 12345), "a#/set_12345.exr");
    EXPECT_EQ(backdropFrameName("##_frame.exr", 0), "00_frame.exr");
    EXPECT_EQ(backdropFrameName("set.exr", 3), "set.exr");
    RenderOptions o;
    EXPECT_FALSE(backdropSequence(o));
    o.backdrop = "set.png";
    EXPECT_FALSE(backdropSequence(o));
    o.backdropDepth = "z_###.exr";
    EXPECT_TRUE(backdropSequence(o));
}

TEST(RenderSettingsFromOptions, TheDefaultsAreTheLibrarysDefaults) {
    const RenderOptions defaults;  // (a named object: GCC 12 misreads a temporary's strings as uninitialised)
    auto s = renderSettings(defaults);
    ASSERT_TRUE(s) << s.error().describe();
    const RenderSettings plain;
    EXPECT_EQ(s->view, plain.view);
    EXPECT_EQ(s->anisotropy.enabled, AnisotropyParams{}.enabled);
    EXPECT_EQ(s->holeFill.maxSpanRadii, plain.holeFill.maxSpanRadii);
    EXPECT_TRUE(s->particleRadii) << "no radius given: the file's own radii are drawn";
    EXPECT_EQ(s->fluidMaterials.size(), 1u);
    RenderOptions two;
    two.material = "water,lava";
    two.opacity = 0.5f;
    auto t = renderSettings(two);
    ASSERT_TRUE(t);
    ASSERT_EQ(t->fluidMaterials.size(), 2u);
    EXPECT_EQ(t->fluidMaterials[1].opacity, 0.5f) << "custom values go over every fluid's preset";
    RenderOptions view;
    view.view = "foam";
    auto refused = renderSettings(view);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("add --noise"), std::string::npos) << refused.error().message;
}

TEST(ResolveRadius, GivenEstimatedOrRefused) {
    int estimated = 0;
    const auto estimate = [&] {
        ++estimated;
        RadiusEstimate e;
        e.radius = 0.02f;
        e.method = RadiusMethod::BulkDensity;
        return e;
    };
    std::string note;
    auto given = resolveRadius(0.05f, estimate, &note);
    ASSERT_TRUE(given);
    EXPECT_EQ(*given, 0.05f);
    EXPECT_EQ(estimated, 0) << "a given radius is not estimated";
    EXPECT_TRUE(note.empty());
    auto guessed = resolveRadius(0.0f, estimate, &note);
    ASSERT_TRUE(guessed);
    EXPECT_EQ(*guessed, 0.02f);
    EXPECT_NE(note.find("radius"), std::string::npos) << note;
    EXPECT_FALSE(resolveRadius(-1.0f, estimate));
    const auto tiny = [] {
        RadiusEstimate e;
        e.radius = 1e-30f;
        return e;
    };
    auto bad = resolveRadius(0.0f, tiny);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("set --radius"), std::string::npos) << bad.error().message;
}

TEST(UpRotation, TurnsTheUpAxisToYAndBack) {
    auto z = upRotation({0, 0, 1});
    ASSERT_TRUE(z);
    const glm::vec3 up = z->apply({0, 0, 1});
    EXPECT_NEAR(up.y, 1.0f, 1e-6f);
    const glm::vec3 back = z->inverse().apply(up);
    EXPECT_NEAR(back.z, 1.0f, 1e-6f);
    EXPECT_FALSE(upRotation({0, 0, 0}));
    EXPECT_TRUE(upRotation({0, 1, 0})->identity);
}

// The job's table: lists, doubles and the "not given" values, as the scene files and the CLI set them.
TEST(OptionTable, TheJobsOptions) {
    JobOptions o;
    ASSERT_TRUE(setJobOption(o, "fluid", std::vector<std::string>{"oil_%04d.bgeo", "air_%04d.bgeo"}));
    EXPECT_EQ(o.moreFluids.size(), 2u);
    ASSERT_TRUE(setJobOption(o, "fluid", std::string("one.bgeo")));  // one text: a list of one
    EXPECT_EQ(o.moreFluids, std::vector<std::string>{"one.bgeo"});
    ASSERT_TRUE(setJobOption(o, "fps", std::int64_t(15)));
    EXPECT_EQ(o.fps, 15.0);
    EXPECT_FALSE(setJobOption(o, "fps", 0.0)) << "out of [0.001, 1000]";
    EXPECT_FALSE(setJobOption(o, "on-error", std::string("retry")));
    EXPECT_FALSE(setJobOption(o, "frames", std::int64_t(-3)));
    JobOptions fresh;
    for (const JobOptionSpec& s : jobOptionTable()) EXPECT_TRUE(checkOption(s, fresh)) << s.name << ": its default";
    EXPECT_TRUE(findJobOption("camera_path")->path);
    EXPECT_FALSE(findJobOption("fps")->path);
    EXPECT_EQ(defaultText(*findJobOption("split")), "auto");
    EXPECT_EQ(defaultText(*findJobOption("frames")), "") << "0 is not given: no default shown";
}

// The other commands' tables (mesh, simulate, whitewater): every row complete,
// its default one its checks accept, printed unless it is the input's own.
template <class O>
void expectCompleteTable(std::span<const OptionSpec<O>> table, const char* which) {
    const std::set<std::string> units = {"", "m", "s", "1/s", "m/s^2"};
    std::set<std::string> names;
    O o;
    for (const OptionSpec<O>& s : table) {
        EXPECT_TRUE(names.insert(s.name).second) << which << ": " << s.name << " twice";
        EXPECT_FALSE(s.help.empty()) << which << ": " << s.name;
        EXPECT_NE(std::string(optionGroupTitle(s.group)), "") << which << ": " << s.name;
        EXPECT_TRUE(units.count(s.unit)) << which << ": " << s.name << " unit '" << s.unit << "'";
        EXPECT_EQ(s.name.find('_'), std::string::npos) << s.name;
        ASSERT_NE(s.field, nullptr) << s.name;
        EXPECT_TRUE(checkOption(s, o)) << which << ": " << s.name << ": its default";
        if (s.flag) {
            EXPECT_TRUE(std::holds_alternative<bool*>(s.field(o))) << s.name;
        }
        // A default the help prints is not repeated in the help line.
        const std::string d = defaultText(s);
        if (!d.empty() && !s.flag) {
            EXPECT_EQ(s.help.find("default " + d), std::string::npos) << s.name;
        }
    }
}

TEST(OptionTable, TheOtherCommandsTablesAreComplete) {
    expectCompleteTable(meshOptionTable(), "mesh");
    expectCompleteTable(simulateOptionTable(), "simulate");
    expectCompleteTable(whitewaterOptionTable(), "whitewater");
    expectCompleteTable(viewerOptionTable(), "view");
    for (const char* name : {"duration", "fps", "radius", "solver", "resume", "stats", "render"})
        EXPECT_NE(findIn(simulateOptionTable(), name), nullptr) << name;
    for (const char* name : {"radius", "fps", "limits", "scale", "trapped-air-rate", "wave-crest-rate", "lifetime",
                             "buoyancy", "drag", "gravity", "box", "spray-below", "bubble-above", "max-particles",
                             "seed"})
        EXPECT_NE(findIn(whitewaterOptionTable(), name), nullptr) << name;
    EXPECT_NE(findIn(meshOptionTable(), "stats"), nullptr);
    EXPECT_EQ(std::string(optionGroupTitle(findIn(whitewaterOptionTable(), "drag")->group)), "Motion");
    EXPECT_EQ(std::string(optionGroupTitle(findIn(whitewaterOptionTable(), "spray-below")->group)), "Classes");
    EXPECT_EQ(std::string(optionGroupTitle(findIn(whitewaterOptionTable(), "seed")->group)), "Generation");
    EXPECT_EQ(std::string(optionGroupTitle(findIn(simulateOptionTable(), "solver")->group)), "Simulation");
}

// Defaults are the parameters' initialisers, printed as the CLI writes them.
TEST(OptionTable, TheOtherCommandsDefaultsArePrinted) {
    const auto whitewater = [](const char* name) { return defaultText(*findIn(whitewaterOptionTable(), name)); };
    const WhitewaterParams p;
    EXPECT_EQ(whitewater("lifetime"), "2,5");
    EXPECT_EQ(whitewater("gravity"), "0,-9.81,0");
    EXPECT_EQ(whitewater("seed"), std::to_string(p.seed));
    EXPECT_EQ(whitewater("max-particles"), std::to_string(p.maxParticles));
    EXPECT_EQ(whitewater("drag"), "0.8");
    EXPECT_EQ(whitewater("limits"), "") << "automatic";
    EXPECT_EQ(whitewater("radius"), "") << "estimated";
    EXPECT_EQ(defaultText(*findIn(simulateOptionTable(), "duration")), "") << "the scene's";
    EXPECT_EQ(defaultText(*findIn(simulateOptionTable(), "solver")), "") << "the scene's";
    // The options' defaults make the generator's own defaults.
    auto made = whitewaterParams(WhitewaterOptions{});
    ASSERT_TRUE(made) << made.error().message;
    EXPECT_EQ(made->scale, p.scale);
    EXPECT_EQ(made->lifetimeMinS, p.lifetimeMinS);
    EXPECT_EQ(made->lifetimeMaxS, p.lifetimeMaxS);
    EXPECT_EQ(made->gravity, p.gravity);
    EXPECT_EQ(made->maxParticles, p.maxParticles);
    EXPECT_EQ(made->trappedAirMax, 0.0f) << "automatic limits";
    EXPECT_TRUE(made->box.empty());
}

TEST(OptionTable, TheOtherCommandsOptionsSetTypedAndRefused) {
    const auto refused = [](const Status& st, const char* option, const char* says) {
        ASSERT_FALSE(st) << option;
        EXPECT_NE(st.error().message.find(option), std::string::npos) << st.error().message;
        EXPECT_NE(st.error().message.find(says), std::string::npos) << st.error().message;
    };
    SimulateOptions s;
    ASSERT_TRUE(setOptionIn(simulateOptionTable(), s, "duration", 2.5));
    EXPECT_EQ(s.duration, 2.5);
    ASSERT_TRUE(setOptionIn(simulateOptionTable(), s, "solver", std::string("pbf")));
    ASSERT_TRUE(setOptionIn(simulateOptionTable(), s, "radius", 0.02));
    ASSERT_TRUE(setOptionIn(simulateOptionTable(), s, "stats", true));
    refused(setOptionIn(simulateOptionTable(), s, "solver", std::string("lbm")), "--solver", "dfsph");
    refused(setOptionIn(simulateOptionTable(), s, "fps", -3.0), "--fps", "positive");
    refused(setOptionIn(simulateOptionTable(), s, "duration", -2.0), "--duration", "expected a number in [0, 1e+06]");
    refused(setOptionIn(simulateOptionTable(), s, "frames", 2.0), "frames", "duration");  // lists the names
    EXPECT_EQ(s.solver, "pbf") << "unchanged on an error";
    sim::Scene scene;
    ASSERT_TRUE(applySimulateOptions(s, scene));
    EXPECT_EQ(scene.duration, 2.5);
    EXPECT_EQ(scene.params.solver, sim::Solver::Pbf);
    EXPECT_EQ(scene.params.radius, 0.02f);
    EXPECT_EQ(scene.fps, sim::Scene{}.fps) << "not given: the scene's";

    WhitewaterOptions w;
    const auto set = [&](const char* name, const OptionValue& v) {
        return setOptionIn(whitewaterOptionTable(), w, name, v);
    };
    ASSERT_TRUE(set("lifetime", std::vector<double>{1.0, 3.0}));
    ASSERT_TRUE(set("gravity", glm::vec3(0.0f, 0.0f, -9.81f)));  // three numbers, as Python passes them
    ASSERT_TRUE(set("box", std::string("0,0,0,1,2,3")));          // the command line's text
    ASSERT_TRUE(set("max_particles", std::int64_t(1000)));
    ASSERT_TRUE(set("seed", std::int64_t(7)));
    refused(set("limits", std::vector<double>{1, 2, 3}), "--limits", "6 numbers");
    refused(set("drag", 2.0), "--drag", "in [0, 1]");
    refused(set("seed", std::int64_t(-1)), "--seed", "not negative");
    refused(set("max-particles", std::int64_t(0)), "--max-particles", "in [1, 1e+09]");
    refused(set("lifetime", std::vector<double>{-1.0, 2.0}), "--lifetime", "each number");
    auto made = whitewaterParams(w);
    ASSERT_TRUE(made) << made.error().message;
    EXPECT_EQ(made->lifetimeMaxS, 3.0f);
    EXPECT_EQ(made->gravity, glm::vec3(0.0f, 0.0f, -9.81f));
    EXPECT_EQ(made->box.max, glm::vec3(1, 2, 3));
    EXPECT_EQ(made->maxParticles, 1000u);
    EXPECT_EQ(made->seed, 7u);
    // What only the whole set can say: the library's errors, naming the option.
    const auto errorOf = [](const Result<WhitewaterParams>& r) { return r ? okStatus() : Status(r.error()); };
    WhitewaterOptions bad = w;
    bad.box = {1, 0, 0, 0, 2, 3};
    refused(errorOf(whitewaterParams(bad)), "--box", "below its maximum");
    bad = w;
    bad.limits = {1, 0, 1, 2, 1, 2};
    refused(errorOf(whitewaterParams(bad)), "--limits", "above its minimum");
    bad = w;
    bad.lifetime = {5, 2};
    refused(errorOf(whitewaterParams(bad)), "lifetime", "min <= max");

    MeshOptions m;
    refused(setOptionIn(meshOptionTable(), m, "radius", -1.0), "--radius", "positive");
    ASSERT_TRUE(setOptionIn(meshOptionTable(), m, "stats", true));
    EXPECT_TRUE(m.stats);
}
}  // namespace options_test_local
