#include "interrupt.h"

#include <csignal>
#include <algorithm>
#include <cstdio>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <unistd.h>

#include "common.h"
#include "meniscus/io.h"
#include "meniscus/temporaries.h"

namespace meniscus::app {

namespace {

volatile std::sig_atomic_t gSignal = 0;
// The note the handler writes, made before the handler is installed (a
// handler may not format text or take memory).
char gNote[96] = {};
std::size_t gNoteLength = 0;

extern "C" void onInterrupt(int signal) {
    if (gSignal) return;  // again (or sent to the whole process group as well): already stopping
    gSignal = signal;
    [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, gNote, gNoteLength);  // async-signal-safe
}

}  // namespace

void installInterruptHandler(const char* item) {
    const int n = std::snprintf(gNote, sizeof gNote, "\nmeniscus: stopping after the %s in progress\n", item);
    gNoteLength = n > 0 ? std::min(std::size_t(n), sizeof gNote - 1) : 0;
    struct sigaction action {};
    action.sa_handler = onInterrupt;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;  // reads and writes in progress go on; the loop asks interrupted()
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

bool interrupted() { return gSignal != 0; }

int interruptExitCode() { return gSignal ? 128 + int(gSignal) : 0; }

int stopInterrupted(const std::string& where, const std::string& then) {
    std::cerr << "\nmeniscus: interrupted " << where << "; " << then << "\n";
    return interruptExitCode();
}

Status prepareOutputFolder(const std::string& output, bool shared) {
    namespace fs = std::filesystem;
    std::string first = output;
    if (output.find('%') != std::string::npos) {
        auto name = formatFramePattern(output, 0);
        if (!name) return name.error();
        first = *name;
    }
    if (auto st = makeOutputFolders(first); !st) return Error{st.error().file, st.error().message, true};
    const fs::path folder = fs::path(first).has_parent_path() ? fs::path(first).parent_path() : fs::path(".");
    if (::access(folder.c_str(), W_OK | X_OK) != 0) {
        const int why = errno;
        return makeUsageError(first, "cannot write into the folder " + folder.string() + ": " + std::strerror(why) +
                                         "; choose another output");
    }
    const auto removed =
        removeStaleTemporaries(folder, shared ? std::chrono::hours(1) : std::chrono::hours(0));
    if (!removed.empty()) {
        std::string names;
        for (std::size_t i = 0; i < removed.size() && i < 3; ++i) names += (i ? ", " : "") + removed[i].filename().string();
        if (removed.size() > 3) names += ", ...";
        std::cerr << "meniscus: removed " << removed.size() << " temporary file" << (removed.size() == 1 ? "" : "s")
                  << " that a killed run left in " << folder.string() << " (" << names << ")\n";
    }
    return okStatus();
}

bool imageComplete(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) return false;
    const std::streamoff size = in.tellg();
    if (isExr(path)) {
        char magic[4] = {};
        in.seekg(0);
        return size >= 4 && in.read(magic, 4) && magic[0] == 0x76 && magic[1] == 0x2f && magic[2] == 0x31 &&
               magic[3] == 0x01;
    }
    static const unsigned char iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    unsigned char tail[12] = {};
    if (size < 12 + 8) return false;
    in.seekg(size - 12);
    return bool(in.read(reinterpret_cast<char*>(tail), 12)) && std::equal(tail, tail + 12, iend);
}

bool meshComplete(const std::string& path) {
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec) && readMesh(path).ok();
}

bool particlesComplete(const std::string& path) {
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec) && readParticles(path, ParticleFormat::Auto, true).ok();
}

}  // namespace meniscus::app
