// End-to-end tests of the `meniscus` command line: info --json on the real
// frames, rendering, sequences, and the malformed-input contract (non-zero exit,
// one clear line naming the file, no output file left behind).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "meniscus/io.h"
#include "test_util.h"

namespace cli_test_local {

namespace fs = std::filesystem;
using namespace meniscus::test;

namespace {

// The frame_stats.csv row for (dataset, frame): count, then bounds min/max, then density min/median/max.
std::vector<double> statsRow(const std::string& dataset, int frame) {
    const auto row = frameStatsRow(dataset, frame);
    if (row.empty()) return {};
    std::vector<double> v;
    for (const char* column : {"num_particles", "xmin", "ymin", "zmin", "xmax", "ymax", "zmax", "density_min",
                               "density_median", "density_max"})
        v.push_back(statsNumber(row, column));
    return v;
}

}  // namespace

TEST(Cli, InfoJsonReportsTheRealFrames) {
    for (const std::string file : {"splishsplash/partio/ParticleData_Fluid_21.bgeo", "splishsplash/vtk/ParticleData_Fluid_21.vtk",
                                   "splishsplash/partio/ParticleData_Fluid_61.bgeo"}) {
        const int frame = file.find("_61") != std::string::npos ? 61 : 21;
        std::string out;
        ASSERT_EQ(runCli("info --json " + shellQuote(testData(file)), &out), 0) << out;
        const auto j = nlohmann::json::parse(out);
        const auto row = statsRow("dambreak_r0.025_small", frame);
        ASSERT_EQ(row.size(), 10u);
        EXPECT_EQ(j["count"].get<double>(), row[0]);
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(j["bounds_min"][k].get<double>(), row[1 + k], 1e-5) << file;
            EXPECT_NEAR(j["bounds_max"][k].get<double>(), row[4 + k], 1e-5) << file;
        }
        EXPECT_NEAR(j["density"]["min"].get<double>(), row[7], 0.01);
        EXPECT_NEAR(j["density"]["median"].get<double>(), row[8], 0.01);
        EXPECT_NEAR(j["density"]["max"].get<double>(), row[9], 0.01);
        std::set<std::string> names;
        for (const auto& a : j["attributes"]) names.insert(a["name"].get<std::string>());
        EXPECT_TRUE(names.count("id") && names.count("velocity") && names.count("density")) << out;
        // docs/pipeline.md#depth-splat's estimate is half the median
        // nearest-neighbour distance. The simulator's r is 0.025 (lattice
        // spacing 0.05 at 800 kg/m^3, ~0.046 at 1000); in a disordered liquid
        // the nearest neighbour sits at ~0.8 of the mean spacing, so the
        // estimate lands near 0.0186.
        EXPECT_GT(j["radius_estimate"].get<double>(), 0.017);
        EXPECT_LT(j["radius_estimate"].get<double>(), 0.026);
    }
}

TEST(Cli, InfoJsonOnTheLargeFrame) {
    std::string out;
    ASSERT_EQ(runCli("info --json " + shellQuote(repoData("dambreak_r0.01/ParticleData_Fluid_21.bgeo")), &out), 0) << out;
    const auto j = nlohmann::json::parse(out);
    const auto row = statsRow("dambreak_r0.01", 21);
    ASSERT_EQ(row.size(), 10u);
    EXPECT_EQ(j["count"].get<double>(), 117649.0);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(j["bounds_max"][k].get<double>(), row[4 + k], 1e-5);
    EXPECT_NEAR(j["density"]["median"].get<double>(), row[8], 0.01);
    EXPECT_GT(j["radius_estimate"].get<double>(), 0.0075);
    EXPECT_LT(j["radius_estimate"].get<double>(), 0.0105);
}

TEST(Cli, RendersPngAndExr) {
    const fs::path dir = tempDir();
    const fs::path in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(in) + " -o " + shellQuote(dir / "f.png") + " --width 160 --height 90", &out), 0)
        << out;
    const auto png = readBytes(dir / "f.png");
    ASSERT_GT(png.size(), 8u);
    EXPECT_EQ(png[1], 'P');
    ASSERT_EQ(runCli("render " + shellQuote(in) + " -o " + shellQuote(dir / "f.exr") +
                           " --width 160 --height 90 --eye 0,2,5 --target 0,0.5,0 --fov 50 --radius 0.03",
                       &out),
              0)
        << out;
    const auto exr = readBytes(dir / "f.exr");
    ASSERT_GT(exr.size(), 4u);
    EXPECT_EQ(exr[0], 0x76);  // OpenEXR magic 76 2f 31 01
    EXPECT_EQ(exr[1], 0x2f);
}

