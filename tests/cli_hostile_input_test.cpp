// What a hostile or mistaken input can do to the command line: an error
// naming the file or option and the problem, with the exit code of
// docs/usage.md#errors (1: the data or the run failed; 2: the command line or
// a scene file's values are wrong), never a crash, an unbounded read or a run
// that "succeeds" having written nothing.
//  - JSON files (render scene files, --camera-path files, simulation scenes)
//    are read within their limits (include/meniscus/json_text.h): a file of
//    /dev/zero or a huge sparse file stops at the limit, deep nesting is
//    refused before it is parsed;
//  - frame rates and durations are bounded where they are read;
//  - a bad option value exits 2 wherever it comes from.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "test_util.h"

namespace cli_hostile_input_test_local {

namespace fs = std::filesystem;
using namespace meniscus;
using namespace meniscus::test;

namespace {

bool has(const std::string& out, const std::string& what) { return out.find(what) != std::string::npos; }

// `render DIR/f.bgeo -o DIR/o.png`, small and on the CPU, with `more` options.
std::string render(const fs::path& dir, const std::string& more) {
    return "render " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "o.png") +
           " --width 32 --height 24 --backend cpu " + more;
}

// `[[[...]]]`, `depth` deep.
std::string nested(std::size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); }

}  // namespace

// 100,000 nested brackets in camera.path once overflowed the stack of the
// recursive code that copies and prints JSON values (SIGSEGV); the nesting is
// now refused by a scan of the bytes before the file is parsed.
TEST(CliHostileInput, DeeplyNestedSceneFileIsRefusedNotACrash) {
    const fs::path dir = dirWithFrame("hostile_nested");
    const auto withPath = [](const std::string& eye) {
        return "{\"particles\": \"f.bgeo\", \"camera\": {\"path\": [{\"time\": 0, \"eye\": " + eye + "}]}}";
    };
    writeText(dir / "s.json", withPath(nested(100000)));
    std::string out;
    EXPECT_EQ(runCli("render " + shellQuote(dir / "s.json") + " -o " + shellQuote(dir / "o.png"), &out), 1) << out;
    EXPECT_TRUE(has(out, "s.json: nested deeper than 64 levels")) << out;
    EXPECT_FALSE(fs::exists(dir / "o.png"));
    // Within the scene file's depth, the camera path's own limit speaks.
    writeText(dir / "s.json", withPath(nested(20)));
    EXPECT_EQ(runCli("render " + shellQuote(dir / "s.json") + " -o " + shellQuote(dir / "o.png"), &out), 2) << out;
    EXPECT_TRUE(has(out, "camera.path")) << out;
    EXPECT_TRUE(has(out, "nested deeper than 8 levels")) << out;
    // As the value of --camera-path, inline (as deep as one argument may be
    // long, 128 KiB) and in a file.
    EXPECT_EQ(runCli(render(dir, "--camera-path '" + nested(30000) + "'"), &out), 2) << out;
    EXPECT_TRUE(has(out, "--camera-path: nested deeper than 8 levels")) << out;
    writeText(dir / "p.json", nested(100000));  // a file that cannot be read: the data's error
    EXPECT_EQ(runCli(render(dir, "--camera-path " + shellQuote(dir / "p.json")), &out), 1) << out;
    EXPECT_TRUE(has(out, "nested deeper than 8 levels")) << out;
    EXPECT_FALSE(fs::exists(dir / "o.png"));
}

// Brackets inside strings (escaped quotes among them) are not nesting.
TEST(CliHostileInput, BracketsInsideStringsAreNotNesting) {
    const fs::path dir = dirWithFrame("hostile_strings");
    writeText(dir / "s.json", "{\"particles\": \"f.bgeo\", \"note\": \"" + std::string(200, '[') + "\\\"" +
                                  std::string(200, '{') + "\"}");
    std::string out;
    EXPECT_EQ(runCli("render " + shellQuote(dir / "s.json") + " -o " + shellQuote(dir / "o.png"), &out), 2) << out;
    EXPECT_TRUE(has(out, "note: unknown key")) << out;  // read and parsed: its key is what is wrong
}

