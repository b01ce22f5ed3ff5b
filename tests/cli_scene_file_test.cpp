// Render scene files: `meniscus render scene.json` gives the bytes of the same
// settings as options; the command line overrides the file; paths are relative
// to the file; unknown keys and bad values are errors that name the key.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "test_util.h"

namespace cli_scene_file_test_local {

namespace fs = std::filesystem;
using namespace meniscus::test;

namespace {

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

}  // namespace

// The minimal form (particles, radius, camera, size, output), rendered from
// another folder: the same bytes as the options; an option on the command line
// overrides the file's.
TEST(SceneFile, TheMinimalFormRendersAsItsOptions) {
    const fs::path dir = dirWithFrame("scene_minimal");
    write(dir / "scene.json",
          R"({"particles": "f.bgeo", "radius": 0.01, "camera": {"eye": [2.6, 2.0, 3.2], "target": [0, 0.35, 0],)"
          R"( "fov": 40}, "render": {"width": 320, "height": 180}, "output": "out.png"})");
    std::string out;
    ASSERT_EQ(runCommand("cd / && " + cliPath() + " render " + shellQuote(dir / "scene.json"), &out), 0) << out;
    ASSERT_TRUE(fs::exists(dir / "out.png")) << out;  // relative to the scene file, not the working folder
    ASSERT_EQ(runCli("render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "cli.png") +
                         " --radius 0.01 --eye 2.6,2,3.2 --target 0,0.35,0 --fov 40 --width 320 --height 180",
                     &out),
              0)
        << out;
    EXPECT_EQ(readBytes(dir / "out.png"), readBytes(dir / "cli.png"));
    ASSERT_EQ(runCli("render " + shellQuote(dir / "scene.json") + " --width 160 --height 90 -o " + shellQuote(dir / "s.png"),
                     &out),
              0)
        << out;
    EXPECT_EQ(readPng(dir / "s.png").width, 160);
    EXPECT_EQ(readBytes(dir / "out.png"), readBytes(dir / "cli.png"));  // the file's own output untouched
}

// Sections, flags, on/off as true/false, lists, a material object with custom
// values, the light: the same bytes as the options they stand for.
TEST(SceneFile, EveryKindOfSettingMatchesItsOption) {
    const fs::path dir = dirWithFrame("scene_kinds");
    write(dir / "scene.json", R"({
      "particles": "f.bgeo", "output": "a.png",
      "camera": {"eye": [2.5, 2.1, 2.9], "target": [0.43, 0.45, 0.0], "up": [0, 1, 0], "fov": 35},
      "render": {"width": 160, "height": 90, "filter": "curvature-flow", "iterations": 20, "backend": "cpu"},
      "anisotropy": false, "fill_holes": 0, "noise": true, "noise-bump": 0.5,
      "material": {"preset": "murky", "ior": 1.5, "absorption": [3, 1, 0.5], "fluid_color": [0.1, 0.2, 0.3]},
      "light": {"direction": [0.2, 1, 0.1]}
    })");
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "scene.json"), &out), 0) << out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "b.png") +
                         " --eye 2.5,2.1,2.9 --target 0.43,0.45,0 --up 0,1,0 --fov 35 --width 160 --height 90 "
                         "--filter curvature-flow --iterations 20 --backend cpu --anisotropy off --fill-holes 0 "
                         "--noise --noise-bump 0.5 --material murky --ior 1.5 --absorption 3,1,0.5 "
                         "--fluid-color 0.1,0.2,0.3 --light 0.2,1,0.1",
                     &out),
              0)
        << out;
    EXPECT_EQ(readBytes(dir / "a.png"), readBytes(dir / "b.png"));
    // And the custom values do change the picture.
    ASSERT_EQ(runCli("render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "c.png") +
                         " --eye 2.5,2.1,2.9 --target 0.43,0.45,0 --up 0,1,0 --fov 35 --width 160 --height 90 "
                         "--filter curvature-flow --iterations 20 --backend cpu --anisotropy off --fill-holes 0 "
                         "--noise --noise-bump 0.5 --material murky",
                     &out),
              0)
        << out;
    EXPECT_NE(readBytes(dir / "a.png"), readBytes(dir / "c.png"));
}