// The EXR carries every AOV (R G B A Z Zraw N.X N.Y N.Z T) and the AOVs agree
// with each other: Z and Zraw cover the same pixels (smoothing keeps the
// coverage), thickness is positive exactly there, normals are unit there.
TEST(Cli, ExrCarriesEveryAov) {
    const fs::path dir = tempDir();
    const fs::path in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(in) + " -o " + shellQuote(dir / "f.exr") + " --width 160 --height 90", &out), 0)
        << out;
    const ExrData exr = readExr(dir / "f.exr");
    std::vector<std::string> names = exr.names;
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"A", "B", "G", "N.X", "N.Y", "N.Z", "R", "T", "Z", "Zraw", "coverage"}));
    auto channel = [&](const std::string& n) -> const std::vector<float>& {
        const auto it = std::find(exr.names.begin(), exr.names.end(), n);
        return exr.channels[std::size_t(it - exr.names.begin())].values;
    };
    const auto &z = channel("Z"), &zraw = channel("Zraw"), &t = channel("T");
    const auto &nx = channel("N.X"), &ny = channel("N.Y"), &nz = channel("N.Z");
    const auto &coverage = channel("coverage"), &alpha = channel("A");
    std::size_t fluid = 0, opaque = 0;
    for (std::size_t i = 0; i < z.size(); ++i) {
        const bool covered = std::isfinite(zraw[i]);
        ASSERT_EQ(std::isfinite(z[i]), covered) << i;
        ASSERT_EQ(coverage[i], covered ? 1.0f : 0.0f) << i;
        opaque += alpha[i] == 1.0f;
        if (!covered) continue;
        ++fluid;
        EXPECT_GT(t[i], 0.0f) << i;
        EXPECT_NEAR(nx[i] * nx[i] + ny[i] * ny[i] + nz[i] * nz[i], 1.0f, 1e-4f) << i;
    }
    EXPECT_GT(fluid, 500u);
    // With the studio background the colour is opaque everywhere, so A says
    // nothing about the fluid: that is what `coverage` is for.
    EXPECT_EQ(opaque, z.size());
    EXPECT_LT(fluid, z.size());
}

// Every filter, material, view and background option renders; unknown names
// fail with a message naming the option and the choices.
TEST(Cli, PipelineOptions) {
    const fs::path dir = tempDir();
    const fs::path in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    const std::string base = "render " + shellQuote(in) + " --width 64 --height 36 -o ";
    std::string out;
    for (const char* f : {"none", "gaussian", "bilateral", "binomial", "curvature-flow", "narrow-range"})
        EXPECT_EQ(runCli(base + shellQuote(dir / "f.png") + " --filter " + f + " --iterations 2", &out), 0) << f << out;
    EXPECT_EQ(runCli(base + shellQuote(dir / "f.png") + " --filter narrow-range --separable", &out), 0) << out;
    for (const char* m : {"water", "murky", "milk", "lava", "sand"})
        EXPECT_EQ(runCli(base + shellQuote(dir / "f.png") + " --material " + m, &out), 0) << m << out;
    for (const char* v : {"final", "depth", "raw-depth", "normals", "thickness"})
        EXPECT_EQ(runCli(base + shellQuote(dir / "f.png") + " --view " + v, &out), 0) << v << out;
    ASSERT_EQ(runCli(base + shellQuote(dir / "t.png") + " --background none", &out), 0) << out;
    EXPECT_EQ(readPng(dir / "t.png").format, png_uint_32(PNG_FORMAT_RGBA));

    const std::pair<const char*, const char*> bad[] = {{"--filter", "median"}, {"--material", "honey"},
                                                       {"--view", "shaded"}, {"--background", "black"}};
    // A value outside an option's choices is bad usage (exit 2), whether the command
    // line's parser sees it or (a material, a list of presets) the settings do.
    for (const auto& [opt, value] : bad) {
        EXPECT_EQ(runCli(base + shellQuote(dir / "bad.png") + " " + opt + " " + value, &out), 2)
            << opt;
        EXPECT_NE(out.find(opt), std::string::npos) << out;
        EXPECT_NE(out.find(value), std::string::npos) << out;
    }
    EXPECT_NE(runCli(base + shellQuote(dir / "bad.png") + " --filter gaussian --separable", &out), 0);
    EXPECT_FALSE(fs::exists(dir / "bad.png"));
}

// The surface noise: its views, its EXR channels, its parameters checked.
TEST(Cli, NoiseOptions) {
    const fs::path dir = tempDir();
    const fs::path in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    const std::string base = "render " + shellQuote(in) + " --width 96 --height 54 -o ";
    std::string out;
    for (const char* v : {"final", "noise", "foam"})
        EXPECT_EQ(runCli(base + shellQuote(dir / "n.png") + " --noise --view " + v, &out), 0) << v << out;
    ASSERT_EQ(runCli(base + shellQuote(dir / "n.exr") + " --noise --noise-bump 0.4 --foam 3 --noise-octaves 2 "
                                                   "--noise-frequency 1.5 --turbulence-tau 0.8",
                     &out),
              0)
        << out;
    const ExrData exr = readExr(dir / "n.exr");
    for (const char* c : {"Noise", "foam"})
        EXPECT_NE(std::find(exr.names.begin(), exr.names.end(), c), exr.names.end()) << c;
    // Without --noise the views say what is missing; bad values name the parameter.
    EXPECT_EQ(runCli(base + shellQuote(dir / "bad.png") + " --view noise", &out), 2);
    EXPECT_NE(out.find("--noise"), std::string::npos) << out;
    EXPECT_EQ(runCli(base + shellQuote(dir / "bad.png") + " --noise --noise-octaves 9", &out), 2);
    EXPECT_NE(out.find("octaves"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "bad.png"));
}

