// The memory budget: how much this process may use, and the one check every
// large allocation makes against it before allocating (a frame's images, a
// mesh's cubes, a simulation's particles, a reader's arrays), so an input or
// setting that would not fit is refused at once with both figures and the
// option that lowers the need, instead of growing for minutes and being
// killed by the kernel.
//
// The budget is the smallest of: the machine's physical memory, the
// process's RLIMIT_AS and RLIMIT_DATA (getrlimit; RLIM_INFINITY is no limit),
// its cgroup's limit (cgroup v2: memory.max of the process's own cgroup, from
// /proc/self/cgroup, and of each cgroup above it, "max" being none; cgroup
// v1: memory.limit_in_bytes), and a cap the program may set (the CLI's
// MENISCUS_MEMORY_LIMIT, docs/usage.md).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "meniscus/result.h"

namespace meniscus {

// The share of the budget one check may claim.
//   kFrameShare: a frame's images (frameBytes). The particles as read, the
//   renderer's per-particle arrays, the scene's geometry and the program
//   itself take the rest, so a frame is held to half.
//   kJobShare: an estimate of a whole command's peak (meshing, simulating, a
//   reader's arrays plus what the command keeps per point). The estimates
//   are within a quarter of the measured peaks (docs/performance.md, "Memory
//   budget"); the fifth left over covers that error and the allocator's
//   slack.
inline constexpr double kFrameShare = 0.5;
inline constexpr double kJobShare = 0.8;

// The figures the budget is the smallest of; 0 = no limit (or unknown).
struct MemoryLimits {
    std::uint64_t physical = 0;
    std::uint64_t rlimitAs = 0;
    std::uint64_t rlimitData = 0;
    std::uint64_t cgroup = 0;
    std::string cgroupFile;      // the memory.max / memory.limit_in_bytes that set `cgroup`
    std::uint64_t programCap = 0;
    std::string programCapName;  // what set it, e.g. "MENISCUS_MEMORY_LIMIT"
};

// How much this process may use and why: bytes 0 when nothing is known.
struct MemoryBudget {
    std::uint64_t bytes = 0;
    std::string source;  // "physical memory", "RLIMIT_AS", "cgroup memory.max", ...
};

// The smallest limit of `limits` and its name.
MemoryBudget smallestLimit(const MemoryLimits& limits);

// Parsing, separate so that it is tested on made-up file contents.
// A cgroup memory limit file's value: memory.max's "max" (none), or bytes.
// cgroup v1 writes "no limit" as a huge page-rounded number (2^63 - 4096):
// values of 2^60 and above are none too. 0 for none or unreadable text.
std::uint64_t parseCgroupMemoryLimit(std::string_view text);
// The process's cgroup path from /proc/self/cgroup's text: the cgroup v2
// line "0::/path" (v1 false), or the v1 line whose controllers include
// "memory" ("4:memory:/path"). Empty when there is none.
std::string cgroupPathOf(std::string_view procSelfCgroup, bool v1);

// The system's limits, read under `root` (empty: the real / ; tests pass a
// folder holding proc/self/cgroup and sys/fs/cgroup/...): physical memory
// and rlimits come from the system calls only when root is empty.
MemoryLimits readMemoryLimits(const std::string& root = "");

// A cap on the budget set by the program (0 removes it), named in messages.
// The library reads no environment variable; the CLI sets this from
// MENISCUS_MEMORY_LIMIT.
void setProgramMemoryCap(std::uint64_t bytes, std::string name);

// The process's budget: the system's limits (read once) and the program's cap.
MemoryBudget availableMemory();
inline std::uint64_t availableMemoryBytes() { return availableMemory().bytes; }

// "9.1 GB", "812 MB", "40 kB" (decimal units, as the messages print them).
std::string formatBytes(std::uint64_t bytes);

// OK when `needBytes` fits in `share` of `budget` (a budget of 0 bytes,
// unknown, accepts everything); otherwise the error, one line:
//   "<what> needs about 9.1 GB; this process may use 7.8 GB (cgroup
//    memory.max)[, and this at most half of it]; <remedy>".
Status checkMemory(std::uint64_t needBytes, std::string_view what, std::string_view remedy,
                   double share = kJobShare, const MemoryBudget& budget = availableMemory());

}  // namespace meniscus