// The automatic camera's direction and distance: the defaults give the default
// view's bytes; another azimuth, elevation or distance another picture; in a
// scene file as camera.azimuth and so on.
TEST(SceneFile, AutomaticCameraDirectionAndDistance) {
    const fs::path dir = dirWithFrame("scene_auto_camera");
    const std::string base = "render " + shellQuote(dir / "f.bgeo") + " --width 160 --height 90 --backend cpu -o ";
    std::string out;
    ASSERT_EQ(runCli(base + shellQuote(dir / "d.png"), &out), 0) << out;
    ASSERT_EQ(runCli(base + shellQuote(dir / "e.png") + " --azimuth 35 --elevation 25", &out), 0) << out;
    EXPECT_EQ(readBytes(dir / "d.png"), readBytes(dir / "e.png"));
    for (const char* other : {"--azimuth 120", "--elevation 60", "--distance 9"}) {
        ASSERT_EQ(runCli(base + shellQuote(dir / "o.png") + " " + other, &out), 0) << out;
        EXPECT_NE(readBytes(dir / "d.png"), readBytes(dir / "o.png")) << other;
    }
    write(dir / "s.json", R"({"particles": "f.bgeo", "output": "s.png", "render": {"width": 160, "height": 90,)"
                          R"( "backend": "cpu"}, "camera": {"azimuth": 120}})");
    ASSERT_EQ(runCli("render " + shellQuote(dir / "s.json"), &out), 0) << out;
    ASSERT_EQ(runCli(base + shellQuote(dir / "a.png") + " --azimuth 120", &out), 0) << out;
    EXPECT_EQ(readBytes(dir / "s.png"), readBytes(dir / "a.png"));
    EXPECT_EQ(runCli(base + shellQuote(dir / "x.png") + " --elevation 90", &out), 2) << out;
}

// --up: the real frame turned to z up, (x, y, z) -> (x, -z, y) with its
// velocities, renders with --up 0,0,1 byte for byte as the y-up original, with
// the automatic camera and with --eye/--target given in the z-up coordinates;
// without --up it lies on its side.
TEST(SceneFile, UpStandsZUpDataTheRightWay) {
    const fs::path dir = dirWithFrame("scene_up");
    auto set = meniscus::readParticles(dir / "f.bgeo");
    ASSERT_TRUE(set) << set.error().describe();
    ASSERT_TRUE(meniscus::writeParticles(dir / "y.ply", *set));
    auto zUp = [](glm::vec3 p) { return glm::vec3(p.x, -p.z, p.y); };
    for (glm::vec3& p : set->positions) p = zUp(p);
    meniscus::Attribute* v = set->find("velocity");
    ASSERT_NE(v, nullptr);
    for (std::size_t k = 0; k + 2 < v->floats.size(); k += 3) {
        const glm::vec3 t = zUp({v->floats[k], v->floats[k + 1], v->floats[k + 2]});
        v->floats[k] = t.x, v->floats[k + 1] = t.y, v->floats[k + 2] = t.z;
    }
    ASSERT_TRUE(meniscus::writeParticles(dir / "z.ply", *set));
    const std::string opts = " --width 160 --height 90 --backend cpu --whiten -o ";
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "y.ply") + opts + shellQuote(dir / "y.png"), &out), 0) << out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "z.ply") + opts + shellQuote(dir / "z.png") + " --up 0,0,1", &out), 0) << out;
    EXPECT_EQ(readBytes(dir / "y.png"), readBytes(dir / "z.png"));
    ASSERT_EQ(runCli("render " + shellQuote(dir / "z.ply") + opts + shellQuote(dir / "side.png"), &out), 0) << out;
    EXPECT_NE(readBytes(dir / "y.png"), readBytes(dir / "side.png"));
    ASSERT_EQ(runCli("render " + shellQuote(dir / "y.ply") + opts + shellQuote(dir / "ye.png") +
                         " --eye 2.5,2.1,2.9 --target 0.43,0.45,0",
                     &out),
              0)
        << out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "z.ply") + opts + shellQuote(dir / "ze.png") +
                         " --eye 2.5,-2.9,2.1 --target 0.43,0,0.45 --up 0,0,1",
                     &out),
              0)
        << out;
    EXPECT_EQ(readBytes(dir / "ye.png"), readBytes(dir / "ze.png"));
    EXPECT_EQ(runCli("render " + shellQuote(dir / "z.ply") + opts + shellQuote(dir / "x.png") + " --up 0,0,0", &out), 2);
    EXPECT_NE(out.find("--up 0,0,0: expected the up axis"), std::string::npos) << out;
}