// The velocity whitening: its view, its EXR channel, its parameters checked,
// and a warning when the file has no velocities.
TEST(Cli, WhiteningOptions) {
    const fs::path dir = tempDir();
    const fs::path in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    const std::string base = "render " + shellQuote(in) + " --width 96 --height 54 -o ";
    std::string out;
    for (const char* v : {"final", "whitening"})
        EXPECT_EQ(runCli(base + shellQuote(dir / "w.png") + " --whiten --view " + v, &out), 0) << v << out;
    ASSERT_EQ(runCli(base + shellQuote(dir / "w.exr") + " --whiten --whiten-threshold 1 --whiten-ramp 3 "
                                                   "--whiten-strength 0.8 --noise",
                     &out),
              0)
        << out;
    const ExrData exr = readExr(dir / "w.exr");
    EXPECT_NE(std::find(exr.names.begin(), exr.names.end(), "whitening"), exr.names.end());
    EXPECT_EQ(runCli(base + shellQuote(dir / "bad.png") + " --view whitening", &out), 2);
    EXPECT_NE(out.find("--whiten"), std::string::npos) << out;
    EXPECT_EQ(runCli(base + shellQuote(dir / "bad.png") + " --whiten --whiten-ramp 0", &out), 2);
    EXPECT_NE(out.find("rampMps"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "bad.png"));
    // Positions only: said, and rendered unwhitened.
    writeText(dir / "p.xyz", "0 0 0\n0.05 0 0\n0 0.05 0\n");
    ASSERT_EQ(runCli("render " + shellQuote(dir / "p.xyz") + " --width 32 --height 18 --radius 0.03 --whiten -o " +
                         shellQuote(dir / "p.png"),
                     &out),
              0)
        << out;
    EXPECT_NE(out.find("no velocity attribute"), std::string::npos) << out;
}

// Several fluids: a PLY whose `phase` column (integers, or whole floats)
// names each particle's fluid, one material per fluid; the EXR's fluid
// channel holds both; the clear errors of a missing attribute, a fraction,
// too many materials and an index out of range.
TEST(Cli, SeveralFluidsFromAnAttribute) {
    const fs::path dir = tempDir();
    auto writePly = [&](const fs::path& p, const char* type, const std::string& third) {
        std::ostringstream ply;
        int n = 0;
        std::ostringstream rows;
        for (int i = 0; i < 12; ++i)
            for (int j = 0; j < 8; ++j)
                for (int k = 0; k < 4; ++k, ++n)
                    rows << 0.02 * i << " " << 0.02 * j << " " << 0.02 * k << " " << (i < 6 ? "0" : third) << "\n";
        ply << "ply\nformat ascii 1.0\nelement vertex " << n << "\nproperty float x\nproperty float y\n"
            << "property float z\nproperty " << type << " phase\nend_header\n" << rows.str();
        writeText(p, ply.str());
    };
    writePly(dir / "two.ply", "int", "1");
    writePly(dir / "twof.ply", "float", "1");
    writePly(dir / "frac.ply", "float", "0.5");
    writePly(dir / "five.ply", "int", "5");
    const std::string opts = " --width 64 --height 40 --radius 0.01 --fluid-attribute phase ";
    std::string out;
    for (const char* in : {"two.ply", "twof.ply"}) {
        ASSERT_EQ(runCli("render " + shellQuote(dir / in) + opts + "--material water,lava -o " + shellQuote(dir / "f.exr"), &out),
                  0)
            << in << out;
        const ExrData exr = readExr(dir / "f.exr");
        const auto at = std::find(exr.names.begin(), exr.names.end(), "fluid");
        ASSERT_NE(at, exr.names.end()) << in;
        const std::vector<float>& v = exr.channels[std::size_t(at - exr.names.begin())].values;
        EXPECT_EQ(std::set<float>(v.begin(), v.end()), (std::set<float>{-1.0f, 0.0f, 1.0f})) << in;
    }
    EXPECT_EQ(runCli("render " + shellQuote(dir / "two.ply") + opts + "--view fluid-id -o " + shellQuote(dir / "id.png"), &out), 0)
        << out;
    EXPECT_EQ(runCli("render " + shellQuote(dir / "two.ply") + " --width 64 --height 40 --radius 0.01 --fluid-attribute "
                         "kind -o " + shellQuote(dir / "bad.png"),
                     &out),
              1);
    EXPECT_NE(out.find("--fluid-attribute kind: no such attribute (the file has: phase)"), std::string::npos) << out;
    EXPECT_NE(out.find("two.ply"), std::string::npos) << out;
    EXPECT_EQ(runCli("render " + shellQuote(dir / "frac.ply") + opts + "-o " + shellQuote(dir / "bad.png"), &out), 1);
    EXPECT_NE(out.find("not a whole number"), std::string::npos) << out;
    EXPECT_EQ(runCli("render " + shellQuote(dir / "five.ply") + opts + "-o " + shellQuote(dir / "bad.png"), &out), 1);
    EXPECT_NE(out.find("fluid index 5: expected 0 to 3"), std::string::npos) << out;
    EXPECT_EQ(runCli("render " + shellQuote(dir / "two.ply") + opts + "--material water,lava,milk,sand,water -o " +
                         shellQuote(dir / "bad.png"),
                     &out),
              2);
    EXPECT_NE(out.find("5 materials for at most 4 fluids"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "bad.png"));
}

