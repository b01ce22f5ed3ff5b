// End-to-end tests of `meniscus mesh`: a real frame to PLY and OBJ, a
// sequence to numbered files, the same bytes for any --threads, bad input and
// bad options fail cleanly with nothing written.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "test_util.h"

namespace cli_mesh_test_local {

namespace fs = std::filesystem;
using namespace meniscus::test;

namespace {

const fs::path kFrame = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");

}  // namespace

TEST(CliMesh, RealFrameToPlyAndObj) {
    const fs::path dir = tempDir();
    std::string out;
    ASSERT_EQ(runCli("mesh " + shellQuote(kFrame) + " -o " + shellQuote(dir / "f.ply") + " --stats", &out), 0) << out;
    EXPECT_NE(out.find("wrote"), std::string::npos) << out;
    EXPECT_NE(out.find("peak"), std::string::npos) << out;  // --stats
    auto back = meniscus::readParticles(dir / "f.ply");  // the vertices, through our own PLY reader
    ASSERT_TRUE(back.ok()) << back.error().describe();
    EXPECT_GT(back->size(), 10000u);
    ASSERT_EQ(runCli("mesh " + shellQuote(kFrame) + " -o " + shellQuote(dir / "f.obj") + " --field thesis --cube-size 1", &out), 0)
        << out;
    const auto obj = readBytes(dir / "f.obj");
    EXPECT_NE(std::string(obj.begin(), obj.begin() + 200).find("# written by meniscus"), std::string::npos);
}

TEST(CliMesh, SameFileForAnyThreadCount) {
    const fs::path dir = tempDir();
    std::string out;
    ASSERT_EQ(runCli("mesh " + shellQuote(kFrame) + " -o " + shellQuote(dir / "one.ply") + " --threads 1", &out), 0) << out;
    ASSERT_EQ(runCli("--threads 3 mesh " + shellQuote(kFrame) + " -o " + shellQuote(dir / "three.ply"), &out), 0) << out;
    EXPECT_TRUE(readBytes(dir / "one.ply") == readBytes(dir / "three.ply"));
}

TEST(CliMesh, SequenceToNumberedFiles) {
    const fs::path dir = tempDir();
    fs::create_directories(dir / "in");
    for (int k : {9, 21}) {
        const std::string name = "ParticleData_Fluid_" + std::to_string(k) + ".bgeo";
        fs::copy_file(testData("splishsplash/partio/" + name), dir / "in" / name);
    }
    std::string out;
    ASSERT_EQ(runCli("mesh " + shellQuote(dir / "in") + " -o " + shellQuote(dir / "m_%04d.ply") + " --cube-size 1", &out), 0)
        << out;
    EXPECT_TRUE(fs::exists(dir / "m_0009.ply"));
    EXPECT_TRUE(fs::exists(dir / "m_0021.ply"));
    // Not on a terminal: one log line per frame.
    EXPECT_NE(out.find("m_0009.ply"), std::string::npos) << out;
    EXPECT_NE(out.find("m_0021.ply"), std::string::npos) << out;
    // Two frames into one name is refused before anything is written.
    EXPECT_NE(runCli("mesh " + shellQuote(dir / "in") + " -o " + shellQuote(dir / "one.ply"), &out), 0);
    EXPECT_NE(out.find("pattern"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "one.ply"));
}

// A sequence for ParaView: .vtp meshes with the attributes asked for, and the
// collection beside them listing each at its frame's number; OBJ refuses
// attributes, an unknown attribute is named with those the files have.
TEST(CliMesh, VtkSequenceWithAttributesAndItsCollection) {
    const fs::path dir = tempDir() / "cli_mesh_vtk";
    fs::create_directories(dir / "in");
    for (int k : {9, 21}) {
        const std::string name = "ParticleData_Fluid_" + std::to_string(k) + ".bgeo";
        fs::copy_file(testData("splishsplash/partio/" + name), dir / "in" / name, fs::copy_options::overwrite_existing);
    }
    std::string out;
    ASSERT_EQ(runCli("mesh " + shellQuote(dir / "in") + " -o " + shellQuote(dir / "out" / "m_%04d.vtp") +
                         " --cube-size 1 --interpolate velocity,density",
                     &out),
              0)
        << out;
    auto pvd = meniscus::readPvd(dir / "out" / "m.pvd");
    ASSERT_TRUE(pvd.ok()) << pvd.error().describe();
    ASSERT_EQ(pvd->files.size(), 2u);
    EXPECT_EQ(pvd->files[0].filename(), "m_0009.vtp");
    EXPECT_EQ(pvd->files[1].filename(), "m_0021.vtp");
    auto back = meniscus::readParticles(dir / "out" / "m_0021.vtp");
    ASSERT_TRUE(back.ok()) << back.error().describe();
    EXPECT_NE(back->find("velocity"), nullptr);
    EXPECT_NE(back->find("density"), nullptr);
    EXPECT_NE(back->find("Normals"), nullptr);
    EXPECT_EQ(runCli("mesh " + shellQuote(kFrame) + " -o " + shellQuote(dir / "f.obj") + " --interpolate velocity", &out),
              2);
    EXPECT_NE(out.find("OBJ has no place for vertex attributes"), std::string::npos) << out;
    EXPECT_EQ(runCli("mesh " + shellQuote(kFrame) + " -o " + shellQuote(dir / "f.vtk") + " --interpolate pressure", &out),
              1);
    EXPECT_NE(out.find("--interpolate pressure: the particles have no such attribute (they have: "), std::string::npos)
        << out;
    EXPECT_FALSE(fs::exists(dir / "f.obj"));
    EXPECT_FALSE(fs::exists(dir / "f.vtk"));
}

TEST(CliMesh, BadInputAndOptionsFailCleanly) {
    const fs::path dir = tempDir();
    std::string out;
    EXPECT_EQ(runCli("mesh " + shellQuote(kFrame) + " -o " + shellQuote(dir / "x.stl"), &out), 1);
    EXPECT_NE(out.find("x.stl"), std::string::npos) << out;
    EXPECT_EQ(runCli("mesh " + shellQuote(dir / "missing.bgeo") + " -o " + shellQuote(dir / "x.ply"), &out), 1);
    EXPECT_NE(out.find("missing.bgeo"), std::string::npos) << out;
    EXPECT_EQ(runCli("mesh " + shellQuote(kFrame) + " -o " + shellQuote(dir / "x.ply") + " --cube-size 0", &out), 2);
    EXPECT_NE(out.find("--cube-size"), std::string::npos) << out;
    EXPECT_EQ(runCli("mesh " + shellQuote(kFrame) + " -o " + shellQuote(dir / "x.ply") + " --field metaballs", &out), 2);
    // A truncated file: the reader's error, naming it.
    const auto bytes = readBytes(kFrame);
    writeBytes(dir / "cut.bgeo", std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + long(bytes.size() / 2)));
    EXPECT_EQ(runCli("mesh " + shellQuote(dir / "cut.bgeo") + " -o " + shellQuote(dir / "x.ply"), &out), 1);
    EXPECT_NE(out.find("cut.bgeo"), std::string::npos) << out;
    fs::remove(dir / "cut.bgeo");
    EXPECT_TRUE(fs::is_empty(dir)) << "nothing written";
    EXPECT_EQ(runCli("mesh --help", &out), 0);
    for (const char* unit : {"particle radii", "metres", "fraction"}) EXPECT_NE(out.find(unit), std::string::npos) << unit;
}