// A scene file that never ends (/dev/zero) is read up to its limit and no
// further; a huge (sparse) one is refused from its size, unread.
TEST(CliHostileInput, EndlessOrHugeJsonFilesStopAtTheirLimit) {
    const fs::path dir = dirWithFrame("hostile_endless");
    std::error_code ec;
    fs::create_symlink("/dev/zero", dir / "zero.json", ec);
    ASSERT_FALSE(ec) << ec.message();
    std::string out;
    EXPECT_EQ(runCli("render " + shellQuote(dir / "zero.json") + " -o " + shellQuote(dir / "o.png"), &out), 1) << out;
    EXPECT_TRUE(has(out, "zero.json: larger than the 16 MiB a render scene file may be")) << out;
    EXPECT_EQ(runCli(render(dir, "--camera-path " + shellQuote(dir / "zero.json")), &out), 1) << out;
    EXPECT_TRUE(has(out, "larger than the 16 MiB a camera path may be")) << out;
    EXPECT_EQ(runCli("simulate " + shellQuote(dir / "zero.json") + " -o " + shellQuote(dir / "f_%04d.bgeo"), &out), 1)
        << out;
    EXPECT_TRUE(has(out, "zero.json: larger than the 4 MiB a simulation scene may be")) << out;

    // 20 GB of nothing, sparse: refused by its size.
    const fs::path huge = dir / "huge.json";
    { std::ofstream(huge) << "{"; }
    fs::resize_file(huge, std::uintmax_t(20) << 30, ec);
    if (ec) GTEST_SKIP() << "no sparse files here: " << ec.message();
    EXPECT_EQ(runCli("render " + shellQuote(huge) + " -o " + shellQuote(dir / "o.png"), &out), 1) << out;
    EXPECT_TRUE(has(out, "huge.json: larger than the 16 MiB a render scene file may be")) << out;
    EXPECT_EQ(runCli("simulate " + shellQuote(huge) + " -o " + shellQuote(dir / "f_%04d.bgeo"), &out), 1) << out;
    EXPECT_TRUE(has(out, "huge.json: larger than the 4 MiB a simulation scene may be")) << out;
    fs::remove(huge);
    EXPECT_FALSE(fs::exists(dir / "o.png"));
    EXPECT_FALSE(fs::exists(dir / "f_0000.bgeo"));
}

// A frame rate or duration too large to count frames of (3e38 once
// overflowed the frame count: exit 0, nothing written) is the value's error.
TEST(CliHostileInput, HugeFpsOrDurationIsTheValuesError) {
    const fs::path dir = tempDir();
    const fs::path scene = writeSmallScene(dir);
    const std::string simulate = "simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "f_%04d.bgeo");
    std::string out;
    EXPECT_EQ(runCli(simulate + " --fps 3e38", &out), 2) << out;
    EXPECT_TRUE(has(out, "--fps")) << out;
    EXPECT_TRUE(has(out, "1000")) << out;  // the range
    EXPECT_EQ(runCli(simulate + " --duration 3e38", &out), 2) << out;
    EXPECT_TRUE(has(out, "--duration")) << out;
    for (const char* field : {"fps", "duration"}) {
        writeText(dir / "big.json", "{\"version\": 1, \"" + std::string(field) +
                                        "\": 3e38, \"params\": {\"radius\": 0.01}, \"domain\": {\"min\": [0, 0, 0], "
                                        "\"max\": [0.4, 0.4, 0.1]}, \"fluid\": [{\"box\": {\"min\": [0, 0, 0], "
                                        "\"max\": [0.2, 0.3, 0.1]}}]}");
        EXPECT_EQ(runCli("simulate " + shellQuote(dir / "big.json") + " -o " + shellQuote(dir / "f_%04d.bgeo"), &out), 2)
            << out;
        EXPECT_TRUE(has(out, "big.json: " + std::string(field) + ": must be at most")) << out;
    }
    EXPECT_FALSE(fs::exists(dir / "f_0000.bgeo"));
}

