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
    std::error_code linkEc;
    const fs::path dest = fs::is_symlink(fs::symlink_status(path, linkEc)) ? fs::weakly_canonical(path, linkEc) : path;
    if (linkEc) return makeError(path.string(), "cannot follow the symbolic link: " + linkEc.message());
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
    std::error_code ec;
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
