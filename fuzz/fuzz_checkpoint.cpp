// libFuzzer target: the simulator's checkpoint reader (src/sim/checkpoint.cpp,
// Simulator::loadCheckpoint), which `simulate --resume` gives a hidden file
// of the output folder. A checkpoint is bound to its scene (a fingerprint)
// and sealed by a checksum, so bytes made up at random stop at those two
// checks; to reach the counts, the body and the values behind them, most
// inputs are applied to a real checkpoint of a small scene instead:
//   byte 0 even: the input (after byte 0) is the file, as it is;
//   byte 0 odd:  the input is a patch: bytes 1-2 an offset into the real
//                checkpoint, the rest written over it from there (the file
//                growing if it runs past the end); with bit 1 of byte 0 set,
//                the file is then cut at the patch's end. The fingerprint is
//                left as patched, and the checksum is made again over the
//                result, so the reader's later checks are what decide.
// What the reader promises for any file (include/meniscus/sim.h):
//  - an error names the file and says what is wrong, and the simulator is as
//    it was (the same particles, the same time);
//  - a checkpoint it accepts gives a frame no later than the last frame file,
//    finite positions inside the domain, and a simulator that steps on.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "fuzz_reader.h"
#include "meniscus/sim.h"

namespace fs = std::filesystem;
using namespace meniscus;

namespace {

constexpr std::int64_t kLastFrame = 3;

const char* kScene = R"({
  "version": 1, "name": "fuzz", "duration": 1, "fps": 50,
  "params": { "radius": 0.05, "lifetime": 0.1, "resort_every": 2 },
  "domain": { "min": [0, 0, 0], "max": [0.4, 0.6, 0.4] },
  "fluid": [ { "box": { "min": [0, 0, 0], "max": [0.2, 0.2, 0.2] } } ],
  "emitters": [ { "position": [0.3, 0.5, 0.2], "direction": [0, -1, 0], "radius": 0.06, "speed": 1.0 } ]
})";

struct Fixture {
    sim::Scene scene;
    std::vector<std::uint8_t> real;  // a checkpoint of the scene after a few steps
    fs::path realFile;               // ... as a file, to reset the simulator from
    fs::path file;                   // where each input is written for the reader
    // One simulator for every input (making one builds the walls' density
    // maps, which would take most of each run): a refused checkpoint leaves
    // it as it was (checked), an accepted one is undone by loading realFile.
    std::unique_ptr<sim::Simulator> sim;
};

std::unique_ptr<sim::Simulator> make(const sim::Scene& scene) {
    auto s = sim::Simulator::create(scene);
    if (!s) fuzz::broken("the fuzz scene does not make a simulator", s.error().describe());
    return std::move(*s);
}

std::vector<std::uint8_t> readAll(const fs::path& path) {
    std::vector<std::uint8_t> bytes;
    if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
        std::uint8_t buf[65536];
        std::size_t got;
        while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.insert(bytes.end(), buf, buf + got);
        std::fclose(f);
    }
    return bytes;
}

Fixture& fixture() {
    static Fixture* fx = [] {
        auto* f = new Fixture;
        auto scene = sim::parseScene(kScene, "fuzz.json");
        if (!scene) fuzz::broken("the fuzz scene does not parse", scene.error().describe());
        f->scene = *scene;
        const fs::path dir = fs::temp_directory_path() / ("meniscus_fuzz_checkpoint_" + std::to_string(::getpid()));
        fs::create_directories(dir);
        f->file = dir / ".fuzz.checkpoint";
        f->realFile = dir / ".real.checkpoint";
        f->sim = make(f->scene);
        if (!f->sim->advanceTo(0.06).ok() || !f->sim->saveCheckpoint(f->realFile, 2).ok())
            fuzz::broken("the real checkpoint cannot be written", f->realFile.string());
        f->real = readAll(f->realFile);
        if (f->real.size() < 64) fuzz::broken("the real checkpoint is too short", f->realFile.string());
        std::atexit([] {
            std::error_code ec;
            fs::remove_all(fixture().file.parent_path(), ec);
        });
        return f;
    }();
    return *fx;
}

// The checksum the writer puts last (64-bit FNV-1a of every byte before it).
void reseal(std::vector<std::uint8_t>& b) {
    if (b.size() < 8) return;
    std::uint64_t h = 14695981039346656037ull;
    for (std::size_t i = 0; i + 8 < b.size(); ++i) h = (h ^ b[i]) * 1099511628211ull;
    for (int k = 0; k < 8; ++k) b[b.size() - 8 + k] = std::uint8_t(h >> (8 * k));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    Fixture& fx = fixture();
    std::vector<std::uint8_t> file;
    if ((data[0] & 1) == 0) {
        file.assign(data + 1, data + size);
    } else {
        if (size < 3) return 0;
        file = fx.real;
        const std::size_t at = (std::size_t(data[1]) | std::size_t(data[2]) << 8) % (file.size() + 1);
        const std::size_t n = size - 3;
        if (at + n > file.size()) file.resize(at + n);
        std::memcpy(file.data() + at, data + 3, n);
        if (data[0] & 2) file.resize(at + n);
        reseal(file);
    }
    if (std::FILE* f = std::fopen(fx.file.c_str(), "wb")) {
        if (!file.empty()) std::fwrite(file.data(), 1, file.size(), f);
        std::fclose(f);
    }
    sim::Simulator* sim = fx.sim.get();
    const std::size_t before = sim->size();
    const double t = sim->time();
    const auto frame = sim->loadCheckpoint(fx.file, kLastFrame);
    if (!fuzz::checkError(frame, fx.file.string())) {
        if (sim->size() != before || sim->time() != t) fuzz::broken("a refused checkpoint changed the simulator", "");
        return 0;
    }
    struct Reset {
        Fixture& fx;
        ~Reset() {
            if (!fx.sim->loadCheckpoint(fx.realFile, kLastFrame).ok())
                fuzz::broken("the real checkpoint no longer loads", fx.realFile.string());
        }
    } reset{fx};
    if (*frame < 0 || *frame > kLastFrame) fuzz::broken("a checkpoint after the last frame was accepted", "");
    const sim::Box& box = fx.scene.domain;
    for (const glm::vec3& p : sim->positions())
        for (int i = 0; i < 3; ++i)
            if (!std::isfinite(p[i]) || p[i] < box.min[i] || p[i] > box.max[i])
                fuzz::broken("an accepted checkpoint has a particle outside the domain", "");
    // It steps on (a few steps: what a resumed run does next).
    if (std::isfinite(sim->time()) && sim->time() < 1.0) (void)sim->advanceTo(sim->time() + 0.005);
    return 0;
}
