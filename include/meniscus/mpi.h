// Sort-last compositing over MPI: the SplatCompositor of
// include/meniscus/sort_last.h on an MPI communicator, for `mpirun meniscus
// render` and for simulations that render in situ on their own communicator.
// Built only when CMake finds MPI (target meniscus_mpi).
#pragma once

#include <cstdint>

#include <mpi.h>

#include "meniscus/sort_last.h"

namespace meniscus {

// Per composite, what it cost this process.
struct CompositeStats {
    double reduceScatterMs = 0.0;  // the reduction: each rank ends with the combined strip it owns
    double gatherMs = 0.0;         // the strips to the root
    // Bytes this process sends in a binary swap of the partial (one step per
    // halving: half of what it still holds, log2 K steps, (K - 1) / K of the
    // image in all), then its strip to the root. What MPI puts on the wire may
    // differ (its algorithm for the collective is its own choice).
    std::uint64_t bytesSent = 0;
    std::uint64_t imageBytes = 0;  // one partial: depth and chords
};

// Combines the partials of every process of `comm` on `root`:
// MPI_Reduce_scatter_block over the pixels (min for the depth, a wrapping
// unsigned sum for the chords: both exact and order-independent, so the
// result is bit-identical to one process splatting every particle), then
// MPI_Gather of the strips. Collective: every process of `comm` calls
// composite() for each splat, in the same order. Errors of MPI come back as a
// Status (the communicator is set to MPI_ERRORS_RETURN while compositing).
class MpiCompositor final : public SplatCompositor {
public:
    explicit MpiCompositor(MPI_Comm comm, int root = 0);
    Status composite(SplatPartial& partial) override;
    bool root() const override { return rank_ == root_; }
    int rank() const { return rank_; }
    int size() const { return size_; }
    const CompositeStats& last() const { return last_; }

private:
    MPI_Comm comm_;
    int root_ = 0, rank_ = 0, size_ = 1;
    CompositeStats last_;
};

}  // namespace meniscus
