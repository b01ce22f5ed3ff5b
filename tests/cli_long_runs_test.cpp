// Long runs of `meniscus render`: a corrupt frame skipped and listed
// (--on-error skip) or ending the run (the default), --resume leaving complete
// outputs, --renumber, a progress line per frame when stderr is a log,
// Ctrl-C leaving only whole files, and the overlapped run (frames read ahead
// and written on workers) giving the sequential run's files and errors.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_util.h"

namespace cli_long_runs_test_local {

namespace fs = std::filesystem;
using namespace meniscus::test;

namespace {

// DIR/in/f_1.bgeo .. f_N.bgeo: the small real frame 21 (copies), the ones in
// `corrupt` replaced by bytes no reader takes. Returns DIR, emptied first.
fs::path sequence(const std::string& name, int n, std::vector<int> corrupt = {}) {
    const fs::path dir = tempDir() / name;
    fs::remove_all(dir);
    fs::create_directories(dir / "in");
    fs::create_directories(dir / "out");
    const fs::path frame = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo");
    for (int i = 1; i <= n; ++i) {
        const fs::path f = dir / "in" / ("f_" + std::to_string(i) + ".bgeo");
        if (std::find(corrupt.begin(), corrupt.end(), i) != corrupt.end()) {
            std::ofstream(f, std::ios::binary) << "Bgeo garbage, not a frame";
        } else {
            fs::create_symlink(frame, f);
        }
    }
    return dir;
}

std::string renderArgs(const fs::path& dir, const std::string& output) {
    return "render " + shellQuote(dir / "in" / "f_*.bgeo") + " -o " + shellQuote(dir / "out" / output) +
           " --width 160 --height 90 --backend cpu";
}

std::vector<std::string> listDir(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

bool pngComplete(const fs::path& p) {
    const auto bytes = readBytes(p);
    static const std::vector<std::uint8_t> iend = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    return bytes.size() > 20 && std::equal(iend.begin(), iend.end(), bytes.end() - 12);
}

}  // namespace

TEST(CliLongRuns, ACorruptFrameIsSkippedAndListedOrStopsTheRun) {
    const fs::path dir = sequence("long_skip", 4, {2});
    std::string out;
    EXPECT_EQ(runCli(renderArgs(dir, "o_%04d.png") + " --on-error skip", &out), 1) << out;
    EXPECT_EQ(listDir(dir / "out"), (std::vector<std::string>{"o_0001.png", "o_0003.png", "o_0004.png"})) << out;
    EXPECT_NE(out.find("1 of 4 frames failed"), std::string::npos) << out;
    EXPECT_NE(out.find("frame 2: " + (dir / "in" / "f_2.bgeo").string()), std::string::npos) << out;
    // A progress line per frame (stderr is not a terminal here).
    EXPECT_NE(out.find("meniscus: rendering 4/4 " + (dir / "out" / "o_0004.png").string() + " in "), std::string::npos)
        << out;
    // The default stops at the corrupt frame: with the automatic camera, which
    // samples it, before any frame; with a given one after frame 1.
    fs::remove_all(dir / "out");
    fs::create_directories(dir / "out");
    EXPECT_EQ(runCli(renderArgs(dir, "o_%04d.png"), &out), 1) << out;
    EXPECT_TRUE(listDir(dir / "out").empty()) << out;
    EXPECT_NE(out.find((dir / "in" / "f_2.bgeo").string()), std::string::npos) << out;
    EXPECT_EQ(runCli(renderArgs(dir, "o_%04d.png") + " --eye 2.5,2.1,2.9 --target 0.43,0.45,0", &out), 1) << out;
    EXPECT_EQ(listDir(dir / "out"), std::vector<std::string>{"o_0001.png"}) << out;
    EXPECT_NE(out.find((dir / "in" / "f_2.bgeo").string()), std::string::npos) << out;
    // The error says how to go on past such frames.
    EXPECT_NE(out.find("frame 2 of 4; --on-error skip renders the others"), std::string::npos) << out;
}

TEST(CliLongRuns, ACorruptFirstFrameLeavesTheCameraToTheOthers) {
    const fs::path dir = sequence("long_first", 3, {1});
    std::string out;
    EXPECT_EQ(runCli(renderArgs(dir, "o_%04d.png") + " --on-error skip", &out), 1) << out;
    EXPECT_EQ(listDir(dir / "out"), (std::vector<std::string>{"o_0002.png", "o_0003.png"})) << out;
    EXPECT_NE(out.find("meniscus: radius 0.02"), std::string::npos) << out;  // from frame 2
    EXPECT_NE(out.find("frame 1: "), std::string::npos) << out;
    // Every frame corrupt: one clear error, nothing written.
    const fs::path bad = sequence("long_all_bad", 2, {1, 2});
    EXPECT_EQ(runCli(renderArgs(bad, "o_%04d.png") + " --on-error skip", &out), 1) << out;
    EXPECT_TRUE(listDir(bad / "out").empty());
}

TEST(CliLongRuns, ResumeKeepsCompleteOutputsAndRedoesTheRest) {
    const fs::path dir = sequence("long_resume", 3);
    std::string out;
    ASSERT_EQ(runCli(renderArgs(dir, "o_%04d.png"), &out), 0) << out;
    const auto whole = readBytes(dir / "out" / "o_0003.png");
    fs::remove(dir / "out" / "o_0002.png");
    fs::resize_file(dir / "out" / "o_0003.png", 100);  // cut short, as by another tool
    const auto firstTime = fs::last_write_time(dir / "out" / "o_0001.png");
    ASSERT_EQ(runCli(renderArgs(dir, "o_%04d.png") + " --resume", &out), 0) << out;
    EXPECT_NE(out.find("wrote 2 frames to"), std::string::npos) << out;
    EXPECT_NE(out.find("(1 already complete, kept)"), std::string::npos) << out;
    EXPECT_EQ(fs::last_write_time(dir / "out" / "o_0001.png"), firstTime);
    EXPECT_TRUE(pngComplete(dir / "out" / "o_0002.png"));
    EXPECT_EQ(readBytes(dir / "out" / "o_0003.png"), whole);
}

TEST(CliLongRuns, RenumberNumbersTheOutputsInOrder) {
    const fs::path dir = tempDir() / "long_renumber";
    fs::remove_all(dir);
    fs::create_directories(dir / "in");
    fs::create_directories(dir / "out");
    for (int n : {3, 7, 20}) fs::create_symlink(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"),
                                                dir / "in" / ("f_" + std::to_string(n) + ".bgeo"));
    std::string out;
    ASSERT_EQ(runCli(renderArgs(dir, "o_%04d.png"), &out), 0) << out;
    EXPECT_EQ(listDir(dir / "out"), (std::vector<std::string>{"o_0003.png", "o_0007.png", "o_0020.png"}));
    fs::remove_all(dir / "out");
    fs::create_directories(dir / "out");
    ASSERT_EQ(runCli(renderArgs(dir, "o_%04d.png") + " --renumber", &out), 0) << out;
    EXPECT_EQ(listDir(dir / "out"), (std::vector<std::string>{"o_0000.png", "o_0001.png", "o_0002.png"}));
}

// Ctrl-C (SIGINT after 1 s of a run of 400 frames): exit 130, a message, and
// only whole files: every PNG complete and no temporary left; a movie is not
// written at all.
TEST(CliLongRuns, InterruptLeavesOnlyWholeFiles) {
    const fs::path dir = sequence("long_interrupt", 400);
    for (const std::string output : {"o_%04d.png", "m.mp4"}) {
        std::string out;
        const int rc = runCommand("timeout --preserve-status -s INT 1 " + cliPath() + " " + renderArgs(dir, output), &out);
        if (output == "m.mp4" && out.find("this build has no movies") != std::string::npos) continue;
        EXPECT_EQ(rc, 130) << output << ": " << out;
        EXPECT_NE(out.find("interrupted after frame"), std::string::npos) << out;
        const auto files = listDir(dir / "out");
        for (const std::string& f : files) {
            EXPECT_NE(f.front(), '.') << "a temporary file is left: " << f;
            EXPECT_TRUE(pngComplete(dir / "out" / f)) << f;
        }
        if (output == "m.mp4") {
            EXPECT_TRUE(files.empty());
        } else {
            EXPECT_LT(files.size(), 400u);
        }
        fs::remove_all(dir / "out");
        fs::create_directories(dir / "out");
    }
}

namespace {

// The real small dam break's frames 1, 9, 21, 61 as DIR/in/f_1.bgeo ..
// f_4.bgeo (distinct pictures), the ones in `corrupt` replaced by bytes no
// reader takes. Returns DIR, emptied first.
fs::path distinctSequence(const std::string& name, std::vector<int> corrupt = {}) {
    const fs::path dir = tempDir() / name;
    fs::remove_all(dir);
    fs::create_directories(dir / "in");
    const int source[] = {1, 9, 21, 61};
    for (int i = 1; i <= 4; ++i) {
        const fs::path f = dir / "in" / ("f_" + std::to_string(i) + ".bgeo");
        if (std::find(corrupt.begin(), corrupt.end(), i) != corrupt.end())
            std::ofstream(f, std::ios::binary) << "Bgeo garbage, not a frame";
        else
            fs::create_symlink(
                testData("splishsplash/partio/ParticleData_Fluid_" + std::to_string(source[i - 1]) + ".bgeo"), f);
    }
    return dir;
}

// `render` of DIR/in into DIR/OUT (emptied first), overlapped or, with
// MENISCUS_RENDER_OVERLAP=0, one step after another; its exit code.
int renderInto(const fs::path& dir, const std::string& out, const std::string& output, bool overlap,
               const std::string& more, std::string* log) {
    fs::remove_all(dir / out);
    fs::create_directories(dir / out);
    return runCommand(std::string(overlap ? "" : "MENISCUS_RENDER_OVERLAP=0 ") + cliPath() + " render " +
                          shellQuote(dir / "in" / "f_*.bgeo") + " -o " + shellQuote(dir / out / output) +
                          " --width 160 --height 90 --backend cpu" + more,
                      log);
}

// The log's lines without the progress lines' timings ("in 0.12 s, ETA
// 0:01"), and with DIR/OUT/ read as DIR/x/.
std::vector<std::string> logLines(std::string log, const fs::path& dir, const std::string& out) {
    const std::string folder = (dir / out).string() + "/";
    for (std::size_t at; (at = log.find(folder)) != std::string::npos;) log.replace(at, folder.size(), "OUT/");
    std::vector<std::string> lines;
    std::size_t start = 0;
    while (start < log.size()) {
        std::size_t end = log.find('\n', start);
        if (end == std::string::npos) end = log.size();
        std::string line = log.substr(start, end - start);
        if (const std::size_t in = line.rfind(" in "); line.rfind("meniscus: rendering ", 0) == 0 && in != std::string::npos)
            line.resize(in);
        lines.push_back(line);
        start = end + 1;
    }
    return lines;
}

}  // namespace

// The overlapped run (frame k + 1 read on a worker and frame k - 1 written on
// another while frame k renders) writes the sequential run's files byte for
// byte, in order, with the same log; a frame that cannot be read ends it, or
// is skipped, exactly as it does sequentially.
TEST(CliLongRuns, TheOverlappedRunIsTheSequentialRunByteForByte) {
    const fs::path dir = distinctSequence("long_overlap");
    std::string seqLog, parLog;
    ASSERT_EQ(renderInto(dir, "seq", "o_%04d.png", false, "", &seqLog), 0) << seqLog;
    ASSERT_EQ(renderInto(dir, "par", "o_%04d.png", true, "", &parLog), 0) << parLog;
    const auto files = listDir(dir / "seq");
    ASSERT_EQ(files, (std::vector<std::string>{"o_0001.png", "o_0002.png", "o_0003.png", "o_0004.png"}));
    EXPECT_EQ(listDir(dir / "par"), files);
    for (const std::string& f : files) EXPECT_EQ(readBytes(dir / "seq" / f), readBytes(dir / "par" / f)) << f;
    EXPECT_NE(readBytes(dir / "seq" / files[0]), readBytes(dir / "seq" / files[1]));  // distinct frames
    EXPECT_EQ(logLines(seqLog, dir, "seq"), logLines(parLog, dir, "par")) << seqLog << "\n---\n" << parLog;

    // Frame 3 unreadable (a given camera: the automatic one would sample it
    // before any frame): the default stops after frame 2, --on-error skip
    // leaves it out, the same way both ways.
    const fs::path bad = distinctSequence("long_overlap_bad", {3});
    const std::string camera = " --eye 2.5,2.1,2.9 --target 0.43,0.45,0";
    for (const std::string& more : {camera, camera + " --on-error skip"}) {
        EXPECT_EQ(renderInto(bad, "seq", "o_%04d.png", false, more, &seqLog), 1) << seqLog;
        EXPECT_EQ(renderInto(bad, "par", "o_%04d.png", true, more, &parLog), 1) << parLog;
        const auto written = listDir(bad / "seq");
        const std::vector<std::string> stop = {"o_0001.png", "o_0002.png"},
                                        skip = {"o_0001.png", "o_0002.png", "o_0004.png"};
        EXPECT_EQ(written, more == camera ? stop : skip) << seqLog;
        EXPECT_EQ(listDir(bad / "par"), written);
        for (const std::string& f : written) EXPECT_EQ(readBytes(bad / "seq" / f), readBytes(bad / "par" / f)) << f;
        EXPECT_EQ(logLines(seqLog, bad, "seq"), logLines(parLog, bad, "par")) << seqLog << "\n---\n" << parLog;
        EXPECT_NE(parLog.find((bad / "in" / "f_3.bgeo").string()), std::string::npos) << parLog;
    }
}
}  // namespace cli_long_runs_test_local
