// LiveSimulation (apps/meniscus/live_simulation.h), the worker behind
// `meniscus view --simulate`, without a window: frames arrive in order with
// increasing time to the scene's end and are the frames `simulate` writes;
// stop() joins (during a step or a wait for the wall clock) and keeps the
// last frame; a paced frame is never early; a failing step ends the worker
// with its error. A reader thread reads every snapshot while the worker runs,
// so the sanitizer build checks the hand-over.
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "live_simulation.h"
#include "meniscus/sim.h"

namespace live_simulation_test_local {

using namespace meniscus;
using meniscus::app::LiveSimulation;

namespace {

// A small dam break (r = 2 cm, 140 particles) in a 0.4 x 0.4 x 0.16 m tank.
sim::Scene smallScene(double duration, double fps) {
    sim::Scene s;
    s.name = "live";
    s.params.radius = 0.02f;
    s.domain = {{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.16f}};
    sim::FluidBlock block;
    block.box = {{0.0f, 0.0f, 0.0f}, {0.24f, 0.32f, 0.16f}};
    s.fluid = {block};
    s.duration = duration;
    s.fps = fps;
    return s;
}

std::unique_ptr<sim::Simulator> make(const sim::Scene& scene) {
    auto made = sim::Simulator::create(scene);
    EXPECT_TRUE(made.ok()) << (made.ok() ? "" : made.error().describe());
    return made.ok() ? std::move(made.value()) : nullptr;
}

struct Seen {
    long number;
    double time;
    std::size_t particles;
};

// Polls latest() as a UI loop does until the worker ends; every new frame is
// read through (its positions summed) and recorded.
std::vector<Seen> watch(const LiveSimulation& live) {
    std::vector<Seen> seen;
    for (bool running = true; running;) {
        running = live.running();  // first: once false, latest() is the last frame
        const LiveSimulation::Frame f = live.latest();
        if (seen.empty() || f.number != seen.back().number) {
            float sum = 0.0f;
            for (const glm::vec3& p : f.particles->positions) sum += p.x + p.y + p.z;
            EXPECT_TRUE(std::isfinite(sum));
            seen.push_back({f.number, f.time, f.particles->size()});
        }
        if (running) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return seen;
}

}  // namespace

TEST(LiveSimulation, FramesArriveInOrderAndAreTheFramesSimulateWrites) {
    const sim::Scene scene = smallScene(0.2, 50.0);  // frames 0..10
    LiveSimulation live(make(scene), scene.fps, scene.duration);
    EXPECT_EQ(live.latest().number, -1);
    EXPECT_EQ(live.latest().particles, nullptr);
    std::atomic<int> calls{0};
    live.start([&] { ++calls; });
    ASSERT_NE(live.latest().particles, nullptr) << "frame 0 is there as soon as start() returns";
    const std::size_t count = live.latest().particles->size();
    ASSERT_GT(count, 100u);
    std::vector<Seen> seen;
    std::thread reader([&] { seen = watch(live); });
    reader.join();

    // The reader may start a frame or two late (the worker does not wait for
    // it): whatever it sees first, the frames then come in order.
    ASSERT_GE(seen.size(), 1u);
    EXPECT_GE(seen.front().number, 0);
    for (std::size_t i = 0; i < seen.size(); ++i) {
        if (i > 0) {
            EXPECT_GT(seen[i].number, seen[i - 1].number);
            EXPECT_GT(seen[i].time, seen[i - 1].time);
        }
        EXPECT_NEAR(seen[i].time, double(seen[i].number) / scene.fps, 1e-9);
        EXPECT_EQ(seen[i].particles, count) << "a closed tank keeps every particle";
    }
    EXPECT_EQ(seen.back().number, 10);
    EXPECT_DOUBLE_EQ(seen.back().time, 0.2);
    EXPECT_FALSE(live.running());
    EXPECT_FALSE(live.error().has_value());
    EXPECT_EQ(calls.load(), 10 + 1) << "once per frame after the first, once at the end";

    // The last frame is bit for bit what simulate's loop (advanceTo each frame's time) gives.
    auto straight = make(scene);
    for (int k = 1; k <= 10; ++k) ASSERT_TRUE(straight->advanceTo(double(k) / scene.fps).ok());
    const auto last = live.latest().particles;
    ASSERT_EQ(last->positions.size(), straight->positions().size());
    for (std::size_t i = 0; i < last->positions.size(); ++i)
        ASSERT_EQ(last->positions[i], straight->positions()[i]) << i;
}

// A 1000 s scene: stop() ends it after the step in progress, joins, and the
// last frame published stays; a second stop() and the destructor are no-ops.
TEST(LiveSimulation, StopJoinsAndKeepsTheLastFrame) {
    const sim::Scene scene = smallScene(1000.0, 100.0);
    LiveSimulation live(make(scene), scene.fps, scene.duration);
    std::atomic<int> calls{0};
    live.start([&] { ++calls; });
    while (live.latest().number < 3) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    live.stop();
    EXPECT_FALSE(live.running());
    EXPECT_FALSE(live.error().has_value());
    const LiveSimulation::Frame f = live.latest();
    EXPECT_GE(f.number, 3);
    EXPECT_LT(f.time, 1000.0);
    EXPECT_EQ(calls.load(), int(f.number) + 1) << "the frames after the first, and the end";
    live.stop();
    EXPECT_EQ(live.latest().number, f.number) << "no worker left to publish";
    EXPECT_EQ(live.latest().particles, f.particles);
}

// Paced at 1e-6 of real time, frame 1 is due in 5.6 hours: stop() must end
// the wait at once (else this test hangs past ctest's timeout).
TEST(LiveSimulation, StopEndsTheWaitForTheWallClock) {
    const sim::Scene scene = smallScene(1.0, 50.0);
    LiveSimulation live(make(scene), scene.fps, scene.duration, 1e-6);
    live.start();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the worker is waiting by now (or soon)
    live.stop();
    EXPECT_FALSE(live.running());
    EXPECT_EQ(live.latest().number, 0);
}

// At speed s a frame at simulated time t is published no sooner than t / s
// after start() (a lower bound: a slow machine only makes it later).
TEST(LiveSimulation, PacedFramesAreNeverEarly) {
    const sim::Scene scene = smallScene(0.1, 50.0);
    const double speed = 2.0;
    LiveSimulation live(make(scene), scene.fps, scene.duration, speed);
    const auto started = std::chrono::steady_clock::now();
    live.start();
    long shown = 0;
    for (bool running = true; running;) {
        running = live.running();
        const LiveSimulation::Frame f = live.latest();
        if (f.number != shown) {
            const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
            EXPECT_GE(elapsed, f.time / speed) << "frame " << f.number;
            shown = f.number;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    EXPECT_EQ(shown, 5);
}

// A step that fails (a non-finite velocity: the simulator reports divergence)
// ends the worker; error() says why, the frames before it stay.
TEST(LiveSimulation, AFailingStepEndsTheWorkerWithItsError) {
    const sim::Scene scene = smallScene(1.0, 50.0);
    auto simulator = make(scene);
    ParticleSet set = simulator->particles();
    Attribute* velocity = nullptr;
    for (Attribute& a : set.attributes)
        if (a.name == kAttrVelocity) velocity = &a;
    ASSERT_NE(velocity, nullptr);
    velocity->floats[1] = std::numeric_limits<float>::quiet_NaN();
    ASSERT_TRUE(simulator->restore(set, 0.0).ok());
    LiveSimulation live(std::move(simulator), scene.fps, scene.duration);
    live.start();
    const std::vector<Seen> seen = watch(live);
    ASSERT_TRUE(live.error().has_value());
    EXPECT_NE(live.error()->message.find("diverged"), std::string::npos) << live.error()->describe();
    EXPECT_EQ(seen.back().number, 0) << "no frame after the failing step";
}
}  // namespace live_simulation_test_local
