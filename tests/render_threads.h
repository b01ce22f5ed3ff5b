// A Renderer's frame on a given number of TBB threads, for the tests that
// check a stage gives the same bits for any thread count.
#pragma once

#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "meniscus/renderer.h"

namespace meniscus::test {

// The AOVs of one fresh Renderer's frame with at most `threads` threads (a
// failed frame is a test failure and empty AOVs); `times` gets its stage times.
inline Aovs renderOnThreads(const ParticleView& particles, const RenderSettings& settings, int threads,
                            std::vector<StageTime>* times = nullptr) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    auto a = Renderer().render(particles, settings, times);
    EXPECT_TRUE(a) << a.error().describe();
    return a ? std::move(*a) : Aovs{};
}

}  // namespace meniscus::test
