// The frame memory check (src/core/frame_memory.cpp) and its use by the
// pipeline: a frame needing more than half the process's memory is refused
// with the figure before anything is allocated.
#include <gtest/gtest.h>

#include "core/frame_memory.h"
#include "meniscus/renderer.h"

namespace meniscus::frame_memory_test_local {
namespace {

TEST(FrameMemory, GrowsWithThePixelCount) {
    EXPECT_EQ(frameBytes(0, 10), 0u);
    EXPECT_EQ(frameBytes(200, 100), 2u * frameBytes(100, 100));
    // At least the kept buffers: scene colour+depth, raw depth, thickness,
    // depth, normals, colour (64 bytes a pixel).
    EXPECT_GE(frameBytes(1280, 720), 1280u * 720u * 64u);
    // The optional stages' images count: N and foam, the whitening map.
    EXPECT_EQ(frameBytes(100, 100, true, false), frameBytes(100, 100) + 100u * 100u * 8u);
    EXPECT_EQ(frameBytes(100, 100, true, true), frameBytes(100, 100) + 100u * 100u * 12u);
    // Several fluids: each one's layer images (80 bytes a pixel) and the fluid AOV.
    EXPECT_EQ(frameBytes(100, 100, false, false, 1), frameBytes(100, 100));
    EXPECT_EQ(frameBytes(100, 100, false, false, 3), frameBytes(100, 100) + 100u * 100u * (3u * 80u + 4u));
    const std::uint64_t need = frameBytes(4000, 4000);
    const MemoryBudget twice{2 * need, "test"};
    EXPECT_TRUE(checkFrameMemory(4000, 4000, twice).ok());
    EXPECT_FALSE(checkFrameMemory(4000, 4000, twice, true, true).ok());
    EXPECT_FALSE(checkFrameMemory(4000, 4000, twice, false, false, 2).ok());
}

// Regression: 16384x16384 was accepted, then took minutes and 9.5 GB.
TEST(FrameMemory, RefusesWithTheFigures) {
    const std::uint64_t gb = 1000000000;
    const Status st = checkFrameMemory(16384, 16384, {24 * gb, "cgroup memory.max"});
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().message,
              "a 16384x16384 frame needs about 22.5 GB; this process may use 24.0 GB (cgroup memory.max), and this at "
              "most half of it; choose a smaller --width/--height");
    EXPECT_TRUE(checkFrameMemory(16384, 16384, {1000 * gb, "physical memory"}).ok());
    EXPECT_TRUE(checkFrameMemory(1280, 720, {24 * gb, "physical memory"}).ok());
    EXPECT_TRUE(checkFrameMemory(16384, 16384, {0, ""}).ok());  // unknown memory: not refused
    EXPECT_GT(availableMemoryBytes(), 0u);
}

TEST(FrameMemory, ThePipelineRefusesBeforeRendering) {
    if (2 * frameBytes(16384, 16384) <= availableMemoryBytes()) GTEST_SKIP() << "this machine could render it";
    RenderSettings s;
    s.camera.width = s.camera.height = 16384;
    s.camera.eye = {0, 0, 3};
    s.radiusM = 0.1f;
    const glm::vec3 p{0, 0, 0};
    auto made = Renderer::create(BackendChoice::Cpu, nullptr);
    ASSERT_TRUE(made.ok());
    const auto r = made->render(std::span(&p, 1), s);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("frame needs about"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace meniscus::frame_memory_test_local
