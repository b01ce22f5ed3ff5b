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
    // Same directory, so the rename is atomic; hidden, so a sequence glob never picks it up.
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    const fs::path tmp = dir / ("." + path.filename().string() + ".tmp" + std::to_string(::getpid()) + "_" +
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
    fs::rename(tmp, path, ec);
    if (ec) {
        const std::string why = ec.message();
        fs::remove(tmp, ec);
        return makeError(path.string(), "cannot create output file: " + why);
    }
    return okStatus();
}

}  // namespace meniscus
