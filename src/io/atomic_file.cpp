// Write-then-rename beside the file replaced (see atomic_file.h).
#include "atomic_file.h"

#include <atomic>
#include <exception>
#include <string>
#include <system_error>

#include <unistd.h>

namespace meniscus {

Status writeAtomically(const std::filesystem::path& path,
                       const std::function<Status(const std::filesystem::path&)>& write) {
    namespace fs = std::filesystem;
    static std::atomic<unsigned> counter{0};
    // A symlinked output is written through the link: the file replaced is its
    // target, so the link stays a link.
    // Links are followed one by one (a dangling one too: its target is created).
    fs::path dest = path;
    std::error_code ec;
    for (int hops = 0; fs::is_symlink(fs::symlink_status(dest, ec)); ++hops) {
        if (hops == 40) return makeError(path.string(), "cannot follow the symbolic link: too many levels of links");
        const fs::path target = fs::read_symlink(dest, ec);
        if (ec) return makeError(path.string(), "cannot follow the symbolic link: " + ec.message());
        dest = (target.is_absolute() ? target : dest.parent_path() / target).lexically_normal();
    }
    // Same directory, so the rename is atomic; hidden, so a sequence glob never picks it up.
    const fs::path dir = dest.has_parent_path() ? dest.parent_path() : fs::path(".");
    const fs::path tmp = dir / ("." + dest.filename().string() + ".tmp" + std::to_string(::getpid()) + "_" +
                                std::to_string(counter++));
    Status st = okStatus();
    try {
        st = write(tmp);
    } catch (const std::exception& e) {
        st = makeError(path.string(), std::string("write failed: ") + e.what());
    }
    if (!st.ok()) {
        fs::remove(tmp, ec);
        return st;
    }
    fs::rename(tmp, dest, ec);
    if (ec) {
        const std::string why = ec.message();
        fs::remove(tmp, ec);
        return makeError(path.string(), "cannot create output file: " + why);
    }
    return okStatus();
}

}  // namespace meniscus