// Several fluids from one sequence per fluid (--fluid, as SPlisHSPlasH writes
// one file per fluid model): frame for frame, the input fluid 0; attributes
// not in every file are left out with a warning; clear errors for a frame
// count that differs and for --fluid with --fluid-attribute.
TEST(Cli, SeveralFluidsFromOneSequencePerFluid) {
    const fs::path dir = tempDir();
    auto writeBlock = [&](const fs::path& p, double x0, bool density) {
        std::ostringstream rows;
        int n = 0;
        for (int i = 0; i < 6; ++i)
            for (int j = 0; j < 8; ++j)
                for (int k = 0; k < 4; ++k, ++n)
                    rows << x0 + 0.02 * i << " " << 0.02 * j << " " << 0.02 * k << " " << n << (density ? " 1000" : "")
                         << "\n";
        writeText(p, "ply\nformat ascii 1.0\nelement vertex " + std::to_string(n) +
                         "\nproperty float x\nproperty float y\nproperty float z\nproperty int id\n" +
                         (density ? "property float density\n" : "") + "end_header\n" + rows.str());
    };
    for (int f : {1, 2}) {
        writeBlock(dir / ("water_" + std::to_string(f) + ".ply"), 0.0, true);
        writeBlock(dir / ("oil_" + std::to_string(f) + ".ply"), 0.12, false);
    }
    writeBlock(dir / "lone.ply", 0.12, false);
    const std::string opts = " --width 64 --height 40 --radius 0.01 --material water,lava ";
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "water_%d.ply") + " --fluid " + shellQuote(dir / "oil_%d.ply") + opts + "-o " +
                         shellQuote(dir / "f_%d.exr"),
                     &out),
              0)
        << out;
    EXPECT_NE(out.find("attribute 'density' is not in every fluid's file alike: left out"), std::string::npos) << out;
    for (int f : {1, 2}) {
        const ExrData exr = readExr(dir / ("f_" + std::to_string(f) + ".exr"));
        const auto at = std::find(exr.names.begin(), exr.names.end(), "fluid");
        ASSERT_NE(at, exr.names.end());
        const std::vector<float>& v = exr.channels[std::size_t(at - exr.names.begin())].values;
        EXPECT_EQ(std::set<float>(v.begin(), v.end()), (std::set<float>{-1.0f, 0.0f, 1.0f})) << f;
    }
    EXPECT_EQ(runCli("render " + shellQuote(dir / "water_%d.ply") + " --fluid " + shellQuote(dir / "lone.ply") + opts + "-o " +
                         shellQuote(dir / "bad_%d.png"),
                     &out),
              1);
    EXPECT_NE(out.find("--fluid: 1 frame(s), the input has 2"), std::string::npos) << out;
    EXPECT_EQ(runCli("render " + shellQuote(dir / "water_1.ply") + " --fluid " + shellQuote(dir / "lone.ply") +
                         " --fluid-attribute id" + opts + "-o " + shellQuote(dir / "bad.png"),
                     &out),
              1);
    EXPECT_NE(out.find("give one or the other"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "bad.png"));
    EXPECT_FALSE(fs::exists(dir / "bad_1.png"));
}

TEST(Cli, DemoNeedsNoInput) {
    const fs::path dir = tempDir();
    std::string out;
    ASSERT_EQ(runCommand("cd " + shellQuote(dir) + " && " + cliPath() + " demo --width 128 --height 72", &out), 0) << out;
    EXPECT_TRUE(fs::exists(dir / "demo.png"));
}

TEST(Cli, RendersASequenceInNaturalOrder) {
    const fs::path dir = tempDir();
    fs::create_directories(dir / "in");
    for (int k : {9, 21, 61}) {
        const std::string name = "ParticleData_Fluid_" + std::to_string(k) + ".bgeo";
        fs::copy_file(testData("splishsplash/partio/" + name), dir / "in" / name);
    }
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "in" / "ParticleData_Fluid_*.bgeo") + " -o " +
                           shellQuote(dir / "out_%04d.png") + " --width 64 --height 36",
                       &out),
              0)
        << out;
    for (const char* name : {"out_0009.png", "out_0021.png", "out_0061.png"}) EXPECT_TRUE(fs::exists(dir / name)) << name;
    // Several frames into one fixed name is refused before anything is written.
    EXPECT_NE(runCli("render " + shellQuote(dir / "in") + " -o " + shellQuote(dir / "one.png"), &out), 0);
    EXPECT_NE(out.find("pattern"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "one.png"));
}