TEST(SceneFile, ErrorsNameTheKey) {
    const fs::path dir = dirWithFrame("scene_errors");
    struct Case {
        const char* json;
        const char* says;
        int rc;
    };
    const Case cases[] = {
        {R"({"particles": "f.bgeo", "output": "x.png", "render": {"colour": 3}})", "render.colour: unknown key", 2},
        // A key or value the option refuses: the settings are at fault (exit 2, as on
        // the command line), named with the key; a file that cannot be read, 1.
        {R"({"particles": "f.bgeo", "output": "x.png", "render": {"width": 0}})", "render.width: --width", 2},
        {R"({"particles": "f.bgeo", "output": "x.png", "render": {"filter": "foo"}})",
         "render.filter: --filter foo: expected one of", 2},
        {R"({"particles": "f.bgeo", "output": "x.png", "camera": {"eye": "here", "target": [0, 0, 0]}})",
         "camera.eye: --eye: expected three numbers x,y,z", 2},
        {R"({"particles": "f.bgeo", "output": "x.png", "noise": "yes"})", "noise: expected true or false", 2},
        {R"({"particles": "f.bgeo", "output": "x.png", "material": {"ior": 0.5}})", "material.ior: --ior", 2},
        {R"({"particles": "f.bgeo", "output": "x.png", "light": {"colour": [1, 1, 1]}})", "light: expected", 2},
        {R"({"particles": 3, "output": "x.png"})", "particles: expected the particle file", 2},
        {R"({"output": "x.png"})", "needs \"particles\"", 2},
        {R"({"particles": "f.bgeo", "output": "x.png",)", "not valid JSON", 1},
        {R"({"particles": "missing.bgeo", "output": "x.png"})", "missing.bgeo", 1},
    };
    for (const Case& c : cases) {
        write(dir / "s.json", c.json);
        std::string out;
        EXPECT_EQ(runCli("render " + shellQuote(dir / "s.json"), &out), c.rc) << c.json << "\n" << out;
        EXPECT_NE(out.find(c.says), std::string::npos) << c.json << "\n" << out;
        if (std::string(c.says) != "missing.bgeo") {  // that error names the particle file
            EXPECT_NE(out.find("s.json"), std::string::npos) << c.json << "\n" << out;
        }
        EXPECT_FALSE(fs::exists(dir / "x.png")) << c.json;
    }
}

