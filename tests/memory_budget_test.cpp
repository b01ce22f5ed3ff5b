// The memory budget (src/core/memory_budget.cpp): the cgroup files and
// /proc/self/cgroup parsed from made-up contents, the smallest limit, the
// program's cap and the check's one-line message.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/frame_memory.h"
#include "meniscus/memory_budget.h"
#include "meniscus/surface.h"
#include "test_util.h"

namespace meniscus::memory_budget_test_local {
namespace {

namespace fs = std::filesystem;

void writeFile(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
}

TEST(MemoryBudget, ParsesCgroupLimitFiles) {
    EXPECT_EQ(parseCgroupMemoryLimit("max\n"), 0u);
    EXPECT_EQ(parseCgroupMemoryLimit("8589934592\n"), 8589934592u);
    EXPECT_EQ(parseCgroupMemoryLimit(" 4096"), 4096u);
    // cgroup v1's "no limit" (2^63 rounded down to a page).
    EXPECT_EQ(parseCgroupMemoryLimit("9223372036854771712\n"), 0u);
    EXPECT_EQ(parseCgroupMemoryLimit(""), 0u);
    EXPECT_EQ(parseCgroupMemoryLimit("12k"), 0u);
    EXPECT_EQ(parseCgroupMemoryLimit("99999999999999999999999"), 0u);  // overflow: unreadable, not a wrap
}

TEST(MemoryBudget, FindsTheProcessCgroup) {
    const std::string hybrid = "9:name=systemd:/\n4:cpu,memory:/docker/abc\n1:cpu:/\n0::/user.slice/job\n";
    EXPECT_EQ(cgroupPathOf(hybrid, false), "/user.slice/job");
    EXPECT_EQ(cgroupPathOf(hybrid, true), "/docker/abc");
    EXPECT_EQ(cgroupPathOf("0::/\n", false), "/");
    EXPECT_EQ(cgroupPathOf("0::/\n", true), "");
    // "memoryx" is not the memory controller.
    EXPECT_EQ(cgroupPathOf("3:memoryx:/a\n", true), "");
    EXPECT_EQ(cgroupPathOf("garbage", false), "");
}

TEST(MemoryBudget, ReadsTheCgroupLimitUnderARoot) {
    const fs::path root = fs::path(::testing::TempDir()) / "meniscus_budget_root";
    fs::remove_all(root);
    // v2: the own cgroup says max, its parent 6 GB, the root 8 GB: 6 GB binds.
    writeFile(root / "proc/self/cgroup", "0::/a/b\n");
    writeFile(root / "sys/fs/cgroup/a/b/memory.max", "max\n");
    writeFile(root / "sys/fs/cgroup/a/memory.max", "6000000000\n");
    writeFile(root / "sys/fs/cgroup/memory.max", "8000000000\n");
    MemoryLimits m = readMemoryLimits(root.string());
    EXPECT_EQ(m.cgroup, 6000000000u);
    EXPECT_EQ(m.cgroupFile, "memory.max");
    EXPECT_EQ(m.physical, 0u);  // the system calls are for the real root only

    // v1 only (the v2 line's cgroup has no memory.max): memory.limit_in_bytes.
    fs::remove_all(root);
    writeFile(root / "proc/self/cgroup", "4:memory:/docker/abc\n0::/\n");
    writeFile(root / "sys/fs/cgroup/memory/docker/abc/memory.limit_in_bytes", "2147483648\n");
    m = readMemoryLimits(root.string());
    EXPECT_EQ(m.cgroup, 2147483648u);
    EXPECT_EQ(m.cgroupFile, "memory.limit_in_bytes");

    // No limit anywhere.
    fs::remove_all(root);
    writeFile(root / "proc/self/cgroup", "4:memory:/x\n");
    writeFile(root / "sys/fs/cgroup/memory/memory.limit_in_bytes", "9223372036854771712\n");
    EXPECT_EQ(readMemoryLimits(root.string()).cgroup, 0u);
    fs::remove_all(root);
}

TEST(MemoryBudget, TakesTheSmallestLimit) {
    MemoryLimits m;
    EXPECT_EQ(smallestLimit(m).bytes, 0u);  // nothing known
    m.physical = 64'000'000'000;
    EXPECT_EQ(smallestLimit(m).source, "physical memory");
    m.cgroup = 8'000'000'000, m.cgroupFile = "memory.max";
    m.rlimitAs = 16'000'000'000;
    EXPECT_EQ(smallestLimit(m).bytes, 8'000'000'000u);
    EXPECT_EQ(smallestLimit(m).source, "cgroup memory.max");
    m.rlimitData = 4'000'000'000;
    EXPECT_EQ(smallestLimit(m).source, "RLIMIT_DATA");
    m.programCap = 1'000'000'000, m.programCapName = "MENISCUS_MEMORY_LIMIT";
    EXPECT_EQ(smallestLimit(m).bytes, 1'000'000'000u);
    EXPECT_EQ(smallestLimit(m).source, "MENISCUS_MEMORY_LIMIT");
}

TEST(MemoryBudget, TheProgramCapLowersTheBudget) {
    const MemoryBudget before = availableMemory();
    ASSERT_GT(before.bytes, 1'000'000u);
    setProgramMemoryCap(1'000'000, "TEST_CAP");
    EXPECT_EQ(availableMemory().bytes, 1'000'000u);
    EXPECT_EQ(availableMemory().source, "TEST_CAP");
    setProgramMemoryCap(0, "");
    EXPECT_EQ(availableMemory().bytes, before.bytes);
}

TEST(MemoryBudget, RefusesWithBothFiguresAndTheRemedy) {
    const MemoryBudget b{7'800'000'000, "cgroup memory.max"};
    const Status st = checkMemory(9'100'000'000, "meshing frame_0021.bgeo at --cube-size 0.05", "raise --cube-size",
                                  1.0, b);
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().message,
              "meshing frame_0021.bgeo at --cube-size 0.05 needs about 9.1 GB; this process may use 7.8 GB (cgroup "
              "memory.max); raise --cube-size");
    EXPECT_TRUE(checkMemory(7'000'000'000, "x", "y", 1.0, b).ok());
    // The job share: 80 % of the budget.
    EXPECT_FALSE(checkMemory(7'000'000'000, "x", "y", kJobShare, b).ok());
    EXPECT_NE(checkMemory(7'000'000'000, "x", "y", kJobShare, b).error().message.find("at most 80% of it"),
              std::string::npos);
    EXPECT_TRUE(checkMemory(6'000'000'000, "x", "y", kJobShare, b).ok());
    EXPECT_TRUE(checkMemory(~std::uint64_t(0), "x", "y", 1.0, {0, ""}).ok());  // unknown budget
    EXPECT_EQ(formatBytes(812'000'000), "812 MB");
    EXPECT_EQ(formatBytes(40'000), "40 kB");
}

// The render's per-particle bytes grow with the stages that keep arrays, and
// a PNG's frame lacks the other AOVs' host copies.
TEST(MemoryBudget, RenderEstimates) {
    EXPECT_EQ(frameBytes(100, 100, false, false, 1, true), frameBytes(100, 100) - 100u * 100u * 20u);
    const std::vector<glm::vec3> p(10, glm::vec3(0.0f));
    const ParticleView v(p);
    const std::uint64_t plain = renderBytesPerParticle(v, false, false, false);
    EXPECT_GE(plain, 12u + 12u + 16u);  // the positions, the splat's centres and rectangles
    EXPECT_EQ(renderBytesPerParticle(v, true, false, false), plain + 132u);  // shapes, centres, view ellipsoids
    EXPECT_GT(renderBytesPerParticle(v, false, true, false), plain);
    const Status st = checkRenderMemory(67108864, 180, 64, 48, frameBytes(64, 48, false, false, 1, true),
                                        {8'000'000'000, "cgroup memory.max"});
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().message,
              "rendering 67108864 particles into a 64x48 frame needs about 12.1 GB; this process may use 8.0 GB "
              "(cgroup memory.max), and this at most 80% of it; select fewer particles (--select) or use a larger "
              "machine");
}

// The mesher estimates its peak from the particles before extracting: the
// surface's cubes grow as 1 / c^2, and under a small budget it is refused
// with the cube size to raise.
TEST(MemoryBudget, TheMesherEstimatesBeforeExtracting) {
    const std::vector<glm::vec3> ball = test::ballOfParticles(glm::vec3(0.0f), 0.2f, 0.02f);
    MeshParams p;
    p.radiusM = 0.01f;
    p.threads = 1;
    MeshStats coarse, fine;
    p.cubeSizeRadii = 1.0f;
    ASSERT_TRUE(extractSurface(ParticleView(ball), p, &coarse).ok());
    p.cubeSizeRadii = 0.25f;
    ASSERT_TRUE(extractSurface(ParticleView(ball), p, &fine).ok());
    EXPECT_GT(coarse.estimatedBytes, 0u);
    EXPECT_GT(double(fine.estimatedBytes), 6.0 * double(coarse.estimatedBytes));
    setProgramMemoryCap(coarse.estimatedBytes, "TEST_CAP");
    const auto refused = extractSurface(ParticleView(ball), p);
    setProgramMemoryCap(0, "");
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("meshing " + std::to_string(ball.size()) +
                                          " particles at a cube size of 0.25 radii (2.5 mm) needs about"),
              std::string::npos)
        << refused.error().message;
    EXPECT_NE(refused.error().message.find("(TEST_CAP)"), std::string::npos) << refused.error().message;
    EXPECT_NE(refused.error().message.find("raise --cube-size"), std::string::npos) << refused.error().message;
}

}  // namespace
}  // namespace meniscus::memory_budget_test_local
