// Write-then-rename beside the file replaced (see atomic_file.h and
// PendingFile in include/meniscus/io.h).
#include "atomic_file.h"

#include <atomic>
#include <cerrno>
#include <chrono>
#include <exception>
#include <string>
#include <system_error>
#include <vector>

#include <signal.h>
#include <unistd.h>

#include "meniscus/io.h"
#include "meniscus/temporaries.h"

namespace meniscus {

namespace {

// What an existing output that is not a regular file is, for the refusal;
// empty where it is absent or a regular file (those are written).
std::string notAFile(const std::filesystem::path& dest) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::symlink_status(dest, ec);
    switch (st.type()) {
        case fs::file_type::not_found:
        case fs::file_type::none:
        case fs::file_type::regular: return {};
        case fs::file_type::directory: return "a directory";
        case fs::file_type::character:
        case fs::file_type::block: return "a device";
        case fs::file_type::fifo: return "a named pipe (FIFO)";
        case fs::file_type::socket: return "a socket";
        default: return "not a regular file";
    }
}

// The refusal of an output that is (or links to) something other than a
// regular file: replacing it by a file (a rename over /dev/null, say) would
// be wrong; it is the command line's output that is wrong (Error::usage).
Status checkReplaceable(const std::filesystem::path& path, const std::filesystem::path& dest) {
    const std::string what = notAFile(dest);
    if (what.empty()) return okStatus();
    const bool linked = path != dest;
    return makeUsageError(path.string(), std::string(linked ? "is a link to " : "is ") + what +
                                             ", not a file; choose another output");
}

}  // namespace

Result<PendingFile> PendingFile::begin(const std::filesystem::path& path) {
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
    // Only a regular file (or nothing) is replaced: never a device, a pipe,
    // a socket or a folder, whether named or linked to.
    if (auto st = checkReplaceable(path, dest); !st) return st.error();
    // Same directory, so the rename is atomic; hidden, so a sequence glob never picks it up.
    const fs::path dir = dest.has_parent_path() ? dest.parent_path() : fs::path(".");
    fs::path tmp = dir / ("." + dest.filename().string() + ".tmp" + std::to_string(::getpid()) + "_" +
                          std::to_string(counter++));
    return PendingFile(path, std::move(dest), std::move(tmp));
}

PendingFile::PendingFile(PendingFile&& other) noexcept
    : path_(std::move(other.path_)), dest_(std::move(other.dest_)), tmp_(std::move(other.tmp_)) {
    other.tmp_.clear();
}

PendingFile& PendingFile::operator=(PendingFile&& other) noexcept {
    if (this != &other) {
        discard();
        path_ = std::move(other.path_);
        dest_ = std::move(other.dest_);
        tmp_ = std::move(other.tmp_);
        other.tmp_.clear();
    }
    return *this;
}

PendingFile::~PendingFile() { discard(); }

void PendingFile::discard() {
    if (tmp_.empty()) return;
    std::error_code ec;
    std::filesystem::remove(tmp_, ec);
    tmp_.clear();
}

Status PendingFile::commit() {
    if (tmp_.empty()) return makeError(path_.string(), "nothing to commit (already committed or discarded)");
    // Checked again just before the rename: the output may have changed
    // since begin().
    if (auto st = checkReplaceable(path_, dest_); !st) {
        discard();
        return st;
    }
    std::error_code ec;
    std::filesystem::rename(tmp_, dest_, ec);
    if (ec) {
        const std::string why = ec.message();
        discard();
        return makeError(path_.string(), "cannot create output file: " + why);
    }
    tmp_.clear();
    return okStatus();
}

Status makeOutputFolders(const std::filesystem::path& file) {
    const std::filesystem::path parent = file.parent_path();
    if (parent.empty()) return okStatus();
    std::error_code ec;
    if (std::filesystem::is_directory(parent, ec)) return okStatus();
    std::filesystem::create_directories(parent, ec);
    if (ec) return makeError(file.string(), "cannot make the folder " + parent.string() + ": " + ec.message());
    return okStatus();
}

Status writeAtomically(const std::filesystem::path& path,
                       const std::function<Status(const std::filesystem::path&)>& write) {
    auto pending = PendingFile::begin(path);
    if (!pending) return pending.error();
    Status st = okStatus();
    try {
        st = write(pending->tmp());
    } catch (const std::exception& e) {
        st = makeError(path.string(), std::string("write failed: ") + e.what());
    }
    if (!st.ok()) return st;  // the pending file removes the temporary
    return pending->commit();
}

namespace {

// The PID in a temporary's name `.<name>.tmp<PID>_<N>` (begin()'s), or -1
// when `file` is not exactly such a name.
long temporaryPid(const std::string& file) {
    if (file.size() < 2 || file[0] != '.') return -1;
    const std::size_t underscore = file.rfind('_');
    if (underscore == std::string::npos || underscore + 1 == file.size()) return -1;
    for (std::size_t i = underscore + 1; i < file.size(); ++i)
        if (file[i] < '0' || file[i] > '9') return -1;
    std::size_t digits = underscore;
    while (digits > 0 && file[digits - 1] >= '0' && file[digits - 1] <= '9') --digits;
    if (digits == underscore || underscore - digits > 9 || digits < 5) return -1;  // ".x.tmp" at least before
    if (file.compare(digits - 4, 4, ".tmp") != 0 || digits - 4 < 2) return -1;  // a name between '.' and ".tmp"
    return std::stol(file.substr(digits, underscore - digits));
}

}  // namespace

std::vector<std::filesystem::path> removeStaleTemporaries(const std::filesystem::path& folder,
                                                          std::chrono::seconds olderThan) {
    namespace fs = std::filesystem;
    std::vector<fs::path> removed;
    std::error_code ec;
    fs::directory_iterator it(folder.empty() ? fs::path(".") : folder, ec);
    if (ec) return removed;
    const auto now = fs::file_time_type::clock::now();
    for (; it != fs::directory_iterator(); it.increment(ec)) {
        if (ec) break;
        const fs::path& file = it->path();
        const long pid = temporaryPid(file.filename().string());
        if (pid <= 0) continue;
        std::error_code fileEc;
        if (!fs::is_regular_file(fs::symlink_status(file, fileEc))) continue;  // only files, never a link's target
        // A PID that names a live process (ours, another run's, another
        // user's: EPERM) keeps its file; only "no such process" removes it.
        if (::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;
        if (olderThan.count() > 0) {
            const auto changed = fs::last_write_time(file, fileEc);
            if (fileEc || now - changed < olderThan) continue;
        }
        if (fs::remove(file, fileEc)) removed.push_back(file);
    }
    return removed;
}

}  // namespace meniscus