// The output's extension picks the format in any case (meshFormatOf); any
// other extension, or none, is refused before anything is read or written.
TEST(CliMesh, OutputExtensionInAnyCase) {
    const fs::path dir = tempDir();
    std::string out;
    ASSERT_EQ(runCli("mesh " + shellQuote(kFrame) + " -o " + shellQuote(dir / "OUT.PLY") + " --cube-size 2", &out), 0) << out;
    ASSERT_EQ(runCli("mesh " + shellQuote(kFrame) + " -o " + shellQuote(dir / "Out.Obj") + " --cube-size 2", &out), 0) << out;
    const auto ply = readBytes(dir / "OUT.PLY"), obj = readBytes(dir / "Out.Obj");
    EXPECT_EQ(std::string(ply.begin(), ply.begin() + 4), "ply\n");
    EXPECT_EQ(std::string(obj.begin(), obj.begin() + 21), "# written by meniscus");
    for (const char* name : {"x.stl", "x", "x.ply.gz"}) {
        EXPECT_EQ(runCli("mesh " + shellQuote(kFrame) + " -o " + shellQuote(dir / name), &out), 1) << name;
        EXPECT_NE(out.find((dir / name).string() + ": output must end in .ply, .obj, .vtp or .vtk"), std::string::npos) << out;
        EXPECT_FALSE(fs::exists(dir / name)) << name;
    }
}

