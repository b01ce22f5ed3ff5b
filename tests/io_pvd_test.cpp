// ParaView collections (.pvd, src/io/pvd.cpp): parsePvd / readPvd, .pvd as a
// sequence (expandSequence), and `meniscus render x.pvd` rendering its frames.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "test_util.h"

namespace meniscus::io_pvd_test_local {
namespace {

namespace fs = std::filesystem;
using test::failsNaming;
using test::runCli;
using test::shellQuote;
using test::tempDir;
using test::toBytes;
using test::writeText;

std::string pvdText(const std::vector<std::string>& dataSets) {
    std::string s = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                    "  <Collection>\n";
    for (const auto& d : dataSets) s += "    <DataSet " + d + "/>\n";
    return s + "  </Collection>\n</VTKFile>\n";
}

Result<PvdCollection> parse(const std::string& text, const std::string& name = "t.pvd") {
    const auto b = toBytes(text);
    return parsePvd(b, name, "base");
}

// Three small frames, each the demo-sized block moved along x by its number,
// written as .vtu in dir/frames/, and a .pvd listing them out of order.
fs::path threeFramePvd(const fs::path& dir) {
    fs::create_directories(dir / "frames");
    for (int f = 1; f <= 3; ++f) {
        ParticleSet set;
        for (int i = 0; i < 8; ++i)
            for (int j = 0; j < 8; ++j)
                for (int k = 0; k < 8; ++k)
                    set.positions.emplace_back(0.05f * float(i) + 0.1f * float(f), 0.05f * float(j), 0.05f * float(k));
        Attribute id;
        id.name = std::string(kAttrId);
        id.type = AttributeType::Int;
        id.components = 1;
        for (std::size_t p = 0; p < set.positions.size(); ++p) id.ints.push_back(std::int64_t(p) + 1000 * f);
        set.attributes.push_back(id);
        const auto st = writeParticles(dir / "frames" / ("frame_" + std::to_string(f) + ".vtu"), set);
        EXPECT_TRUE(st.ok()) << st.error().describe();
    }
    const fs::path pvd = dir / "series.pvd";
    writeText(pvd, pvdText({R"(timestep="0.2" group="" part="0" file="frames/frame_3.vtu")",
                            R"(timestep="0" group="" part="0" file="frames/frame_1.vtu")",
                            R"(timestep="0.1" group="" part="0" file="frames/frame_2.vtu")"}));
    return pvd;
}

TEST(Pvd, ThreeFramesOutOfOrderReadInTimestepOrder) {
    const fs::path dir = tempDir();
    const fs::path pvd = threeFramePvd(dir);
    const auto c = readPvd(pvd);
    ASSERT_TRUE(c.ok()) << c.error().describe();
    ASSERT_EQ(c->files.size(), 3u);
    EXPECT_EQ(c->times, (std::vector<double>{0.0, 0.1, 0.2}));
    EXPECT_EQ(c->parts, (std::vector<long long>{0, 0, 0}));
    EXPECT_TRUE(c->warnings.empty());
    for (int f = 0; f < 3; ++f)
        EXPECT_EQ(c->files[std::size_t(f)], dir / "frames" / ("frame_" + std::to_string(f + 1) + ".vtu"));

    // As a sequence: the same files, and each loads with its own data.
    EXPECT_TRUE(isSequenceSpec(pvd.string()));
    const auto seq = expandSequence(pvd.string());
    ASSERT_TRUE(seq.ok()) << seq.error().describe();
    EXPECT_EQ(*seq, c->files);
    for (std::size_t f = 0; f < 3; ++f) {
        const auto set = readParticles((*seq)[f]);
        ASSERT_TRUE(set.ok()) << set.error().describe();
        const Attribute* id = set->find(kAttrId);
        ASSERT_TRUE(id);
        EXPECT_EQ(id->ints[0], std::int64_t(1000 * (f + 1)));
    }
}

TEST(Pvd, RenderWritesOneImagePerDataSet) {
    const fs::path dir = tempDir();
    const fs::path pvd = threeFramePvd(dir);
    fs::create_directories(dir / "out");
    std::string out;
    ASSERT_EQ(runCli("render " + shellQuote(pvd) + " -o " + shellQuote(dir / "out" / "f_%02d.png") +
                         " --width 64 --height 48",
                     &out),
              0)
        << out;
    std::vector<std::string> pngs;
    for (const auto& e : fs::directory_iterator(dir / "out")) pngs.push_back(e.path().filename().string());
    std::sort(pngs.begin(), pngs.end());
    EXPECT_EQ(pngs, (std::vector<std::string>{"f_01.png", "f_02.png", "f_03.png"})) << out;
}

TEST(Pvd, RelativeAndAbsolutePathsAndNoTimesteps) {
    const auto c = parse(pvdText({R"(file="a/x_1.vtu")", R"(file="/abs/y.vtu")", R"(file="z.vtp")"}));
    ASSERT_TRUE(c.ok()) << c.error().describe();
    EXPECT_EQ(c->files, (std::vector<fs::path>{"base/a/x_1.vtu", "/abs/y.vtu", "base/z.vtp"}));
    EXPECT_EQ(c->times, (std::vector<double>{0.0, 1.0, 2.0}));  // file order
    EXPECT_FALSE(c->timed);
}

TEST(Pvd, LowestPartOfEachTimestep) {
    const auto c = parse(pvdText({R"(timestep="1" part="1" file="p1_1.vtu")", R"(timestep="1" part="0" file="p0_1.vtu")",
                                  R"(timestep="0.5e0" part="1" file="p1_0.vtu")",
                                  R"(timestep="0.5e0" part="0" file="p0_0.vtu")"}));
    ASSERT_TRUE(c.ok()) << c.error().describe();
    EXPECT_EQ(c->files, (std::vector<fs::path>{"base/p0_0.vtu", "base/p0_1.vtu"}));
    EXPECT_EQ(c->times, (std::vector<double>{0.5, 1.0}));
    ASSERT_EQ(c->warnings.size(), 1u);
    EXPECT_NE(c->warnings[0].find("2 dataset(s)"), std::string::npos) << c->warnings[0];
}

TEST(Pvd, ErrorsNameThePvd) {
    EXPECT_TRUE(failsNaming(parse(""), "t.pvd", "empty"));
    EXPECT_TRUE(failsNaming(parse("<VTKFile type=\"Collection\"><Collection>"), "t.pvd", "XML"));
    EXPECT_TRUE(failsNaming(parse(pvdText({})), "t.pvd", "no datasets"));
    EXPECT_TRUE(failsNaming(parse("<VTKFile type=\"UnstructuredGrid\"><Collection/></VTKFile>"), "t.pvd",
                          "not a ParaView collection"));
    EXPECT_TRUE(failsNaming(parse("<Collection/>"), "t.pvd", "not a ParaView collection"));
    EXPECT_TRUE(failsNaming(parse("<VTKFile type=\"Collection\"></VTKFile>"), "t.pvd", "<Collection>"));
    EXPECT_TRUE(failsNaming(parse(pvdText({R"(timestep="0.1s" file="a.vtu")"})), "t.pvd", "bad timestep '0.1s'"));
    EXPECT_TRUE(failsNaming(parse(pvdText({R"(timestep="nan" file="a.vtu")"})), "t.pvd", "bad timestep"));
    EXPECT_TRUE(failsNaming(parse(pvdText({R"(timestep="inf" file="a.vtu")"})), "t.pvd", "bad timestep"));
    EXPECT_TRUE(failsNaming(parse(pvdText({R"(timestep="" file="a.vtu")"})), "t.pvd", "bad timestep"));
    EXPECT_TRUE(failsNaming(parse(pvdText({R"(timestep="1")"})), "t.pvd", "no file"));
    EXPECT_TRUE(failsNaming(parse(pvdText({R"(timestep="1" file="a.vtu")", R"(file="b.vtu")"})), "t.pvd",
                          "no timestep"));
    EXPECT_TRUE(failsNaming(parse(pvdText({R"(timestep="1" part="-1" file="a.vtu")"})), "t.pvd", "bad part"));
    EXPECT_TRUE(failsNaming(parse(pvdText({R"(timestep="1" file="a.vtu")", R"(timestep="1.0" file="b.vtu")"})),
                          "t.pvd", "both timestep 1"));

    // On the disk: a missing .pvd, and a .pvd listing a missing file.
    const fs::path dir = tempDir();
    const fs::path missing = dir / "none.pvd";
    EXPECT_TRUE(failsNaming(readPvd(missing), missing.string(), "no such file"));
    const auto seq = expandSequence(missing.string());
    ASSERT_FALSE(seq.ok());
    const fs::path pvd = dir / "gone.pvd";
    writeText(pvd, pvdText({R"(timestep="0.25" file="frames/f_7.vtu")"}));
    EXPECT_TRUE(failsNaming(readPvd(pvd), pvd.string(), "does not exist"));
    const auto seq2 = expandSequence(pvd.string());
    ASSERT_FALSE(seq2.ok());
    EXPECT_EQ(seq2.error().file, pvd.string());
    EXPECT_NE(seq2.error().message.find("f_7.vtu"), std::string::npos) << seq2.error().message;

    std::string out;
    EXPECT_NE(runCli("render " + shellQuote(pvd) + " -o " + shellQuote(dir / "f_%02d.png") + " --width 64 --height 48",
                     &out),
              0);
    EXPECT_NE(out.find("gone.pvd"), std::string::npos) << out;
}

// A movie's rate from the data: evenly spaced times give 1 / dt, anything
// else none; a .pvd carries a rate only when it gives timesteps.
TEST(Pvd, FrameRateOfEvenTimesteps) {
    EXPECT_NEAR(*evenFrameRate(std::vector<double>{0.0, 0.04, 0.08, 0.12}), 25.0, 1e-9);
    EXPECT_NEAR(*evenFrameRate(std::vector<double>{1.0, 1.0 + 1.0 / 15, 1.0 + 2.0 / 15}), 15.0, 1e-9);
    EXPECT_FALSE(evenFrameRate(std::vector<double>{0.0}));
    EXPECT_FALSE(evenFrameRate(std::vector<double>{0.0, 0.1, 0.3}));  // uneven
    EXPECT_FALSE(evenFrameRate(std::vector<double>{0.2, 0.1, 0.0}));  // decreasing
    EXPECT_FALSE(evenFrameRate(std::vector<double>{0.0, 0.0}));
    const fs::path dir = tempDir();
    const std::vector<fs::path> files = {dir / "a.xyz", dir / "b.xyz", dir / "c.xyz"};
    for (const fs::path& f : files) writeText(f, "0 0 0\n");
    ASSERT_TRUE(writePvd(dir / "timed.pvd", files, {0.0, 0.5, 1.0}).ok());
    auto rate = frameRateOfInput(dir / "timed.pvd");
    ASSERT_TRUE(rate.ok()) << rate.error().describe();
    EXPECT_NEAR(rate->value(), 2.0, 1e-9);
    writeText(dir / "untimed.pvd", "<VTKFile type=\"Collection\"><Collection><DataSet file=\"a.xyz\"/>"
                                  "<DataSet file=\"b.xyz\"/></Collection></VTKFile>");
    rate = frameRateOfInput(dir / "untimed.pvd");
    ASSERT_TRUE(rate.ok()) << rate.error().describe();
    EXPECT_FALSE(rate->has_value());
    rate = frameRateOfInput(dir / "a.xyz");
    ASSERT_TRUE(rate.ok());
    EXPECT_FALSE(rate->has_value());
}

}  // namespace
}  // namespace meniscus::io_pvd_test_local
