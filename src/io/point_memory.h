// The memory budget's check for the particle readers: a file's announced
// point count times the bytes the reader holds per point, refused before the
// arrays are allocated. The readers first make sure the bytes for that many
// points exist (a count is never trusted before); this check is the other
// half, for files that honestly hold more points than this process can keep
// (a 1 MB gzip BGEO may inflate to 67 million points).
#pragma once

#include <cstdint>
#include <string>

#include "io/io_util.h"
#include "meniscus/memory_budget.h"

namespace meniscus::io_util {

// Throws ParseFailure (guardParse names the file) when `points` points of
// `bytesPerPoint` bytes do not fit in the job's share of the budget.
inline void checkPointMemory(std::uint64_t points, std::uint64_t bytesPerPoint) {
    const std::uint64_t need = points > ~std::uint64_t(0) / std::max<std::uint64_t>(bytesPerPoint, 1)
                                   ? ~std::uint64_t(0)
                                   : points * bytesPerPoint;
    if (auto st = checkMemory(need,
                              "holding its " + std::to_string(points) + " points (" + std::to_string(bytesPerPoint) +
                                  " bytes each while reading)",
                              "read it where more memory is available, or split it into smaller files");
        !st)
        fail(st.error().message);
}

}  // namespace meniscus::io_util
