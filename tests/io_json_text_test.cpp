// JSON text read within bounds (include/meniscus/json_text.h): the size
// refused from the file's size or at the limit while reading (a device that
// never ends), the nesting refused by a scan of the bytes that minds strings
// and their escapes, errors naming the file and the limit.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "meniscus/geometry.h"
#include "meniscus/json_text.h"
#include "meniscus/sim.h"
#include "test_util.h"

namespace io_json_text_test_local {

namespace fs = std::filesystem;
using namespace meniscus;
using namespace meniscus::test;

namespace {

constexpr JsonLimits kSmall{100, 3, "a test file"};

std::string said(const Status& st) { return st ? std::string("ok") : st.error().describe(); }

}  // namespace

TEST(JsonText, NestingIsCountedOutsideStringsOnly) {
    EXPECT_TRUE(checkJsonText("[[[1]]]", "t.json", kSmall));
    EXPECT_EQ(said(checkJsonText("[[[[1]]]]", "t.json", kSmall)),
              "t.json: nested deeper than 3 levels (line 1, column 4); a test file never needs that");
    EXPECT_EQ(said(checkJsonText("{\"a\":\n [{\"b\": [[]]}]}", "t.json", kSmall)),
              "t.json: nested deeper than 3 levels (line 2, column 9); a test file never needs that");
    // Brackets in strings, an escaped quote and an escaped backslash among them.
    EXPECT_TRUE(checkJsonText(R"(["[[[[", "\"[[[[", "\\", ["{{{{"]])", "t.json", kSmall));
    EXPECT_FALSE(checkJsonText(R"(["\\", [[["x"]]]])", "t.json", kSmall));  // \\ ends the escape: the string closes
    // More closing than opening brackets is the parser's to say; the scan goes on.
    EXPECT_TRUE(checkJsonText("]]]]]] [[[1]]]", "t.json", kSmall));
}

TEST(JsonText, SizeIsCheckedBeforeNesting) {
    EXPECT_EQ(said(checkJsonText(std::string(101, '['), "t.json", kSmall)),
              "t.json: larger than the 100 bytes a test file may be");
    EXPECT_TRUE(checkJsonText(std::string(100, ' '), "t.json", kSmall));
    EXPECT_EQ(byteSizeText(std::uintmax_t(16) << 20), "16 MiB");
    EXPECT_EQ(byteSizeText(4096), "4 KiB");
    EXPECT_EQ(byteSizeText(1000), "1000 bytes");
}

TEST(JsonText, ReadsAFileWithinItsLimits) {
    const fs::path dir = tempDir();
    writeText(dir / "ok.json", "[[1]]");
    auto ok = readJsonText(dir / "ok.json", kSmall);
    ASSERT_TRUE(ok.ok()) << ok.error().describe();
    EXPECT_EQ(*ok, "[[1]]");
    writeText(dir / "big.json", std::string(101, ' '));
    EXPECT_TRUE(failsNaming(readJsonText(dir / "big.json", kSmall), (dir / "big.json").string(), "larger than the 100 bytes"));
    writeText(dir / "deep.json", "[[[[1]]]]");
    EXPECT_TRUE(failsNaming(readJsonText(dir / "deep.json", kSmall), (dir / "deep.json").string(), "nested deeper than 3"));
    writeText(dir / "empty.json", "");
    EXPECT_TRUE(failsNaming(readJsonText(dir / "empty.json", kSmall), (dir / "empty.json").string(), "the file is empty"));
    EXPECT_TRUE(failsNaming(readJsonText(dir / "none.json", kSmall), (dir / "none.json").string(), "no such file"));
    EXPECT_TRUE(failsNaming(readJsonText(dir, kSmall), dir.string(), "is a directory"));
}

// A device that never ends is read up to the limit and no further; a huge
// sparse file is refused from its size.
TEST(JsonText, EndlessAndHugeFilesStopAtTheLimit) {
    const fs::path dir = tempDir();
    std::error_code ec;
    fs::create_symlink("/dev/zero", dir / "zero.json", ec);
    ASSERT_FALSE(ec) << ec.message();
    for (const JsonLimits& limits : {kSmall, json_limits::kRenderScene, json_limits::kSimulationScene})
        EXPECT_TRUE(failsNaming(readJsonText(dir / "zero.json", limits), (dir / "zero.json").string(),
                                "larger than the " + byteSizeText(limits.maxBytes) + " " + limits.kind + " may be"));
    writeText(dir / "huge.json", "{");
    fs::resize_file(dir / "huge.json", std::uintmax_t(20) << 30, ec);
    if (ec) GTEST_SKIP() << "no sparse files here: " << ec.message();
    EXPECT_TRUE(failsNaming(readJsonText(dir / "huge.json", json_limits::kGeometry), (dir / "huge.json").string(),
                            "larger than the 16 MiB a geometry JSON file may be"));
    fs::remove(dir / "huge.json");
}

// Every JSON reader goes through these limits.
TEST(JsonText, EveryReaderRefusesTheDeepDocument) {
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    EXPECT_TRUE(failsNaming(parseGeometry(deep, "g.json", {}), "g.json", "nested deeper than 64"));
    EXPECT_TRUE(failsNaming(parseSplishSplashScene(deep, "s.json", {}), "s.json", "nested deeper than 64"));
    EXPECT_TRUE(failsNaming(sim::parseScene(deep, "sim.json"), "sim.json", "nested deeper than 16"));
    const fs::path dir = tempDir();
    writeText(dir / "deep.json", deep);
    EXPECT_TRUE(failsNaming(readGeometry((dir / "deep.json").string()), (dir / "deep.json").string(), "nested deeper"));
    EXPECT_TRUE(failsNaming(sim::readScene(dir / "deep.json"), (dir / "deep.json").string(), "nested deeper"));
}
}  // namespace io_json_text_test_local
