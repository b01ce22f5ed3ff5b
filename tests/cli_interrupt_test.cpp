// Every long command stops cleanly on Ctrl-C (SIGINT) and SIGTERM and goes on
// with --resume: render, mesh, convert, whitewater and simulate are started
// on a sequence, signalled once their first output exists, and must exit 130
// (143 for SIGTERM) leaving only whole files (each parses) and no temporary;
// --resume then completes the outputs, byte for byte those of a run never
// interrupted. A killed run's temporaries (dead PID) are swept by the next
// run, a live process's kept; an output folder that cannot be made is an
// error (exit 2) before any work.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include "meniscus/io.h"
#include "test_util.h"

namespace cli_interrupt_test_local {

namespace fs = std::filesystem;
using namespace meniscus::test;

namespace {

// The CLI with `args` in a child process (stdout and stderr into *output),
// sent `signal` as soon as `first` exists. Returns its exit code; -N when the
// signal N itself ended it (the command did not handle it), -1000 when it
// ended before `first` appeared or took over two minutes.
int interruptOnceWritten(const std::string& args, const fs::path& first, int signal, std::string* output) {
    const fs::path log = first.parent_path().parent_path() / ("log_" + std::to_string(::getpid()) + ".txt");
    const std::string command = "exec " + cliPath() + " " + args + " > " + shellQuote(log) + " 2>&1";
    const pid_t child = ::fork();
    if (child == 0) {
        ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    int status = 0;
    bool signalled = false;
    const auto start = std::chrono::steady_clock::now();
    for (;;) {
        const pid_t done = ::waitpid(child, &status, WNOHANG);
        if (done == child) break;
        if (!signalled && fs::exists(first)) {
            ::kill(child, signal);
            signalled = true;
        }
        if (std::chrono::steady_clock::now() - start > std::chrono::minutes(2)) {
            ::kill(child, SIGKILL);
            ::waitpid(child, &status, 0);
            signalled = false;
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    std::ifstream in(log);
    *output = std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    fs::remove(log);
    if (!signalled) return -1000;
    if (WIFSIGNALED(status)) return -WTERMSIG(status);
    return WEXITSTATUS(status);
}

std::vector<std::string> listDir(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

bool pngWhole(const fs::path& p) {
    const auto bytes = readBytes(p);
    static const std::vector<std::uint8_t> iend = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    return bytes.size() > 20 && std::equal(iend.begin(), iend.end(), bytes.end() - 12) && readPng(p).width > 0;
}

// Every file in `dir` whole (a PNG, a mesh or a particle file that parses),
// none hidden (a temporary); returns how many there are.
std::size_t expectOnlyWholeFiles(const fs::path& dir) {
    const auto files = listDir(dir);
    for (const std::string& f : files) {
        if (f.front() == '.' && f.ends_with(".checkpoint")) continue;  // simulate's solver checkpoint
        EXPECT_NE(f.front(), '.') << "a temporary is left: " << f;
        const fs::path p = dir / f;
        if (p.extension() == ".png") {
            EXPECT_TRUE(pngWhole(p)) << f;
        } else if (p.extension() == ".ply" && f.rfind("m_", 0) == 0) {
            EXPECT_TRUE(meniscus::readMesh(p).ok()) << f;
        } else if (p.extension() != ".pvd") {
            auto set = meniscus::readParticles(p, meniscus::ParticleFormat::Auto, true);
            EXPECT_TRUE(set.ok()) << f << ": " << (set ? "" : set.error().describe());
        }
    }
    return files.size();
}

// The files of two folders, the same names with the same bytes (simulate's
// checkpoint: the same name).
void expectSameFiles(const fs::path& a, const fs::path& b) {
    const auto names = listDir(a);
    ASSERT_EQ(names, listDir(b));
    ASSERT_FALSE(names.empty());
    for (const std::string& f : names)
        if (!f.ends_with(".checkpoint")) {  // holds the run's timings beside its state
            EXPECT_TRUE(readBytes(a / f) == readBytes(b / f)) << f << " differs";
        }
}

// DIR/in/f_1.bgeo .. f_N.bgeo, symbolic links to the real demo frames 19 .. 23 in turn.
fs::path realFrames(const std::string& name, int n) {
    const fs::path dir = tempDir() / name;
    fs::remove_all(dir);
    fs::create_directories(dir / "in");
    for (int i = 1; i <= n; ++i)
        fs::create_symlink(repoData("demo/ParticleData_Fluid_" + std::to_string(19 + (i - 1) % 5) + ".bgeo"),
                           dir / "in" / ("f_" + std::to_string(i) + ".bgeo"));
    return dir;
}

// One command (`run(out)` its arguments writing into folder `out`, whose
// first output is `firstName`): the whole run into DIR/whole, then into
// DIR/cut signalled once the first output exists, then resumed there.
void interruptAndResume(const fs::path& dir, const std::function<std::string(const fs::path&)>& run,
                        const std::string& firstName, int signal = SIGINT) {
    std::string out;
    ASSERT_EQ(runCli(run(dir / "whole"), &out), 0) << out;
    const std::size_t all = listDir(dir / "whole").size();
    const int rc = interruptOnceWritten(run(dir / "cut"), dir / "cut" / firstName, signal, &out);
    ASSERT_EQ(rc, 128 + signal) << out;
    EXPECT_NE(out.find("meniscus: interrupted after"), std::string::npos) << out;
    EXPECT_NE(out.find("--resume"), std::string::npos) << out;
    const std::size_t kept = expectOnlyWholeFiles(dir / "cut");
    EXPECT_GE(kept, 1u);
    EXPECT_LT(kept, all) << "the run was not stopped early";
    ASSERT_EQ(runCli(run(dir / "cut") + " --resume", &out), 0) << out;
    EXPECT_NE(out.find("complete"), std::string::npos) << "the interrupted run's outputs are kept: " << out;
    expectSameFiles(dir / "whole", dir / "cut");
}

}  // namespace

TEST(CliInterrupt, RenderStopsAfterTheFrameAndResumesToTheSameBytes) {
    const fs::path dir = realFrames("interrupt_render", 20);
    interruptAndResume(dir, [&](const fs::path& out) {
        return "render " + shellQuote(dir / "in" / "f_%d.bgeo") + " -o " + shellQuote(out / "o_%04d.png") +
               " --width 96 --height 54 --backend cpu --eye 2.5,2.1,2.9 --target 0.43,0.45,0";
    }, "o_0001.png", SIGTERM);
}

TEST(CliInterrupt, MeshStopsAfterTheMeshAndResumesToTheSameBytes) {
    const fs::path dir = realFrames("interrupt_mesh", 10);
    interruptAndResume(dir, [&](const fs::path& out) {
        return "mesh " + shellQuote(dir / "in" / "f_%d.bgeo") + " -o " + shellQuote(out / "m_%04d.ply") +
               " --cube-size 2";
    }, "m_0001.ply");
}

TEST(CliInterrupt, ConvertStopsAfterTheFrameAndResumesToTheSameBytes) {
    const fs::path dir = realFrames("interrupt_convert", 60);
    interruptAndResume(dir, [&](const fs::path& out) {
        return "convert " + shellQuote(dir / "in" / "f_%d.bgeo") + " " + shellQuote(out / "c_%04d.vtu");
    }, "c_0001.vtu");
}

TEST(CliInterrupt, WhitewaterStopsAfterTheFrameAndResumesToTheSameBytes) {
    const fs::path dir = realFrames("interrupt_whitewater", 15);
    interruptAndResume(dir, [&](const fs::path& out) {
        return "whitewater " + shellQuote(dir / "in" / "f_%d.bgeo") + " -o " + shellQuote(out / "d_%04d.bgeo") +
               " --fps 15 --limits 1,10,0.5,5,1,14";
    }, "d_0001.bgeo");
}

// simulate --render: stopped between two steps, the frame in progress is not
// written; a picture missing for a frame whose particles were written (a run
// killed between the two) is rendered by --resume from the particle file, the
// same bytes as the whole run's. (The frames simulated after the resume point
// come from the solver's checkpoint: the next test checks their bytes.)
TEST(CliInterrupt, SimulateStopsBetweenStepsAndResumeRendersTheMissingPictures) {
    const fs::path dir = tempDir() / "interrupt_simulate";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path scene = writeSmallScene(dir);
    const auto run = [&](const std::string& where) {
        return "simulate " + shellQuote(scene) + " -o " + shellQuote(dir / where / "f_%04d.bgeo") + " --render " +
               shellQuote(dir / where / "i_%04d.png") + " --width 64 --height 48 --duration 2";
    };
    std::string out;
    const int rc = interruptOnceWritten(run("cut"), dir / "cut" / "i_0001.png", SIGINT, &out);
    ASSERT_EQ(rc, 130) << out;
    EXPECT_NE(out.find("meniscus: interrupted after frame"), std::string::npos) << out;
    EXPECT_NE(out.find("is not written"), std::string::npos) << out;
    const std::size_t files = expectOnlyWholeFiles(dir / "cut");
    EXPECT_LT(files, 2u * 101u) << "the run was not stopped early";
    // Every frame's particles came with its picture; frame 1's picture lost
    // (killed in between), then resumed.
    long last = -1;
    while (fs::exists(dir / "cut" / ("f_000" + std::to_string(last + 1) + ".bgeo")) && last < 8) ++last;
    ASSERT_GE(last, 1) << out;
    const fs::path lost = dir / "cut" / "i_0001.png";
    const auto picture = readBytes(lost);
    fs::remove(lost);
    // The resumed run: up to the frame after the resume point (--duration) is enough.
    const std::string resume = run("cut") + " --resume";
    ASSERT_EQ(runCli(resume.substr(0, resume.find(" --duration")) + " --duration " +
                         std::to_string((last + 1) / 50.0) + " --resume",
                     &out),
              0)
        << out;
    EXPECT_NE(out.find("rendered the missing " + lost.string()), std::string::npos) << out;
    EXPECT_TRUE(readBytes(lost) == picture) << "the picture rendered from the particle file is the whole run's";
    expectOnlyWholeFiles(dir / "cut");
}

// simulate (DFSPH) stopped by SIGINT after frame 2, then --resume: every
// frame file, the .pvd too, has the bytes of a run never stopped, because
// --resume loads the solver's checkpoint (.f.checkpoint beside the frames)
// rather than the last particle file, which lacks the warm start, order,
// ages and step size.
TEST(CliInterrupt, SimulateResumedFromItsCheckpointWritesTheSameBytes) {
    const fs::path dir = tempDir() / "interrupt_simulate_exact";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path scene = writeSmallScene(dir);
    const auto run = [&](const std::string& where) {
        return "simulate " + shellQuote(scene) + " -o " + shellQuote(dir / where / "f_%04d.bgeo") + " --duration 2";
    };
    std::string out;
    ASSERT_EQ(runCli(run("whole"), &out), 0) << out;
    EXPECT_TRUE(fs::exists(dir / "whole" / ".f.checkpoint")) << out;
    const int rc = interruptOnceWritten(run("cut"), dir / "cut" / "f_0002.bgeo", SIGINT, &out);
    ASSERT_EQ(rc, 130) << out;
    const std::size_t kept = expectOnlyWholeFiles(dir / "cut");
    EXPECT_LT(kept, 101u) << "the run was not stopped early";
    ASSERT_TRUE(fs::exists(dir / "cut" / ".f.checkpoint"));
    ASSERT_EQ(runCli(run("cut") + " --resume", &out), 0) << out;
    EXPECT_NE(out.find("resuming exactly after frame"), std::string::npos) << out;
    expectSameFiles(dir / "whole", dir / "cut");
    // Without the checkpoint the same resume is the same flow, not the same
    // bits: the comparison above can fail.
    for (int k = 3; k <= 100; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "f_%04d.bgeo", k);
        fs::remove(dir / "cut" / name);
    }
    fs::remove(dir / "cut" / ".f.checkpoint");
    ASSERT_EQ(runCli(run("cut") + " --resume", &out), 0) << out;
    EXPECT_NE(out.find("no solver checkpoint"), std::string::npos) << out;
    EXPECT_FALSE(readBytes(dir / "whole" / "f_0100.bgeo") == readBytes(dir / "cut" / "f_0100.bgeo"));
}

// A run killed by SIGKILL leaves its temporary (.NAME.tmpPID_N); the next run
// into the folder removes those of dead processes only, and says so.
TEST(CliInterrupt, StaleTemporariesOfDeadProcessesAreSwept) {
    const fs::path dir = realFrames("interrupt_sweep", 2);
    fs::create_directories(dir / "out");
    const fs::path dead = dir / "out" / ".x.png.tmp999999_0";
    const fs::path live = dir / "out" / (".x.png.tmp" + std::to_string(::getpid()) + "_3");
    const fs::path other = dir / "out" / ".x.png.tmpabc_0";  // not the pattern
    const fs::path folder = dir / "out" / ".y.png.tmp999999_1";  // the pattern, but a folder
    for (const fs::path& p : {dead, live, other}) writeText(p, "partial");
    fs::create_directories(folder);
    std::string out;
    ASSERT_EQ(runCli("convert " + shellQuote(dir / "in" / "f_%d.bgeo") + " " + shellQuote(dir / "out" / "c_%04d.vtu"),
                     &out),
              0)
        << out;
    EXPECT_FALSE(fs::exists(dead)) << out;
    EXPECT_TRUE(fs::exists(live)) << "a live process's temporary stays";
    EXPECT_TRUE(fs::exists(other));
    EXPECT_TRUE(fs::exists(folder));
    EXPECT_NE(out.find("removed 1 temporary file that a killed run left in " + (dir / "out").string() +
                       " (.x.png.tmp999999_0)"),
              std::string::npos)
        << out;
    // Every command sweeps where it writes.
    writeText(dead, "partial");
    ASSERT_EQ(runCli("mesh " + shellQuote(dir / "in" / "f_1.bgeo") + " -o " + shellQuote(dir / "out" / "m.ply") +
                         " --cube-size 2",
                     &out),
              0)
        << out;
    EXPECT_FALSE(fs::exists(dead)) << out;
}

// An output folder that cannot be made (a file stands where it would go) is
// said before any work, exit 2, nothing written.
TEST(CliInterrupt, AnOutputFolderThatCannotBeMadeFailsFirst) {
    const fs::path dir = realFrames("interrupt_bad_output", 2);
    writeText(dir / "file", "not a folder");
    const fs::path bad = dir / "file" / "sub";
    const std::string in = shellQuote(dir / "in" / "f_%d.bgeo");
    const fs::path scene = writeSmallScene(dir);
    const std::vector<std::string> commands = {
        "render " + in + " -o " + shellQuote(bad / "o_%04d.png") + " --width 32 --height 18 --backend cpu",
        "mesh " + in + " -o " + shellQuote(bad / "m_%04d.ply"),
        "convert " + in + " " + shellQuote(bad / "c_%04d.vtu"),
        "whitewater " + in + " -o " + shellQuote(bad / "d_%04d.bgeo") + " --fps 15",
        "simulate " + shellQuote(scene) + " -o " + shellQuote(bad / "f_%04d.bgeo"),
        "simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "s" / "f_%04d.bgeo") + " --render " +
            shellQuote(bad / "i_%04d.png"),
        "simulate " + shellQuote(scene) + " -o " + shellQuote(dir / "s" / "f_%04d.bgeo") + " --render " +
            shellQuote(bad / "m.mp4"),
        "render " + in + " -o " + shellQuote(bad / "m.mp4") + " --width 32 --height 18 --backend cpu",
    };
    for (const std::string& c : commands) {
        std::string out;
        const int rc = runCli(c, &out);
        if (out.find("this build has no movies") != std::string::npos) continue;
        EXPECT_EQ(rc, 2) << c << "\n" << out;
        EXPECT_NE(out.find("cannot make the folder"), std::string::npos) << c << "\n" << out;
        EXPECT_EQ(out.find("wrote"), std::string::npos) << c << "\n" << out;
        EXPECT_FALSE(fs::exists(dir / "s" / "f_0000.bgeo")) << "nothing simulated";
    }
}
}  // namespace cli_interrupt_test_local
