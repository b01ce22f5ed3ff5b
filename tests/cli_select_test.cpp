// --select on the commands that load frames (apps/meniscus/common.cpp,
// Frames::load): a DualSPHysics frame with its boundary particles dropped
// renders and meshes exactly as a file holding only its fluid particles;
// bad selections fail naming the option, the file and the attributes; the
// boundary particles drawn as walls, as the liquid or not at all.
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_util.h"

namespace meniscus::cli_select_test_local {
namespace {

namespace fs = std::filesystem;
using test::readBytes;
using test::runCli;
using test::shellQuote;
using test::tempDir;
using test::testData;
using test::writeText;

const fs::path kCsv = testData("dualsphysics/PartCsv_0000.csv");
const fs::path kVtk = testData("dualsphysics/PartAll_0000.vtk");
const std::string kSmall = " --backend cpu --width 80 --height 60";

// The CSV's header and its fluid rows (Type, the ninth field, 3): what a
// file of the fluid alone holds.
fs::path fluidOnlyCsv(const fs::path& dir) {
    std::ifstream in(kCsv);
    std::string line, out;
    int rows = 0;
    for (int n = 0; std::getline(in, line); ++n) {
        std::vector<std::string> f;
        std::stringstream ss(line);
        for (std::string cell; std::getline(ss, cell, ';');) f.push_back(cell);
        if (n == 0 || (f.size() > 8 && f[8] == "3")) {
            out += line + "\n";
            rows += n > 0;
        }
    }
    EXPECT_EQ(rows, 24);
    const fs::path p = dir / "fluid_only.csv";
    writeText(p, out);
    return p;
}

TEST(CliSelect, RenderDrawsOnlyTheSelectedParticles) {
    const fs::path dir = tempDir();
    const fs::path fluid = fluidOnlyCsv(dir);
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(kCsv) + " -o " + shellQuote(dir / "selected.png") +
                         " --select 'Type==fluid'" + kSmall, &out), 0) << out;
    ASSERT_EQ(runCli("render " + shellQuote(fluid) + " -o " + shellQuote(dir / "fluid.png") + kSmall, &out), 0) << out;
    ASSERT_EQ(runCli("render " + shellQuote(kCsv) + " -o " + shellQuote(dir / "all.png") + kSmall, &out), 0) << out;
    const auto selected = readBytes(dir / "selected.png");
    EXPECT_FALSE(selected.empty());
    EXPECT_EQ(selected, readBytes(dir / "fluid.png"));
    EXPECT_NE(selected, readBytes(dir / "all.png")) << "the boundary particles show without --select";
    // The VTK of the same particles, its Type an integer: the same picture.
    ASSERT_EQ(runCli("render " + shellQuote(kVtk) + " -o " + shellQuote(dir / "vtk.png") +
                         " --select 'type != bound'" + kSmall, &out), 0) << out;
    EXPECT_EQ(readBytes(dir / "vtk.png"), selected);
}

TEST(CliSelect, MeshOfTheSelection) {
    const fs::path dir = tempDir();
    const fs::path fluid = fluidOnlyCsv(dir);
    std::string out;
    ASSERT_EQ(runCli("mesh " + shellQuote(kCsv) + " -o " + shellQuote(dir / "selected.ply") +
                         " --select 'Type==fluid' --cube-size 1", &out), 0) << out;
    ASSERT_EQ(runCli("mesh " + shellQuote(fluid) + " -o " + shellQuote(dir / "fluid.ply") + " --cube-size 1", &out), 0)
        << out;
    EXPECT_EQ(readBytes(dir / "selected.ply"), readBytes(dir / "fluid.ply"));
}

TEST(CliSelect, BadSelectionsFailNamingTheProblem) {
    const fs::path dir = tempDir();
    std::string out;
    // An attribute the file lacks: the file, the name and those it has.
    EXPECT_EQ(runCli("render " + shellQuote(kCsv) + " -o " + shellQuote(dir / "x.png") + " --select 'Tpye==3'" + kSmall,
                     &out), 1) << out;
    EXPECT_NE(out.find("PartCsv_0000.csv"), std::string::npos) << out;
    EXPECT_NE(out.find("no attribute 'Tpye'"), std::string::npos) << out;
    EXPECT_NE(out.find("Type"), std::string::npos) << out;
    // Nothing left.
    EXPECT_EQ(runCli("render " + shellQuote(kCsv) + " -o " + shellQuote(dir / "x.png") +
                         " --select 'Type==fluid && density>5000'" + kSmall, &out), 1) << out;
    EXPECT_NE(out.find("PartCsv_0000.csv"), std::string::npos) << out;
    EXPECT_NE(out.find("no particle matches"), std::string::npos) << out;
    // Not an expression: said before any file is read.
    EXPECT_EQ(runCli("mesh " + shellQuote(kCsv) + " -o " + shellQuote(dir / "x.ply") + " --select 'Type=fluid'", &out), 1)
        << out;
    EXPECT_NE(out.find("--select 'Type=fluid'"), std::string::npos) << out;
    EXPECT_NE(out.find("=="), std::string::npos) << out;
    EXPECT_TRUE(fs::is_empty(dir)) << "nothing written";
}

