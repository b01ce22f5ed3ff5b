// Wall-clock laps for the per-phase timings of a step.
#pragma once

#include <chrono>

namespace meniscus::sim {

class Timer {
public:
    // Milliseconds since the last lap (or since construction).
    double lap() {
        const auto now = std::chrono::steady_clock::now();
        const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
        last_ = now;
        return ms;
    }

private:
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace meniscus::sim
