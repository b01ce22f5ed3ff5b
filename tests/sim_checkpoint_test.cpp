// The simulator's checkpoint (src/sim/checkpoint.cpp): a simulator loaded from
// it steps to the same bits as the one that wrote it; a file cut short at any
// length, a flipped byte, counts the file cannot hold, another scene or a
// later frame are errors naming the file that leave the state as it was.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "meniscus/sim.h"
#include "test_util.h"

namespace sim_checkpoint_test_local {

namespace fs = std::filesystem;
using namespace meniscus;
using namespace meniscus::test;

namespace {

// A column of DFSPH fluid with a nozzle and a lifetime: warm start, re-sorts,
// emitted ids, ages and the emitter's clock all matter.
sim::Scene scene(float radius = 0.02f) {
    auto sc = sim::parseScene(R"({
  "version": 1, "name": "ckpt", "duration": 1, "fps": 50,
  "params": { "radius": )" + std::to_string(radius) + R"(, "lifetime": 0.1, "resort_every": 3 },
  "domain": { "min": [0, 0, 0], "max": [0.4, 0.6, 0.2] },
  "fluid": [ { "box": { "min": [0, 0, 0], "max": [0.2, 0.3, 0.2] } } ],
  "emitters": [ { "position": [0.3, 0.5, 0.1], "direction": [0, -1, 0], "radius": 0.05, "speed": 1.0 } ]
})",
                              "ckpt.json");
    EXPECT_TRUE(sc.ok()) << sc.error().describe();
    return *sc;
}

std::unique_ptr<sim::Simulator> make(const sim::Scene& sc) {
    auto s = sim::Simulator::create(sc);
    EXPECT_TRUE(s.ok()) << s.error().describe();
    return std::move(*s);
}

bool samePositions(const sim::Simulator& a, const sim::Simulator& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a.positions()[i] != b.positions()[i] || a.velocities()[i] != b.velocities()[i] || a.ids()[i] != b.ids()[i])
            return false;
    return true;
}

}  // namespace

TEST(SimCheckpoint, LoadedSimulatorStepsToTheSameBits) {
    const fs::path dir = tempDir();
    const sim::Scene sc = scene();
    auto a = make(sc);
    ASSERT_TRUE(a->advanceTo(0.04).ok());
    ASSERT_TRUE(a->saveCheckpoint(dir / ".c.checkpoint", 2).ok());
    auto b = make(sc);
    auto frame = b->loadCheckpoint(dir / ".c.checkpoint", 2);
    ASSERT_TRUE(frame.ok()) << frame.error().describe();
    EXPECT_EQ(*frame, 2);
    EXPECT_EQ(b->time(), a->time());
    EXPECT_EQ(b->totals().steps, a->totals().steps);
    ASSERT_TRUE(samePositions(*a, *b));
    // While the first block lives (its ages reach the lifetime at 0.1 s).
    ASSERT_TRUE(a->advanceTo(0.09).ok());
    ASSERT_TRUE(b->advanceTo(0.09).ok());
    EXPECT_EQ(a->totals().expired, 0u);
    EXPECT_TRUE(samePositions(*a, *b)) << "the same bits after the checkpoint";
    ASSERT_TRUE(a->advanceTo(0.12).ok());
    ASSERT_TRUE(b->advanceTo(0.12).ok());
    EXPECT_GT(a->totals().emitted, 0u);
    EXPECT_GT(a->totals().expired, 0u) << "the lifetime removed particles";
    EXPECT_TRUE(samePositions(*a, *b)) << "the same bits after the checkpoint";
    // From the particles alone (restore) the flow is the same but not the bits:
    // the test above can fail.
    auto c = make(sc);
    auto d = make(sc);
    ASSERT_TRUE(c->advanceTo(0.04).ok());
    ASSERT_TRUE(d->restore(c->particles(), c->time()).ok());
    ASSERT_TRUE(c->advanceTo(0.09).ok());
    ASSERT_TRUE(d->advanceTo(0.09).ok());
    EXPECT_FALSE(samePositions(*c, *d));
}

TEST(SimCheckpoint, DamagedFilesAreErrorsNamingTheFileAndChangeNothing) {
    const fs::path dir = tempDir();
    const fs::path path = dir / ".c.checkpoint";
    const sim::Scene sc = scene();
    auto a = make(sc);
    ASSERT_TRUE(a->advanceTo(0.04).ok());
    ASSERT_TRUE(a->saveCheckpoint(path, 2).ok());
    const std::vector<std::uint8_t> good = readBytes(path);
    ASSERT_GT(good.size(), 184u);
    auto fresh = make(sc);
    const std::size_t n0 = fresh->size();
    const fs::path bad = dir / ".bad.checkpoint";
    auto expectRefused = [&](const std::vector<std::uint8_t>& bytes, const std::string& why) {
        writeBytes(bad, bytes);
        auto r = fresh->loadCheckpoint(bad, 100);
        ASSERT_FALSE(r.ok()) << why;
        EXPECT_NE(r.error().describe().find(bad.string()), std::string::npos) << r.error().describe();
        EXPECT_EQ(fresh->time(), 0.0) << why;
        EXPECT_EQ(fresh->size(), n0) << why;
    };
    // Cut short anywhere: in the magic, the header, the body, the checksum.
    for (std::size_t cut : {std::size_t(0), std::size_t(5), std::size_t(40), std::size_t(183), std::size_t(184),
                            std::size_t(1000), good.size() / 2, good.size() - 1})
        expectRefused(std::vector<std::uint8_t>(good.begin(), good.begin() + std::ptrdiff_t(cut)),
                      "cut at " + std::to_string(cut));
    // A byte flipped in the body: the checksum.
    auto flipped = good;
    flipped[good.size() / 2] ^= 0x40;
    expectRefused(flipped, "flipped");
    // A particle count the file cannot hold (2^27), and one past the bound:
    // refused from the file's size, nothing allocated for them.
    for (std::uint64_t n : {std::uint64_t(1) << 27, ~std::uint64_t(0)}) {
        auto huge = good;
        std::memcpy(huge.data() + 56, &n, 8);  // after magic, version, size, fingerprint, frame, t, dt, next id
        expectRefused(huge, "count " + std::to_string(n));
    }
    // Not a checkpoint; another version.
    expectRefused(std::vector<std::uint8_t>(300, 'x'), "not a checkpoint");
    auto version = good;
    version[8] = 2;
    expectRefused(version, "version 2");
    // Of a later frame than the last frame file.
    auto later = fresh->loadCheckpoint(path, 1);
    ASSERT_FALSE(later.ok());
    EXPECT_NE(later.error().message.find("frame 2"), std::string::npos) << later.error().message;
    EXPECT_EQ(fresh->time(), 0.0);
    // Of another scene (another radius).
    auto other = make(scene(0.025f));
    auto foreign = other->loadCheckpoint(path, 100);
    ASSERT_FALSE(foreign.ok());
    EXPECT_NE(foreign.error().message.find("another scene"), std::string::npos) << foreign.error().message;
    // The good file still loads.
    EXPECT_TRUE(fresh->loadCheckpoint(path, 2).ok());
    EXPECT_TRUE(samePositions(*a, *fresh));
}
}  // namespace sim_checkpoint_test_local
