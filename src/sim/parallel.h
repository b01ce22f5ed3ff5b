// The simulator's parallel loops over particles (oneTBB), in fixed chunks so
// that sums come out the same for any thread count.
#pragma once

#include <cstddef>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace meniscus::sim {

inline constexpr std::size_t kParticleGrain = 512;

template <class F>
void forAll(std::size_t n, F&& f) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kParticleGrain), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) f(i);
    });
}

// Sum of f(i) over all particles, the same for any thread count.
template <class F>
double sumAll(std::size_t n, F&& f) {
    return tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, n, kParticleGrain), 0.0,
        [&](const tbb::blocked_range<std::size_t>& r, double acc) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) acc += double(f(i));
            return acc;
        },
        [](double a, double b) { return a + b; });
}

}  // namespace meniscus::sim
