// Write-then-rename, so that a failed write never leaves a partial file.
#pragma once

#include <filesystem>
#include <functional>

#include "meniscus/result.h"

namespace meniscus {

// Calls write(tmpPath) with a temporary path in the same directory as `path`;
// on success renames it onto `path`, on failure (or exception) removes it.
Status writeAtomically(const std::filesystem::path& path,
                       const std::function<Status(const std::filesystem::path& tmpPath)>& write);

}  // namespace meniscus
