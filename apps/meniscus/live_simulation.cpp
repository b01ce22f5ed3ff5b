// LiveSimulation (see live_simulation.h).
#include "live_simulation.h"

#include <chrono>
#include <cmath>
#include <utility>

namespace meniscus::app {

LiveSimulation::LiveSimulation(std::unique_ptr<sim::Simulator> simulator, double fps, double duration, double speed)
    : sim_(std::move(simulator)), fps_(fps), duration_(duration), speed_(speed) {}

LiveSimulation::~LiveSimulation() { stop(); }

void LiveSimulation::start(std::function<void()> onFrame) {
    if (worker_.joinable() || latest_.number >= 0) return;
    onFrame_ = std::move(onFrame);
    // The frame the simulator is on (0 for a new one), published before the worker exists.
    publish(long(std::floor(sim_->time() * fps_ + 1e-9)));
    running_ = true;
    worker_ = std::thread([this] { run(); });
}

void LiveSimulation::stop() {
    {
        std::lock_guard lock(mutex_);  // so a worker about to wait sees it
        stop_ = true;
    }
    stopped_.notify_all();
    if (worker_.joinable()) worker_.join();
}

LiveSimulation::Frame LiveSimulation::latest() const {
    std::lock_guard lock(mutex_);
    return latest_;
}

bool LiveSimulation::running() const { return running_; }

std::optional<Error> LiveSimulation::error() const {
    std::lock_guard lock(mutex_);
    return error_;
}

void LiveSimulation::publish(long number) {
    // The copy is made outside the lock: the UI only ever waits for a pointer swap.
    Frame frame{std::make_shared<const ParticleSet>(sim_->particles()), sim_->time(), number};
    std::lock_guard lock(mutex_);
    latest_ = std::move(frame);
}

void LiveSimulation::run() {
    const long last = long(std::floor(duration_ * fps_ + 1e-9));
    const auto started = std::chrono::steady_clock::now();
    const double t0 = sim_->time();
    long k = latest().number;
    while (!stop_ && k < last) {
        ++k;
        const double t = double(k) / fps_;
        // Step by step rather than advanceTo(t), so stop() waits for one step, not a whole frame.
        while (!stop_ && sim_->time() < t) {
            if (auto st = sim_->step(t); !st) {
                std::lock_guard lock(mutex_);
                error_ = st.error();
                stop_ = true;
            }
        }
        if (speed_ > 0.0) {  // not before its time on the wall clock
            const auto due = started + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                           std::chrono::duration<double>((t - t0) / speed_));
            std::unique_lock lock(mutex_);
            stopped_.wait_until(lock, due, [this] { return stop_.load(); });
        }
        if (stop_) break;
        publish(k);
        if (onFrame_) onFrame_();
    }
    running_ = false;
    if (onFrame_) onFrame_();
}

}  // namespace meniscus::app
