// The simulation behind `meniscus view --simulate`: a worker thread steps a
// Simulator and hands each finished frame (every 1/fps simulated seconds) to
// the UI thread as an immutable snapshot under a mutex, so the UI never waits
// for a step and never touches the simulator while it runs.
#pragma once

#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "meniscus/result.h"
#include "meniscus/sim.h"
#include "meniscus/types.h"

namespace meniscus::app {

class LiveSimulation {
public:
    struct Frame {
        std::shared_ptr<const ParticleSet> particles;  // null before start()
        double time = 0.0;                              // simulated seconds
        long number = -1;                               // k of t = k / fps; -1 before start()
    };

    // Steps `simulator` to `duration` (s), publishing a frame every 1/fps s
    // (fps > 0): the frames `meniscus simulate` would write. With speed > 0 a
    // frame is published no sooner than its simulated time / speed after
    // start() in wall-clock time (speed 1: real time at most, so a fast
    // simulation plays rather than jumps to its end); 0: as fast as it goes.
    LiveSimulation(std::unique_ptr<sim::Simulator> simulator, double fps, double duration, double speed = 0.0);
    ~LiveSimulation();  // stop()
    LiveSimulation(const LiveSimulation&) = delete;
    LiveSimulation& operator=(const LiveSimulation&) = delete;

    // Publishes the current state as the first frame, at once, then steps on a
    // worker thread. `onFrame` is called on the worker after each new frame
    // and once more when the worker ends (e.g. Window::wake, so a UI loop
    // sleeping in waitEvents looks). Only the first call starts anything.
    void start(std::function<void()> onFrame = {});
    // Asks the worker to stop after the time step it is in (or at once while
    // it waits for the wall clock) and joins it; the last frame published
    // stays. Idempotent.
    void stop();

    Frame latest() const;  // the newest finished frame
    bool running() const;  // the worker is still stepping (not at the end, stopped or failed)
    std::optional<Error> error() const;  // why the worker ended early: a step failed

private:
    void run();
    void publish(long number);

    std::unique_ptr<sim::Simulator> sim_;  // the worker's alone once started
    double fps_, duration_, speed_;
    std::function<void()> onFrame_;
    std::atomic<bool> stop_{false}, running_{false};
    mutable std::mutex mutex_;  // guards latest_ and error_; stop_ is set under it for stopped_
    std::condition_variable stopped_;  // ends the worker's wait for the wall clock
    Frame latest_;
    std::optional<Error> error_;
    std::thread worker_;
};

}  // namespace meniscus::app
