// The option table (include/meniscus/options.h): every row complete, typed
// values set and refused as the faces need, the policies said once.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "meniscus/options.h"
#include "meniscus/particles.h"

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
    EXPECT_EQ(o.noiseParams.bump, 0.75f);
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
    EXPECT_TRUE(o.noise);
    ASSERT_TRUE(setRenderOption(o, "iterations", 3.0));  // a whole float is a whole number
    EXPECT_EQ(o.iterations, 3);
    // Everything else is still its default.
    RenderOptions fresh;
    EXPECT_EQ(o.width, fresh.width);
    EXPECT_EQ(o.noiseParams.frequency, fresh.noiseParams.frequency);
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

TEST(RenderSettingsFromOptions, TheDefaultsAreTheLibrarysDefaults) {
    auto s = renderSettings(RenderOptions{});
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