// --boundary-particles (include/meniscus/boundary.h): walls by default, which
// differ from both the liquid and the hidden picture; liquid is what a file
// without DualSPHysics' Type draws (every particle the liquid: the picture
// before the option); hidden is the fluid alone, as --select 'Type==fluid'.
TEST(CliSelect, BoundaryParticlesAsWallsLiquidOrHidden) {
    const fs::path dir = tempDir();
    // The same particles, their Type column renamed: no DualSPHysics types.
    std::ifstream in(kCsv);
    std::stringstream text;
    text << in.rdbuf();
    std::string renamed = text.str();
    const std::size_t at = renamed.find(";Type;");
    ASSERT_NE(at, std::string::npos);
    renamed.replace(at, 6, ";Kind;");
    writeText(dir / "untyped.csv", renamed);
    std::string out;
    const auto render = [&](const fs::path& in, const std::string& png, const std::string& more) {
        EXPECT_EQ(runCli("render " + shellQuote(in) + " -o " + shellQuote(dir / png) + " --up 0,0,1" + more + kSmall,
                         &out), 0) << out;
        return readBytes(dir / png);
    };
    const auto walls = render(kCsv, "walls.png", "");
    const auto liquid = render(kCsv, "liquid.png", " --boundary-particles liquid");
    const auto hidden = render(kCsv, "hidden.png", " --boundary-particles hidden");
    ASSERT_FALSE(walls.empty());
    EXPECT_EQ(liquid, render(dir / "untyped.csv", "untyped.png", "")) << "liquid: as before the option";
    EXPECT_EQ(hidden, render(kCsv, "selected.png", " --select 'Type==fluid'")) << "hidden: the fluid alone";
    EXPECT_NE(walls, liquid);
    EXPECT_NE(walls, hidden);
    EXPECT_EQ(render(kCsv, "walls2.png", " --boundary-particles walls"), walls) << "walls: the default";
    // The VTK of the same particles (Type an integer): the same walls.
    EXPECT_EQ(render(kVtk, "vtk.png", ""), walls);
    // A --select that keeps the fluid alone leaves no wall to draw.
    EXPECT_EQ(render(kCsv, "sel_walls.png", " --select 'Type==fluid' --boundary-particles walls"), hidden);
    // A render scene file's key, as the option.
    writeText(dir / "scene.json", "{\"particles\": " + std::string("\"") + kCsv.string() +
                                      "\", \"output\": \"scene.png\", \"render\": {\"width\": 80, \"height\": 60, "
                                      "\"backend\": \"cpu\", \"up\": [0, 0, 1], \"boundary_particles\": \"hidden\"}}");
    EXPECT_EQ(runCli("render " + shellQuote(dir / "scene.json"), &out), 0) << out;
    EXPECT_EQ(readBytes(dir / "scene.png"), hidden) << "the scene file's boundary_particles";
    // A file of boundary particles alone (as DualSPHysics' PartBound): the walls, no liquid.
    std::string bound;
    std::stringstream lines(text.str());
    int n = 0;
    for (std::string line; std::getline(lines, line); ++n)
        if (n == 0 || line.substr(line.size() - 3) != ";3;") bound += line + "\n";
    writeText(dir / "bound.csv", bound);
    const auto walled = render(dir / "bound.csv", "bound.png", "");
    EXPECT_FALSE(walled.empty());
    EXPECT_EQ(out.find("warning"), std::string::npos) << out;
    // Not a mode: said naming the option.
    EXPECT_NE(runCli("render " + shellQuote(kCsv) + " -o " + shellQuote(dir / "x.png") +
                         " --boundary-particles solid" + kSmall, &out), 0);
    EXPECT_NE(out.find("--boundary-particles"), std::string::npos) << out;
}

TEST(CliSelect, HelpExplainsIt) {
    for (const char* cmd : {"render", "view", "mesh"}) {
        std::string out;
        EXPECT_EQ(runCli(std::string(cmd) + " --help", &out), 0) << out;
        for (const char* word : {"--select", "Type==fluid", "&&", "velocity.x", "m/s"})
            EXPECT_NE(out.find(word), std::string::npos) << cmd << ": " << word;
        if (std::string(cmd) != "mesh") {
            for (const char* word : {"--boundary-particles", "walls", "hidden"})
                EXPECT_NE(out.find(word), std::string::npos) << cmd << ": " << word;
        }
    }
}

}  // namespace
}  // namespace meniscus::cli_select_test_local