TEST(Cli, BadArgumentsGiveAClearError) {
    const fs::path dir = tempDir();
    const fs::path in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    std::string out;
    EXPECT_NE(runCli("render " + shellQuote(in) + " -o " + shellQuote(dir / "x.jpg"), &out), 0);
    EXPECT_NE(out.find("x.jpg"), std::string::npos) << out;
    EXPECT_NE(runCli("render " + shellQuote(in) + " -o " + shellQuote(dir / "x.png") + " --eye 1,2", &out), 0);
    EXPECT_NE(out.find("--eye"), std::string::npos) << out;
    EXPECT_NE(runCli("render " + shellQuote(in) + " -o " + shellQuote(dir / "x.png") + " --eye 0,0,0 --target 0,0,0", &out), 0);
    EXPECT_NE(runCli("render " + shellQuote(dir / "missing.bgeo") + " -o " + shellQuote(dir / "x.png"), &out), 0);
    EXPECT_NE(out.find("missing.bgeo"), std::string::npos) << out;
    EXPECT_TRUE(fs::is_empty(dir));
    // An output folder that cannot be made (a file stands where it would be)
    // is an error naming the output; a missing one is made (OutputFoldersAreMade).
    { std::ofstream(dir / "a_file") << "x"; }
    EXPECT_NE(runCli("render " + shellQuote(in) + " -o " + shellQuote(dir / "a_file" / "x.png"), &out), 0);
    EXPECT_NE(out.find("x.png"), std::string::npos) << out;
    EXPECT_NE(out.find("cannot make the folder"), std::string::npos) << out;
}

