// Frame-parallel rendering without MPI: `render --shard I/N` renders the I-th
// of N contiguous shares of a sequence, named as in the whole run, and the N
// runs together write the whole run's images byte for byte: with the noise's
// turbulence (whose memory spans frames) and for a simulation scene (stepped
// through every frame time) too. --resume keeps the same bytes as well.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_util.h"

namespace cli_shard_test_local {

namespace fs = std::filesystem;
using namespace meniscus::test;

namespace {

const char* const kFrames[] = {"1", "9", "21", "61"};

// DIR/in holding four real frames of the small dam break.
fs::path sequenceDir(const std::string& name) {
    const fs::path dir = tempDir() / name;
    fs::create_directories(dir / "in");
    for (const char* n : kFrames)
        fs::copy_file(testData(std::string("splishsplash/partio/ParticleData_Fluid_") + n + ".bgeo"),
                      dir / "in" / (std::string("ParticleData_Fluid_") + n + ".bgeo"));
    return dir;
}

std::string render(const fs::path& in, const fs::path& out, const std::string& more) {
    return "render " + shellQuote(in) + " -o " + shellQuote(out) + " --width 96 --height 64 --backend cpu " + more;
}

std::vector<std::string> names(const fs::path& dir) {
    std::vector<std::string> out;
    if (fs::exists(dir))
        for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

// Every file of `whole` has a byte-identical twin in `parts`, and nothing more is there.
void expectSameFiles(const fs::path& whole, const fs::path& parts) {
    ASSERT_EQ(names(whole), names(parts));
    ASSERT_FALSE(names(whole).empty());
    for (const std::string& n : names(whole)) EXPECT_EQ(readBytes(whole / n), readBytes(parts / n)) << n;
}

// `in` rendered with `more` as a whole run into DIR/whole and as `shares`
// runs of --shard I/N into DIR/parts; the frames each share wrote, in order.
std::vector<std::size_t> renderInShares(const fs::path& in, const fs::path& dir, const std::string& more, int shares) {
    std::string out;
    fs::create_directories(dir / "whole");
    fs::create_directories(dir / "parts");
    EXPECT_EQ(runCli(render(in, dir / "whole" / "f_%02d.png", more), &out), 0) << out;
    std::vector<std::size_t> written;
    for (int i = 0; i < shares; ++i) {
        const std::size_t before = names(dir / "parts").size();
        const std::string shard = " --shard " + std::to_string(i) + "/" + std::to_string(shares);
        EXPECT_EQ(runCli(render(in, dir / "parts" / "f_%02d.png", more + shard), &out), 0) << out;
        written.push_back(names(dir / "parts").size() - before);
    }
    return written;
}

}  // namespace

TEST(CliShard, SharesTogetherWriteTheWholeRunsImagesWithTurbulentNoise) {
    const fs::path dir = sequenceDir("shard_noise");
    // Contiguous shares of 4 frames over 3: 1, 1 and 2 frames.
    EXPECT_EQ(renderInShares(dir / "in", dir, "--noise", 3), (std::vector<std::size_t>{1, 1, 2}));
    expectSameFiles(dir / "whole", dir / "parts");
}

TEST(CliShard, MoreSharesThanFramesLeavesSomeEmpty) {
    const fs::path dir = sequenceDir("shard_many");
    EXPECT_EQ(renderInShares(dir / "in", dir, "", 7), (std::vector<std::size_t>{0, 1, 0, 1, 0, 1, 1}));
    expectSameFiles(dir / "whole", dir / "parts");
}

TEST(CliShard, ResumeKeepsTheWholeRunsBytesWithTurbulentNoise) {
    const fs::path dir = sequenceDir("shard_resume");
    std::string out;
    fs::create_directories(dir / "run");
    ASSERT_EQ(runCli(render(dir / "in", dir / "run" / "f_%02d.png", "--noise"), &out), 0) << out;
    const auto f21 = readBytes(dir / "run" / "f_21.png");
    const auto f61 = readBytes(dir / "run" / "f_61.png");
    fs::remove(dir / "run" / "f_21.png");
    fs::remove(dir / "run" / "f_61.png");
    ASSERT_EQ(runCli(render(dir / "in", dir / "run" / "f_%02d.png", "--noise --resume"), &out), 0) << out;
    EXPECT_EQ(readBytes(dir / "run" / "f_21.png"), f21);
    EXPECT_EQ(readBytes(dir / "run" / "f_61.png"), f61);
}

TEST(CliShard, ASimulationSceneSplitsIntoTheSameImages) {
    const fs::path dir = tempDir() / "shard_simulation";
    fs::create_directories(dir);
    renderInShares(writeSmallScene(dir), dir, "", 2);
    expectSameFiles(dir / "whole", dir / "parts");
}

TEST(CliShard, BadSharesAreErrorsNamingTheOption) {
    const fs::path dir = sequenceDir("shard_errors");
    std::string out;
    for (const char* bad : {"3/3", "a/b", "1", "-1/2", "0/0", "1/2/3", "1/2x"}) {
        EXPECT_EQ(runCli(render(dir / "in", dir / "f_%02d.png", std::string("--shard '") + bad + "'"), &out), 2) << bad;
        EXPECT_NE(out.find("--shard"), std::string::npos) << out;
    }
    EXPECT_EQ(runCli(render(dir / "in", dir / "f.mp4", "--shard 0/2"), &out), 2);
    EXPECT_NE(out.find("--shard"), std::string::npos) << out;
    EXPECT_TRUE(names(dir).size() == 1u) << "only in/ is there";
}
}  // namespace cli_shard_test_local