// Scene geometry (docs/geometry.md): the scene file's `geometry` key (a file
// relative to the scene file, inline objects whose files are too) gives the
// bytes of the same --geometry options, and of one --geometry holding both
// as a JSON list; --cut-away off draws a container's
// near walls (a different picture); a missing file is an error naming it and
// the option; a simulation scene's colliders are drawn (render scene.json).
TEST(SceneFile, GeometryKeyMatchesTheOptionAndErrorsNameTheFile) {
    const fs::path dir = dirWithFrame("scene_geometry");
    fs::create_directories(dir / "models");
    write(dir / "models" / "cube.obj",
          "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
          "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n");
    write(dir / "scene.json", R"({
      "particles": "f.bgeo", "output": "a.png", "radius": 0.01,
      "camera": {"eye": [2.6, 2.0, 3.2], "target": [0, 0.35, 0]},
      "render": {"width": 160, "height": 90, "backend": "cpu"},
      "geometry": [
        {"file": "models/cube.obj", "scale": 0.3, "translate": [0.6, 0, 0.3], "material": {"color": [0.8, 0.2, 0.1]}},
        {"box": {"min": [-0.5, -0.05, -0.5], "max": [1.5, 1.0, 0.5]}, "cutaway": true}
      ]
    })");
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(dir / "scene.json"), &out), 0) << out;
    const std::string cube = R"({"file": ")" + (dir / "models" / "cube.obj").string() +
                             R"(", "scale": 0.3, "translate": [0.6, 0, 0.3], "material": {"color": [0.8, 0.2, 0.1]}})";
    const std::string tank = R"({"box": {"min": [-0.5, -0.05, -0.5], "max": [1.5, 1.0, 0.5]}, "cutaway": true})";
    const std::string options = " --radius 0.01 --eye 2.6,2,3.2 --target 0,0.35,0 --width 160 --height 90 "
                                "--backend cpu --geometry " + shellQuote(cube) + " --geometry " + shellQuote(tank);
    ASSERT_EQ(runCli("render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "b.png") + options, &out), 0)
        << out;
    EXPECT_EQ(readBytes(dir / "a.png"), readBytes(dir / "b.png"));
    ASSERT_EQ(runCli("render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "c.png") + options +
                         " --cut-away off",
                     &out),
              0)
        << out;
    EXPECT_NE(readBytes(dir / "a.png"), readBytes(dir / "c.png"));
    ASSERT_EQ(runCli("render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "d.png") + options, &out), 0);
    EXPECT_EQ(readBytes(dir / "a.png"), readBytes(dir / "d.png"));
    // Both objects as one inline JSON list (one value, its commas and brackets kept whole).
    const std::string listed = " --radius 0.01 --eye 2.6,2,3.2 --target 0,0.35,0 --width 160 --height 90 "
                               "--backend cpu --geometry " + shellQuote("[" + cube + ", " + tank + "]");
    ASSERT_EQ(runCli("render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "l.png") + listed, &out), 0)
        << out;
    EXPECT_EQ(readBytes(dir / "a.png"), readBytes(dir / "l.png"));

    // Errors (docs/usage.md#errors): a missing mesh file is the data's (exit 1);
    // an unknown key of an inline object is the option's value (exit 2, as any
    // bad option value).
    EXPECT_EQ(runCli("render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "e.png") +
                         " --geometry " + shellQuote(dir / "nothing.obj"),
                     &out),
              1);
    EXPECT_NE(out.find("--geometry"), std::string::npos) << out;
    EXPECT_NE(out.find("nothing.obj"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "e.png"));
    EXPECT_EQ(runCli("render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "e.png") +
                         " --geometry " + shellQuote(R"({"box": {"min": [0, 0, 0], "max": [1, 1, 1]}, "colour": 1})"),
                     &out),
              2);
    EXPECT_NE(out.find("colour"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "e.png"));
}

// Shadows (docs/geometry.md#shadows): auto draws them with geometry (as
// --shadows on) and not without it (as --shadows off); off with geometry
// and on without it are other pictures; an unknown value is an error naming
// the option.
TEST(SceneFile, ShadowsOptionAutoOnOff) {
    const fs::path dir = dirWithFrame("scene_shadows");
    const std::string box = R"({"box": {"min": [-0.2, 0.5, -0.2], "max": [0.2, 0.6, 0.2]}})";
    const std::string base = "render " + shellQuote(dir / "f.bgeo") +
                             " --radius 0.01 --eye 2.6,2,3.2 --target 0,0.35,0 --width 120 --height 80 --backend cpu";
    const std::string geometry = " --geometry " + shellQuote(box);
    std::string out;
    auto render = [&](const std::string& name, const std::string& more) {
        EXPECT_EQ(runCli(base + " -o " + shellQuote(dir / name) + more, &out), 0) << out;
        return readBytes(dir / name);
    };
    const auto autoWith = render("a.png", geometry);
    EXPECT_EQ(autoWith, render("b.png", geometry + " --shadows on"));
    EXPECT_NE(autoWith, render("c.png", geometry + " --shadows off"));
    const auto autoWithout = render("d.png", "");
    EXPECT_EQ(autoWithout, render("e.png", " --shadows off"));
    EXPECT_NE(autoWithout, render("f.png", " --shadows on"));
    EXPECT_NE(runCli(base + " -o " + shellQuote(dir / "g.png") + " --shadows sometimes", &out), 0);
    EXPECT_NE(out.find("--shadows"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "g.png"));
}
}  // namespace cli_scene_file_test_local
