// Frame sequences: directory / glob / printf expansion in natural order,
// naturalLess as a strict weak order, and output names from printf patterns.
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "test_util.h"

namespace meniscus::io_sequence_test_local {
namespace {

namespace fs = std::filesystem;
using test::tempDir;
using test::writeText;

std::vector<std::string> fileNames(const std::vector<fs::path>& paths) {
    std::vector<std::string> out;
    for (const fs::path& p : paths) out.push_back(p.filename().string());
    return out;
}

// ParticleData_Fluid_{1,2,10,11,3}.bgeo plus files that must be ignored.
fs::path makeSplishDir() {
    const fs::path dir = tempDir();
    for (int n : {1, 2, 10, 11, 3}) writeText(dir / ("ParticleData_Fluid_" + std::to_string(n) + ".bgeo"), "");
    writeText(dir / ".ParticleData_Fluid_4.bgeo", "");      // hidden
    writeText(dir / "ParticleData_Fluid_5.bgeo.tmp", "");   // being written
    writeText(dir / "ParticleData_Fluid_6.bgeo~", "");      // editor backup
    writeText(dir / "README.txt", "");
    writeText(dir / "stats.csv", "");                        // another kind, less numerous
    fs::create_directories(dir / "ParticleData_Fluid_7.bgeo");  // a directory, not a file
    return dir;
}

const std::vector<std::string> kExpected = {"ParticleData_Fluid_1.bgeo", "ParticleData_Fluid_2.bgeo",
                                            "ParticleData_Fluid_3.bgeo", "ParticleData_Fluid_10.bgeo",
                                            "ParticleData_Fluid_11.bgeo"};

TEST(Sequence, DirectoryInNaturalOrder) {
    const fs::path dir = makeSplishDir();
    const auto frames = expandSequence(dir.string());
    ASSERT_TRUE(frames.ok()) << frames.error().describe();
    EXPECT_EQ(fileNames(frames.value()), kExpected);
    EXPECT_EQ(frames->front(), dir / "ParticleData_Fluid_1.bgeo");
    EXPECT_TRUE(isSequenceSpec(dir.string()));
}

TEST(Sequence, GlobInNaturalOrder) {
    const fs::path dir = makeSplishDir();
    const auto frames = expandSequence((dir / "ParticleData_Fluid_*.bgeo").string());
    ASSERT_TRUE(frames.ok()) << frames.error().describe();
    EXPECT_EQ(fileNames(frames.value()), kExpected);

    const auto oneDigit = expandSequence((dir / "ParticleData_Fluid_?.bgeo").string());
    ASSERT_TRUE(oneDigit.ok()) << oneDigit.error().describe();
    EXPECT_EQ(fileNames(oneDigit.value()),
              (std::vector<std::string>{"ParticleData_Fluid_1.bgeo", "ParticleData_Fluid_2.bgeo",
                                        "ParticleData_Fluid_3.bgeo"}));
    EXPECT_TRUE(isSequenceSpec((dir / "ParticleData_Fluid_*.bgeo").string()));
}

TEST(Sequence, PrintfInNaturalOrder) {
    const fs::path dir = makeSplishDir();
    const auto frames = expandSequence((dir / "ParticleData_Fluid_%d.bgeo").string());
    ASSERT_TRUE(frames.ok()) << frames.error().describe();
    EXPECT_EQ(fileNames(frames.value()), kExpected);
    EXPECT_TRUE(isSequenceSpec((dir / "ParticleData_Fluid_%d.bgeo").string()));
}

TEST(Sequence, ZeroPaddedPrintf) {
    const fs::path dir = tempDir();
    for (const char* n : {"frame_0010.ply", "frame_0002.ply", "frame_0001.ply", "frame_12345.ply", "frame_1.ply",
                          "frame_0003.ply.part", "frame_00x4.ply", "other_0005.ply"})
        writeText(dir / n, "");
    const auto frames = expandSequence((dir / "frame_%04d.ply").string());
    ASSERT_TRUE(frames.ok()) << frames.error().describe();
    EXPECT_EQ(fileNames(frames.value()),
              (std::vector<std::string>{"frame_0001.ply", "frame_0002.ply", "frame_0010.ply", "frame_12345.ply"}));
}

TEST(Sequence, SpacePaddedPrintfAndLiteralPercent) {
    const fs::path dir = tempDir();
    // printf("f%3d%%", n) writes "f  7%", "f 12%", "f123%"; "f 7%" and "f 1 %" it never writes.
    for (const char* n : {"f  7%.xyz", "f 12%.xyz", "f123%.xyz", "f 1 %.xyz", "f 7%.xyz"}) writeText(dir / n, "");
    const auto frames = expandSequence((dir / "f%3d%%.xyz").string());
    ASSERT_TRUE(frames.ok()) << frames.error().describe();
    EXPECT_EQ(fileNames(frames.value()), (std::vector<std::string>{"f  7%.xyz", "f 12%.xyz", "f123%.xyz"}));
}

TEST(Sequence, DirectoryPicksTheMostNumerousKind) {
    const fs::path dir = tempDir();
    for (const char* n : {"a_1.vtk", "a_2.vtk", "a_1.ply", "a_2.ply", "a_3.ply", "notes.txt", "a_1.bgeo.gz"})
        writeText(dir / n, "");
    const auto frames = expandSequence(dir.string());
    ASSERT_TRUE(frames.ok()) << frames.error().describe();
    EXPECT_EQ(fileNames(frames.value()), (std::vector<std::string>{"a_1.ply", "a_2.ply", "a_3.ply"}));
}

TEST(Sequence, DirectoryWithCompressedBgeo) {
    const fs::path dir = tempDir();
    for (const char* n : {"f_10.bgeo.gz", "f_9.bgeo.gz", "f_1.bgeo"}) writeText(dir / n, "");
    const auto frames = expandSequence(dir.string());
    ASSERT_TRUE(frames.ok()) << frames.error().describe();
    EXPECT_EQ(fileNames(frames.value()), (std::vector<std::string>{"f_9.bgeo.gz", "f_10.bgeo.gz"}));
}

TEST(Sequence, PlainFileIsItself) {
    const fs::path dir = tempDir();
    // Even a name that looks like a pattern is taken literally when the file exists.
    for (const char* n : {"single.ply", "odd_%d_*.csv"}) {
        writeText(dir / n, "");
        const auto frames = expandSequence((dir / n).string());
        ASSERT_TRUE(frames.ok()) << frames.error().describe();
        ASSERT_EQ(frames->size(), 1u);
        EXPECT_EQ(frames->front(), dir / n);
        EXPECT_FALSE(isSequenceSpec((dir / n).string()));
    }
}

TEST(Sequence, NoMatchNamesTheSpec) {
    const fs::path dir = makeSplishDir();
    for (const fs::path& spec : {dir / "nothing_*.bgeo", dir / "nothing_%04d.bgeo", dir / "missing.bgeo",
                                 dir / "no_such_dir" / "f_%d.ply", dir / "no_such_dir" / "*.ply"}) {
        const auto frames = expandSequence(spec.string());
        ASSERT_FALSE(frames.ok()) << spec;
        EXPECT_NE(frames.error().describe().find(spec.string()), std::string::npos) << frames.error().describe();
    }
    const fs::path empty = dir / "empty_dir";
    fs::create_directories(empty);
    writeText(empty / "readme.md", "");
    const auto none = expandSequence(empty.string());
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().describe().find(empty.string()), std::string::npos);
    EXPECT_NE(none.error().describe().find("no particle files"), std::string::npos);
}

TEST(Sequence, BadPatternsAreErrors) {
    const fs::path dir = makeSplishDir();
    for (const char* bad : {"f_%d_%d.bgeo", "f_%s.bgeo", "f_%5.2f.bgeo", "f_%d_*.bgeo", "f_%"}) {
        const std::string spec = (dir / bad).string();
        const auto frames = expandSequence(spec);
        ASSERT_FALSE(frames.ok()) << spec;
        EXPECT_NE(frames.error().describe().find(spec), std::string::npos) << frames.error().describe();
    }
    const auto wildDir = expandSequence((dir / "*" / "x.bgeo").string());
    ASSERT_FALSE(wildDir.ok());
    EXPECT_NE(wildDir.error().describe().find("file name"), std::string::npos) << wildDir.error().describe();
}

TEST(Sequence, IsSequenceSpec) {
    EXPECT_TRUE(isSequenceSpec("frames/f_%04d.ply"));
    EXPECT_TRUE(isSequenceSpec("frames/f_*.ply"));
    EXPECT_TRUE(isSequenceSpec("frames/f_?.ply"));
    EXPECT_FALSE(isSequenceSpec("frames/f_100%%.ply"));
    EXPECT_FALSE(isSequenceSpec("frames/does_not_exist.ply"));
    EXPECT_FALSE(isSequenceSpec(""));
}

// ---------------------------------------------------------------- naturalLess

TEST(NaturalLess, NumbersByValue) {
    EXPECT_TRUE(naturalLess("a_2", "a_10"));
    EXPECT_FALSE(naturalLess("a_10", "a_2"));
    EXPECT_TRUE(naturalLess("ParticleData_Fluid_9.bgeo", "ParticleData_Fluid_21.bgeo"));
    EXPECT_TRUE(naturalLess("a_99", "a_123456789012345678901234567890"));  // beyond 64 bits
    EXPECT_TRUE(naturalLess("a", "a_1"));
    EXPECT_TRUE(naturalLess("a_1", "b_0"));
    EXPECT_TRUE(naturalLess("A", "a"));  // bytewise outside digits
    EXPECT_FALSE(naturalLess("a_2", "a_2"));
    EXPECT_TRUE(naturalLess("x1y2", "x1y10"));
    EXPECT_TRUE(naturalLess("x2y1", "x10y0"));
}

TEST(NaturalLess, PaddingTieIsConsistent) {
    // Equal values with different padding: exactly one order, the same every time.
    EXPECT_NE(naturalLess("a_02", "a_2"), naturalLess("a_2", "a_02"));
    EXPECT_TRUE(naturalLess("a_2", "a_02"));
    EXPECT_TRUE(naturalLess("a_02", "a_3"));
    EXPECT_TRUE(naturalLess("a_2", "a_002"));
    EXPECT_TRUE(naturalLess("a_0", "a_00"));
    // The padding only breaks ties: later text decides first.
    EXPECT_TRUE(naturalLess("a_02b", "a_2c"));
}

TEST(NaturalLess, StrictWeakOrderOnASample) {
    const std::vector<std::string> s = {"",      "a",      "a_",     "a_0",   "a_00",  "a_1",    "a_01",
                                        "a_001", "a_2",    "a_02",   "a_10",  "a_010", "a_2b",   "a_02b",
                                        "a_2c",  "a_02c",  "a_1_1",  "a_1_01", "a_01_1", "b",     "B",
                                        "1",     "01",     "10",     "a_9x",  "a_9",   "a_ 9",   "a_-9",
                                        "x1y2",  "x01y2",  "x1y02",  "x1y10", "9999999999999999999999", "z"};
    for (const auto& a : s) {
        EXPECT_FALSE(naturalLess(a, a)) << a;
        for (const auto& b : s) {
            if (a != b) {
                EXPECT_NE(naturalLess(a, b), naturalLess(b, a)) << a << " vs " << b;  // total on distinct strings
            }
            for (const auto& c : s) {
                if (naturalLess(a, b) && naturalLess(b, c)) {
                    EXPECT_TRUE(naturalLess(a, c)) << a << " " << b << " " << c;
                }
            }
        }
    }
    std::vector<std::string> sorted = s;
    std::sort(sorted.begin(), sorted.end(), [](const std::string& a, const std::string& b) { return naturalLess(a, b); });
    EXPECT_TRUE(std::is_sorted(sorted.begin(), sorted.end(),
                               [](const std::string& a, const std::string& b) { return naturalLess(a, b); }));
}

// ---------------------------------------------------------------- formatFramePattern

TEST(FormatFramePattern, Formats) {
    auto check = [](const std::string& pattern, long n, const std::string& expected) {
        const auto r = formatFramePattern(pattern, n);
        ASSERT_TRUE(r.ok()) << pattern << ": " << r.error().describe();
        EXPECT_EQ(r.value(), expected);
    };
    check("out_%04d.png", 7, "out_0007.png");
    check("out_%04d.png", 123456, "out_123456.png");
    check("out_%d.exr", 21, "out_21.exr");
    check("dir/f%3d.png", 5, "dir/f  5.png");
    check("100%%_%02d.png", 3, "100%_03.png");
    check("%d", 0, "0");
}

TEST(FormatFramePattern, Errors) {
    for (const char* bad : {"out.png", "a%d_%d", "a%s.png", "a%5.2f.png", "trailing%", "a%ld.png", "%%only.png"}) {
        const auto r = formatFramePattern(bad, 1);
        ASSERT_FALSE(r.ok()) << bad;
        EXPECT_NE(r.error().describe().find(bad), std::string::npos) << r.error().describe();
    }
    EXPECT_NE(formatFramePattern("out.png", 1).error().describe().find("no %d"), std::string::npos);
    EXPECT_NE(formatFramePattern("a%d_%d", 1).error().describe().find("more than one"), std::string::npos);
}

}  // namespace
}  // namespace meniscus::io_sequence_test_local