// A bad option value exits 2, from the command line or a scene file, and
// says what is wrong in the option's terms.
TEST(CliHostileInput, BadOptionValuesExitTwoInTheOptionsTerms) {
    const fs::path dir = dirWithFrame("hostile_options");
    struct Case {
        std::string options, says;
    };
    const Case cases[] = {
        {"--width 0", "--width"},
        {"--iso 5", "--iso"},
        {"--cube-size 100", "--cube-size"},
        {"--shard 5/3", "--shard 5/3"},
        {"--eye nan,0,0 --target 0,0,0", "--eye"},
        {"--fov 180", "--fov"},
        {"--fov 0", "--fov"},
        {"--light 0,0,0", "--light 0,0,0: the direction toward the light cannot be zero"},
    };
    for (const Case& c : cases) {
        std::string out;
        EXPECT_EQ(runCli(render(dir, c.options), &out), 2) << c.options << "\n" << out;
        EXPECT_TRUE(has(out, c.says)) << c.options << "\n" << out;
        EXPECT_FALSE(fs::exists(dir / "o.png")) << c.options;
    }
    // The mesher's values, checked as options before a frame is read.
    for (const char* options : {"--iso 5", "--cube-size 100", "--support 40", "--block 2"}) {
        std::string out;
        EXPECT_EQ(runCli("mesh " + shellQuote(dir / "f.bgeo") + " -o " + shellQuote(dir / "m.ply") + " " + options, &out), 2)
            << options << "\n" << out;
        EXPECT_TRUE(has(out, std::string(options).substr(0, std::string(options).find(' ')))) << options << "\n" << out;
        EXPECT_FALSE(fs::exists(dir / "m.ply")) << options;
    }
    // The same values from a render scene file: 2, naming the key.
    writeText(dir / "s.json", "{\"particles\": \"f.bgeo\", \"render\": {\"iso\": 5}}");
    std::string out;
    EXPECT_EQ(runCli("render " + shellQuote(dir / "s.json") + " -o " + shellQuote(dir / "o.png"), &out), 2) << out;
    EXPECT_TRUE(has(out, "render.iso")) << out;
    writeText(dir / "s.json", "{\"particles\": \"f.bgeo\", \"light\": [0, 0, 0]}");
    EXPECT_EQ(runCli("render " + shellQuote(dir / "s.json") + " -o " + shellQuote(dir / "o.png"), &out), 2) << out;
    EXPECT_TRUE(has(out, "cannot be zero")) << out;
    // Data that cannot be read is 1.
    EXPECT_EQ(runCli("render " + shellQuote(dir / "missing.bgeo") + " -o " + shellQuote(dir / "o.png"), &out), 1)
        << out;
}

// A simulation scene's values are the settings too: 2, the value as written.
TEST(CliHostileInput, BadSimulationSceneValuesExitTwo) {
    const fs::path dir = tempDir();
    writeText(dir / "tiny.json",
              "{\"version\": 1, \"params\": {\"radius\": 1e-9}, \"domain\": {\"min\": [0, 0, 0], \"max\": [0.4, 0.4, "
              "0.1]}, \"fluid\": [{\"box\": {\"min\": [0, 0, 0], \"max\": [0.2, 0.3, 0.1]}}]}");
    std::string out;
    EXPECT_EQ(runCli("simulate " + shellQuote(dir / "tiny.json") + " -o " + shellQuote(dir / "f_%04d.bgeo"), &out), 2)
        << out;
    EXPECT_TRUE(has(out, "radius 1e-09 m is not in [1e-6, 10]")) << out;
    // Not JSON at all is the data's failure: 1.
    writeText(dir / "bad.json", "{\"version\": 1,");
    EXPECT_EQ(runCli("simulate " + shellQuote(dir / "bad.json") + " -o " + shellQuote(dir / "f_%04d.bgeo"), &out), 1)
        << out;
    EXPECT_FALSE(fs::exists(dir / "f_0000.bgeo"));
}
}  // namespace cli_hostile_input_test_local
