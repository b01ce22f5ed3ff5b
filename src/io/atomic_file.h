// Write-then-rename, so that a failed write never leaves a partial file.
#pragma once

#include <filesystem>
#include <functional>

#include "meniscus/result.h"

namespace meniscus {

// Calls write(tmpPath) with a temporary path in the same directory as `path`;
// on success renames it onto `path`, on failure (or exception) removes it.
// When `path` is a symbolic link the write goes through it: the temporary file
// is made beside the link's (final) target and renamed onto the target, so the
// link stays and points at the new content. An output that is not a regular
// file, or a link to one that is not (a device, a FIFO, a socket, a folder),
// is refused (Error::usage) before write is called: it is never replaced.
Status writeAtomically(const std::filesystem::path& path,
                       const std::function<Status(const std::filesystem::path& tmpPath)>& write);

}  // namespace meniscus