// Every command makes its outputs' missing folders the same way (render's
// images and mesh's meshes here; convert, simulate and whitewater in theirs).
// An unquoted pattern expanded by the shell: the error says to quote it
// instead of listing the paths back.
TEST(Cli, AnExpandedPatternIsExplained) {
    const fs::path dir = tempDir();
    for (const char* name : {"f_1.xyz", "f_2.xyz", "f_3.xyz"}) std::ofstream(dir / name) << "0 0 0\n";
    std::string out;
    EXPECT_EQ(runCli("render " + shellQuote(dir / "f_1.xyz") + " " + shellQuote(dir / "f_2.xyz") + " " +
                         shellQuote(dir / "f_3.xyz") + " -o " + shellQuote(dir / "x.png"),
                     &out),
              2)
        << out;
    EXPECT_NE(out.find("the shell expanded an unquoted pattern; quote it"), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
}

TEST(Cli, OutputFoldersAreMade) {
    const fs::path dir = tempDir();
    const fs::path in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    std::string out;
    const fs::path image = dir / "new" / "deeper" / "x.png";
    EXPECT_EQ(runCli("render " + shellQuote(in) + " -o " + shellQuote(image) + " --width 64 --height 36", &out), 0)
        << out;
    EXPECT_TRUE(fs::is_regular_file(image));
    const fs::path mesh = dir / "meshes" / "m.ply";
    EXPECT_EQ(runCli("mesh " + shellQuote(in) + " -o " + shellQuote(mesh), &out), 0) << out;
    EXPECT_TRUE(fs::is_regular_file(mesh));
}

// Every malformed input: exit code 1, one line on stderr naming the file, and no
// output (nor temporary) file in the output directory.
TEST(Cli, MalformedInputsFailCleanly) {
    const fs::path dir = tempDir();
    const auto bgeo = readBytes(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
    const auto vtk = readBytes(testData("splishsplash/vtk/ParticleData_Fluid_21.vtk"));
    auto cut = [](std::vector<std::uint8_t> v, std::size_t n) {
        v.resize(std::min(n, v.size()));
        return v;
    };
    std::vector<std::pair<std::string, std::vector<std::uint8_t>>> cases{
        {"truncated_gzip.bgeo", cut(bgeo, bgeo.size() / 2)},
        {"truncated_header.bgeo", cut(bgeo, 12)},
        {"truncated.vtk", cut(vtk, vtk.size() / 3)},
        {"truncated_header.vtk", cut(vtk, 40)},
        {"wrong_magic.bgeo", toBytes("Bxyz not a bgeo file at all, sorry")},
        {"wrong_magic.vtk", toBytes("# not vtk\nhello\nASCII\n")},
        {"gzip_garbage.bgeo", toBytes("\x1f\x8b\x08\x00garbage-garbage-garbage-garbage")},
        {"empty.ply", {}},
        {"zero.ply", toBytes("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                             "property float z\nend_header\n")},
        {"count_too_big.ply", toBytes("ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
                                      "property float z\nend_header\n0 0 0\n1 1 1\n")},
        {"ascii_as_binary.ply", toBytes("ply\nformat binary_little_endian 1.0\nelement vertex 100\nproperty float x\n"
                                        "property float y\nproperty float z\nend_header\n0 0 0\n1 1 1\n")},
        {"all_nan.xyz", toBytes("nan 0 0\n0 nan 0\ninf 1 1\n")},
        {"bad_number.csv", toBytes("x,y,z\n0,0,0\n1,one,1\n")},
        {"unknown.dat", toBytes("just some text")},
    };
    for (const auto& [name, bytes] : cases) {
        const fs::path in = dir / "in" / name;
        fs::create_directories(in.parent_path());
        writeBytes(in, bytes);
        const fs::path outDir = dir / ("out_" + name);
        fs::create_directories(outDir);
        for (const char* ext : {".png", ".exr"}) {
            std::string out;
            const int rc = runCli("render " + shellQuote(in) + " -o " + shellQuote(outDir / (std::string("r") + ext)), &out);
            EXPECT_EQ(rc, 1) << name << ": " << out;
            EXPECT_NE(out.find(name), std::string::npos) << name << ": " << out;
            EXPECT_NE(out.find("error"), std::string::npos) << name << ": " << out;
            EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << name << ": " << out;
            EXPECT_TRUE(fs::is_empty(outDir)) << name;
        }
        std::string out;
        EXPECT_EQ(runCli("info --json " + shellQuote(in), &out), 1) << name << ": " << out;
    }
}

TEST(Cli, NanPositionsAreDroppedWithACountedWarning) {
    const fs::path dir = tempDir();
    writeText(dir / "some_nan.xyz", "0 0 0\nnan 1 1\n0.1 0 0\n0 0.1 0\n0.1 0.1 inf\n");
    std::string out;
    ASSERT_EQ(runCli("info --json " + shellQuote(dir / "some_nan.xyz"), &out), 0) << out;
    EXPECT_NE(out.find("dropped 2 of 5"), std::string::npos) << out;
}

TEST(Cli, HelpExplainsTheCommands) {
    std::string out;
    EXPECT_EQ(runCli("--help", &out), 0);
    for (const char* word : {"render", "info", "demo", "Examples"}) EXPECT_NE(out.find(word), std::string::npos) << word;
    EXPECT_EQ(runCli("render --help", &out), 0);
    for (const char* word : {"--eye", "--radius", "--fov", "--width"}) EXPECT_NE(out.find(word), std::string::npos) << word;
}

// `meniscus view` needs a display: with none (DISPLAY and WAYLAND_DISPLAY
// unset) it fails at once, exit code 1, with one line that says why (GLFW's
// reason), and writes no screenshot. A build without GLFW fails the same way,
// saying it has no viewer. Its help names the controls and the view options.
TEST(Cli, ViewWithoutADisplayFailsClearly) {
    const fs::path dir = tempDir();
    std::string out;
    EXPECT_EQ(runCommand("env -u DISPLAY -u WAYLAND_DISPLAY " + cliPath() + " view --frames 1 --screenshot " +
                             shellQuote(dir / "s.png"),
                         &out),
              1)
        << out;
    EXPECT_EQ(out.rfind("meniscus: error: ", 0), 0u) << out;
    EXPECT_NE(out.find("GLFW"), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
    EXPECT_FALSE(fs::exists(dir / "s.png"));

    EXPECT_EQ(runCli("--help", &out), 0);
    EXPECT_NE(out.find("view"), std::string::npos);
    EXPECT_EQ(runCli("view --help", &out), 0);
    for (const char* word : {"orbit", "zoom", "Esc", "display", "--filter", "--material", "--screenshot"})
        EXPECT_NE(out.find(word), std::string::npos) << word;
    EXPECT_EQ(out.find("--backend"), std::string::npos) << "the viewer always renders with GL";
}


// ------------------------------------- hardening: usage errors, ranges, radius

// Bad usage exits 2, as docs/usage.md#errors says (CLI11's own codes were 105/106).
TEST(Cli, UsageErrorsExitTwo) {
    std::string out;
    EXPECT_EQ(runCli("", &out), 2) << out;
    EXPECT_EQ(runCli("info", &out), 2) << out;
    EXPECT_EQ(runCli("info --no-such-option x.xyz", &out), 2) << out;
    EXPECT_EQ(runCli("render x.xyz -o y.png --width 0", &out), 2) << out;
    EXPECT_EQ(runCli("--help", &out), 0) << out;
}

TEST(Cli, TinyAndHugeCoordinatesFailWithTheFileNamed) {
    const fs::path dir = tempDir() / "cli_coords";
    fs::create_directories(dir);
    std::string out;
    // Two points 1e-15 m apart: info ends (it used to hang), render refuses the radius.
    writeText(dir / "t.xyz", "0 0 0\n1e-15 0 0\n");
    EXPECT_EQ(runCli("info " + shellQuote(dir / "t.xyz"), &out), 0) << out;
    EXPECT_NE(out.find("radius      5e-16 m"), std::string::npos) << out;
    EXPECT_EQ(runCli("render " + shellQuote(dir / "t.xyz") + " -o " + shellQuote(dir / "t.png"), &out), 1) << out;
    EXPECT_NE(out.find("t.xyz: the estimated particle radius 5e-16 m is out of range"), std::string::npos) << out;
    // Coordinates up to 1e30: what is wrong with the data, naming the file.
    std::string big;
    for (int i = 0; i < 1000; ++i) big += std::to_string(i) + "e27 " + std::to_string(999 - i) + "e27 1e27\n";
    writeText(dir / "big.xyz", big);
    for (const std::string cmd : {"info ", "render "}) {
        const std::string args = cmd + shellQuote(dir / "big.xyz") + (cmd == "render " ? " -o " + shellQuote(dir / "b.png") : "");
        EXPECT_EQ(runCli(args, &out), 1) << out;
        EXPECT_NE(out.find("big.xyz: coordinates reach"), std::string::npos) << out;
        EXPECT_NE(out.find("rescale the data"), std::string::npos) << out;
    }
    EXPECT_FALSE(fs::exists(dir / "b.png"));
}

// `meniscus render` of the real frame 21 into DIR/r.png with extra arguments.
int renderFrame21(const std::string& dirName, const std::string& args, std::string* out) {
    const fs::path dir = tempDir() / dirName;
    fs::create_directories(dir);
    return runCli("render " + shellQuote(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo")) + " -o " +
                      shellQuote(dir / "r.png") + " " + args,
                  out);
}

TEST(Cli, RadiusOutOfRangeIsSaid) {
    std::string out;
    EXPECT_EQ(renderFrame21("cli_radius_range", "--radius 1e30", &out), 2);
    EXPECT_NE(out.find("--radius: particle radius 1e+30 m is out of range"), std::string::npos) << out;
}

TEST(Cli, RenderSaysWhichRadiusAndHow) {
    std::string out;
    ASSERT_EQ(renderFrame21("cli_radius_line", "--width 64 --height 36", &out), 0) << out;
    EXPECT_NE(out.find("meniscus: radius 0.023"), std::string::npos) << out;
    EXPECT_NE(out.find("bulk number density"), std::string::npos) << out;
}

// A file with a smoothing length h and no radius renders as the same file with
// the radius h / (2 x 1.2), byte for byte, particle by particle (radii varying
// 0.6-1.4x across the set); --h-per-spacing changes it; render and info say
// where the radius came from.
TEST(Cli, SmoothingLengthGivesEachParticleItsRadius) {
    auto set = meniscus::readParticles(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
    ASSERT_TRUE(set) << set.error().describe();
    std::vector<float> h(set->size()), r(set->size());
    for (std::size_t i = 0; i < h.size(); ++i) {
        h[i] = 0.06f * (0.6f + 0.8f * hash01(std::uint32_t(i), 17));
        r[i] = h[i] * (1.0f / (2.0f * 1.2f));  // the library's arithmetic
    }
    const fs::path dir = tempDir() / "cli_smoothing_length";
    fs::create_directories(dir);
    meniscus::ParticleSet withH{set->positions, {{"h", meniscus::AttributeType::Float, 1, h, {}}}, {}};
    meniscus::ParticleSet withR{set->positions, {{"radius", meniscus::AttributeType::Float, 1, r, {}}}, {}};
    ASSERT_TRUE(meniscus::writeParticles(dir / "h.ply", withH));
    ASSERT_TRUE(meniscus::writeParticles(dir / "r.ply", withR));
    const std::string view = " --width 160 --height 90 --eye 2.5,2.1,2.9 --target 0.43,0.45,0";
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "h.ply") + " -o " + shellQuote(dir / "h.png") + view, &out), 0) << out;
    EXPECT_NE(out.find("radii from the smoothing length 'h': r = h / (2 x 1.2)"), std::string::npos) << out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "r.ply") + " -o " + shellQuote(dir / "r.png") + view, &out), 0) << out;
    EXPECT_EQ(out.find("smoothing length"), std::string::npos) << out;
    EXPECT_EQ(readBytes(dir / "h.png"), readBytes(dir / "r.png"));
    ASSERT_EQ(runCli("render " + shellQuote(dir / "h.ply") + " -o " + shellQuote(dir / "k.png") + view + " --h-per-spacing 2",
                     &out),
              0)
        << out;
    EXPECT_NE(readBytes(dir / "k.png"), readBytes(dir / "r.png"));
    ASSERT_EQ(runCli("info --json " + shellQuote(dir / "h.ply"), &out), 0) << out;
    const auto j = nlohmann::json::parse(out.substr(out.find('{')));
    EXPECT_EQ(j["radius_from_smoothing_length"]["attribute"], "h");
    EXPECT_EQ(j["radius_method"], "file-attribute");
    EXPECT_EQ(j["attributes"].size(), 1u);  // the file's own: h
    EXPECT_NE(runCli("info " + shellQuote(dir / "h.ply") + " --h-per-spacing 0", &out), 0);
}

// --version says what the build has; a subcommand's option given before the
// subcommand is a usage error saying where it goes, while
// --threads works on either side.
TEST(Cli, VersionAndWhereOptionsGo) {
    std::string out;
    ASSERT_EQ(runCli("--version", &out), 0) << out;
    EXPECT_EQ(out.rfind("meniscus 0.", 0), 0u) << out;
    EXPECT_NE(out.find("backends: cpu"), std::string::npos) << out;
    EXPECT_NE(out.find("movies: "), std::string::npos) << out;
    const fs::path dir = tempDir() / "cli_where";
    fs::create_directories(dir);
    const std::string in = shellQuote(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
    EXPECT_EQ(runCli("--width 64 render " + in + " -o " + shellQuote(dir / "a.png"), &out), 2) << out;
    EXPECT_NE(out.find("--width is an option of a subcommand and goes after it"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "a.png"));
    EXPECT_EQ(runCli("--threads 1 render " + in + " -o " + shellQuote(dir / "b.png") + " --width 64 --height 36", &out), 0)
        << out;
    EXPECT_EQ(runCli("render " + in + " -o " + shellQuote(dir / "c.png") + " --width 64 --height 36 --threads 1", &out), 0)
        << out;
    EXPECT_EQ(readBytes(dir / "b.png"), readBytes(dir / "c.png"));
}

TEST(Cli, AnisotropyOnOffAndItsErrors) {
    std::string out;
    ASSERT_EQ(renderFrame21("cli_aniso_on", "--width 64 --height 36 --anisotropy on --anisotropy-radius 5", &out), 0)
        << out;
    EXPECT_EQ(renderFrame21("cli_aniso_word", "--width 64 --height 36 --anisotropy yes", &out), 2);
    EXPECT_NE(out.find("--anisotropy: yes: expected on or off"), std::string::npos) << out;
    EXPECT_EQ(renderFrame21("cli_aniso_ratio", "--width 64 --height 36 --anisotropy on --anisotropy-ratio 0.5", &out), 2);
    EXPECT_NE(out.find("--anisotropy: kr: 1 to 16"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(tempDir() / "cli_aniso_ratio" / "r.png"));
}

TEST(Cli, HugeFrameIsRefusedWithTheFigure) {
    const fs::path dir = tempDir() / "cli_huge";
    fs::create_directories(dir);
    std::string out;
    const int rc = runCli("render " + shellQuote(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo")) + " -o " +
                              shellQuote(dir / "h.png") + " --width 16384 --height 16384 --backend cpu",
                          &out);
    if (rc == 0) GTEST_SKIP() << "this machine has the memory for it";
    EXPECT_EQ(rc, 1) << out;
    EXPECT_NE(out.find("a 16384x16384 frame needs about"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "h.png"));
}

// Regression: a symlinked output was replaced by a regular file.
TEST(Cli, SymlinkedOutputIsWrittenThrough) {
    const fs::path dir = tempDir() / "cli_symlink";
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::create_symlink("target.png", dir / "link.png");
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo")) + " -o " +
                         shellQuote(dir / "link.png") + " --width 64 --height 36",
                     &out),
              0)
        << out;
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "link.png")));
    EXPECT_TRUE(fs::is_regular_file(dir / "target.png"));
    EXPECT_GT(fs::file_size(dir / "target.png"), 100u);
    EXPECT_NE(out.find("through the link"), std::string::npos) << out;
}