// The mesh path through the CLI: render --surface mesh on both backends gives
// the same picture within the GL parity tolerance, and differs from the
// screen-space one (the mesh really replaced smoothing and normals).
TEST(CliMesh, RenderSurfaceMesh) {
    const fs::path dir = tempDir();
    std::string out;
    const std::string common = shellQuote(kFrame) + " --width 160 --height 90 --radius 0.025 ";
    ASSERT_EQ(runCli("render " + common + "-o " + shellQuote(dir / "mesh_cpu.png") + " --surface mesh --backend cpu", &out), 0)
        << out;
    ASSERT_EQ(runCli("render " + common + "-o " + shellQuote(dir / "screen.png") + " --backend cpu", &out), 0) << out;
    const auto mesh = readPng(dir / "mesh_cpu.png").bytes, screen = readPng(dir / "screen.png").bytes;
    ASSERT_EQ(mesh.size(), screen.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < mesh.size(); ++i) differ += mesh[i] != screen[i];
    EXPECT_GT(differ, mesh.size() / 50) << "the mesh path should not look like the splat path";
    if (runCli("render " + common + "-o " + shellQuote(dir / "mesh_gl.png") + " --surface mesh --backend gl", &out) == 0) {
        const auto gl = readPng(dir / "mesh_gl.png").bytes;
        ASSERT_EQ(gl.size(), mesh.size());
        std::size_t off = 0;
        int worst = 0;
        for (std::size_t i = 0; i < gl.size(); ++i) {
            const int d = std::abs(int(gl[i]) - int(mesh[i]));
            worst = std::max(worst, d);
            off += d > 2;
        }
        EXPECT_LE(off, gl.size() / 200) << "worst " << worst;  // silhouette pixels only (tests/gl_raster_mesh_test.cpp)
    }
    EXPECT_EQ(runCli("render " + common + "-o " + shellQuote(dir / "x.png") + " --surface voxels", &out), 2);
}

TEST(CliMesh, CompareWritesTwoLabelledPanels) {
    const fs::path dir = tempDir();
    std::string out;
    ASSERT_EQ(runCli("compare " + shellQuote(kFrame) + " -o " + shellQuote(dir / "c.png") +
                         " --width 200 --height 120 --radius 0.025 --backend cpu",
                     &out),
              0)
        << out;
    // The table on stdout names both paths with their times.
    EXPECT_NE(out.find("| screen space"), std::string::npos) << out;
    EXPECT_NE(out.find("| mesh (sph field"), std::string::npos) << out;
    EXPECT_NE(out.find(" ms |"), std::string::npos) << out;
    const auto png = readPng(dir / "c.png");
    const int w = png.width, h = png.height;
    const auto& rgba = png.bytes;
    const std::size_t channels = rgba.size() / (std::size_t(w) * std::size_t(h));
    EXPECT_EQ(w, 400);
    EXPECT_EQ(h, 120);
    // White caption pixels in the top strip of each panel.
    auto whiteIn = [&](int x0, int x1) {
        int n = 0;
        for (int y = 0; y < 22; ++y)
            for (int x = x0; x < x1; ++x) {
                const std::size_t at = (std::size_t(y) * std::size_t(w) + std::size_t(x)) * channels;
                n += rgba[at] == 255 && rgba[at + 1] == 255 && rgba[at + 2] == 255;
            }
        return n;
    };
    EXPECT_GT(whiteIn(0, 200), 50);
    EXPECT_GT(whiteIn(200, 400), 50);
    EXPECT_NE(runCli("compare " + shellQuote(kFrame) + " -o " + shellQuote(dir / "c.jpg"), &out), 0);
    EXPECT_FALSE(fs::exists(dir / "c.jpg"));
}
}  // namespace cli_mesh_test_local
