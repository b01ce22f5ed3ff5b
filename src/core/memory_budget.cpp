// The memory budget (include/meniscus/memory_budget.h): the smallest of the
// machine's memory, the process's rlimits, its cgroup's limit and the
// program's cap; and the one check against it.
#include "meniscus/memory_budget.h"

#include <cstdio>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>

#include <sys/resource.h>
#include <unistd.h>

#include "shared/text_lines.h"

namespace meniscus {

namespace {

std::optional<std::string> readSmallFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::string text(4096, '\0');
    in.read(text.data(), std::streamsize(text.size()));
    text.resize(std::size_t(in.gcount()));
    return text;
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\n' || s.front() == '\r')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\n' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

// The smallest limit in the memory files of `dir` and each folder above it
// up to `mount` (a cgroup's limit binds every cgroup below it), 0 for none.
std::uint64_t cgroupLimitAlong(const std::string& mount, std::string path, const char* file, std::string* which) {
    std::uint64_t best = 0;
    while (true) {
        const std::string f = mount + path + (path.empty() || path.back() != '/' ? "/" : "") + file;
        if (auto text = readSmallFile(f))
            if (const std::uint64_t v = parseCgroupMemoryLimit(*text); v != 0 && (best == 0 || v < best)) {
                best = v;
                *which = file;
            }
        if (path.empty() || path == "/") break;
        const std::size_t slash = path.find_last_of('/');
        path = slash == std::string::npos || slash == 0 ? std::string("/") : path.substr(0, slash);
    }
    return best;
}

std::mutex& capMutex() {
    static std::mutex m;
    return m;
}
std::uint64_t gCap = 0;
std::string gCapName;

}  // namespace

std::uint64_t parseCgroupMemoryLimit(std::string_view text) {
    text = trim(text);
    if (text.empty() || text == "max") return 0;
    std::uint64_t v = 0;
    for (char c : text) {
        if (c < '0' || c > '9') return 0;
        if (v > (~std::uint64_t(0) - 9) / 10) return 0;
        v = v * 10 + std::uint64_t(c - '0');
    }
    if (v >= (std::uint64_t(1) << 60)) return 0;  // v1's "no limit"
    return v;
}

std::string cgroupPathOf(std::string_view text, bool v1) {
    shared::TextLines lines(text);
    for (std::string_view line; lines.next(line);) {
        // hierarchy-ID:controller-list:cgroup-path
        const std::size_t c1 = line.find(':');
        if (c1 == std::string_view::npos) continue;
        const std::size_t c2 = line.find(':', c1 + 1);
        if (c2 == std::string_view::npos) continue;
        const std::string_view id = line.substr(0, c1), controllers = line.substr(c1 + 1, c2 - c1 - 1);
        const std::string path(trim(line.substr(c2 + 1)));
        if (!v1) {
            if (id == "0" && controllers.empty()) return path;
            continue;
        }
        std::size_t p = 0;
        while (p <= controllers.size()) {
            std::size_t q = controllers.find(',', p);
            if (q == std::string_view::npos) q = controllers.size();
            if (controllers.substr(p, q - p) == "memory") return path;
            p = q + 1;
        }
    }
    return {};
}

MemoryLimits readMemoryLimits(const std::string& root) {
    MemoryLimits m;
    if (root.empty()) {
        const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGESIZE);
        if (pages > 0 && pageSize > 0) m.physical = std::uint64_t(pages) * std::uint64_t(pageSize);
        rlimit r{};
        if (::getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY) m.rlimitAs = std::uint64_t(r.rlim_cur);
        if (::getrlimit(RLIMIT_DATA, &r) == 0 && r.rlim_cur != RLIM_INFINITY) m.rlimitData = std::uint64_t(r.rlim_cur);
    }
    const auto self = readSmallFile(root + "/proc/self/cgroup");
    if (!self) return m;
    // cgroup v2 (the unified hierarchy); v1's memory controller if there is none.
    // In a container the path may be the host's while the mount shows the
    // container's own cgroup at its root: the walk up reaches that too.
    std::string which;
    if (const std::string v2 = cgroupPathOf(*self, false); !v2.empty())
        m.cgroup = cgroupLimitAlong(root + "/sys/fs/cgroup", v2, "memory.max", &which);
    if (m.cgroup == 0)
        if (const std::string v1 = cgroupPathOf(*self, true); !v1.empty())
            m.cgroup = cgroupLimitAlong(root + "/sys/fs/cgroup/memory", v1, "memory.limit_in_bytes", &which);
    if (m.cgroup != 0) m.cgroupFile = which;
    return m;
}

MemoryBudget smallestLimit(const MemoryLimits& m) {
    MemoryBudget b;
    auto take = [&](std::uint64_t v, const std::string& name) {
        if (v != 0 && (b.bytes == 0 || v < b.bytes)) b = {v, name};
    };
    take(m.physical, "physical memory");
    take(m.rlimitAs, "RLIMIT_AS");
    take(m.rlimitData, "RLIMIT_DATA");
    take(m.cgroup, "cgroup " + m.cgroupFile);
    take(m.programCap, m.programCapName);
    return b;
}

void setProgramMemoryCap(std::uint64_t bytes, std::string name) {
    std::lock_guard lock(capMutex());
    gCap = bytes;
    gCapName = std::move(name);
}

MemoryBudget availableMemory() {
    static const MemoryLimits system = readMemoryLimits();
    MemoryLimits m = system;
    {
        std::lock_guard lock(capMutex());
        m.programCap = gCap;
        m.programCapName = gCapName;
    }
    return smallestLimit(m);
}

std::string formatBytes(std::uint64_t bytes) {
    char s[32];
    const double b = double(bytes);
    if (b >= 1e9) std::snprintf(s, sizeof s, "%.1f GB", b / 1e9);
    else if (b >= 1e6) std::snprintf(s, sizeof s, "%.0f MB", b / 1e6);
    else std::snprintf(s, sizeof s, "%.0f kB", b / 1e3);
    return s;
}

Status checkMemory(std::uint64_t needBytes, std::string_view what, std::string_view remedy, double share,
                   const MemoryBudget& budget) {
    if (budget.bytes == 0 || double(needBytes) <= share * double(budget.bytes)) return okStatus();
    std::string msg = std::string(what) + " needs about " + formatBytes(needBytes) + "; this process may use " +
                      formatBytes(budget.bytes) + " (" + budget.source + ")";
    if (share == 0.5) msg += ", and this at most half of it";
    else if (share < 1.0) msg += ", and this at most " + std::to_string(int(share * 100.0 + 0.5)) + "% of it";
    msg += "; ";
    msg += remedy;
    return makeError("", msg);
}

}  // namespace meniscus
