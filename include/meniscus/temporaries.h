// The temporaries of write-then-rename (PendingFile, include/meniscus/io.h):
// every output is first written as `.<name>.tmp<PID>_<N>` beside it and
// renamed when whole. A process killed before the rename (SIGKILL, a power
// cut) leaves its temporary behind; the next run into the folder removes it.
#pragma once

#include <chrono>
#include <filesystem>
#include <vector>

namespace meniscus {

// The temporaries a killed process left in `folder`: regular files named
// exactly `.<name>.tmp<PID>_<N>` whose PID is no live process (kill(PID, 0)
// fails with ESRCH) are removed; a live process's (this one's, another run's,
// another user's), and anything else, stay. Only those unchanged for
// `olderThan` (0: any age), for a folder that processes on other machines
// write into as well (their PIDs mean nothing here). Returns the files
// removed; a folder that cannot be listed removes nothing.
std::vector<std::filesystem::path> removeStaleTemporaries(const std::filesystem::path& folder,
                                                          std::chrono::seconds olderThan = std::chrono::seconds(0));

}  // namespace meniscus