// A build without MPI, started by mpirun on several processes, says in one line
// that it is not an MPI build instead of rendering the whole job once per
// process (the launcher's environment is what it sees; OpenMPI's is faked here,
// so no mpirun is needed). An MPI build would start MPI on that environment:
// its tests are cli_mpi_test's.
TEST(Cli, ANonMpiBuildUnderMpirunSaysSo) {
#ifdef MENISCUS_HAVE_MPI
    GTEST_SKIP() << "an MPI build (cli_mpi_test covers mpirun)";
#else
    const std::filesystem::path dir = tempDir() / "not_mpi";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    std::string out;
    EXPECT_EQ(runCommand("OMPI_COMM_WORLD_SIZE=3 " + cliPath() + " render " +
                             shellQuote(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo")) + " -o " +
                             shellQuote(dir / "f.png") + " --width 64 --height 48",
                         &out),
              1)
        << out;
    EXPECT_NE(out.find("not an MPI build"), std::string::npos) << out;
    EXPECT_FALSE(std::filesystem::exists(dir / "f.png"));
#endif
}

// `render --help` is laid out for a newcomer: the title names every output (a
// movie too), and the option groups come in the order people set them, the
// input and camera first, the cluster last (apps/meniscus/help_format.h).
TEST(Cli, RenderHelpGroupsInOrder) {
    std::string out;
    ASSERT_EQ(runCli("render --help", &out), 0) << out;
    const std::string title = out.substr(0, out.find('\n'));
    EXPECT_NE(title.find("MP4"), std::string::npos) << title;
    EXPECT_NE(title.find("PNG"), std::string::npos) << title;
    EXPECT_NE(title.find("EXR"), std::string::npos) << title;
    std::size_t previous = 0;
    std::string previousGroup = "the title";
    for (const char* group : {"Input", "Camera", "Look", "Surface", "Extras", "Output", "Movie", "Performance", "Cluster"}) {
        const std::size_t at = out.find("\n" + std::string(group) + ":\n");
        ASSERT_NE(at, std::string::npos) << group << " missing:\n" << out;
        EXPECT_GT(at, previous) << group << " comes before " << previousGroup << ":\n" << out;
        previous = at;
        previousGroup = group;
    }
    // The common options sit in their groups: the input under Input, --width under Camera, --threads under Performance.
    const auto groupOf = [&out](const std::string& option) {
        const std::size_t at = out.find("\n  " + option);
        if (at == std::string::npos) return std::string("(not listed)");
        const std::size_t head = out.rfind(":\n", at);
        const std::size_t start = out.rfind('\n', head - 1) + 1;
        return out.substr(start, head - start);
    };
    EXPECT_EQ(groupOf("input"), "Input");
    EXPECT_EQ(groupOf("--width"), "Camera");
    EXPECT_EQ(groupOf("--material"), "Look");
    EXPECT_EQ(groupOf("--filter"), "Surface");
    EXPECT_EQ(groupOf("--noise"), "Extras");
    EXPECT_EQ(groupOf("-o,--output"), "Output");
    EXPECT_EQ(groupOf("--fps"), "Movie");
    EXPECT_EQ(groupOf("--threads"), "Performance");
    EXPECT_EQ(groupOf("--shard"), "Cluster");
    EXPECT_EQ(out.find("README"), std::string::npos) << "scene files are docs/usage.md#scene-files";
    EXPECT_NE(out.find("docs/usage.md#scene-files"), std::string::npos);
}
}  // namespace cli_test_local
