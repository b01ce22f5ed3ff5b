// Sort-last compositing over MPI (include/meniscus/mpi.h). The field's way is
// binary swap (Ma et al. 1994; IceT's radix-k generalises it): each step, pairs
// of processes swap halves of what they hold and combine, so after log2 K steps
// each holds 1/K of the finished image. MPI_Reduce_scatter_block is that
// collective with the library's own choice of algorithm (OpenMPI's is a
// recursive halving for commutative operations), so it is used as is rather
// than re-implemented on point-to-point messages. The operations are MPI_MIN
// on floats (the depth: exact) and MPI_SUM on unsigned 32-bit integers (the
// fixed-point chords: modular, hence exact and order-independent), which is
// what makes the result bit-identical for any process count.
#include "meniscus/mpi.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace meniscus {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

std::string mpiMessage(int code) {
    char text[MPI_MAX_ERROR_STRING] = {};
    int len = 0;
    MPI_Error_string(code, text, &len);
    return std::string(text, std::size_t(std::max(len, 0)));
}

// The communicator's error handler set to MPI_ERRORS_RETURN for one scope
// (the caller's own handler is put back), so a failure is a Status here.
class ErrorsReturn {
public:
    explicit ErrorsReturn(MPI_Comm comm) : comm_(comm) {
        MPI_Comm_get_errhandler(comm_, &saved_);
        MPI_Comm_set_errhandler(comm_, MPI_ERRORS_RETURN);
    }
    ~ErrorsReturn() {
        MPI_Comm_set_errhandler(comm_, saved_);
        MPI_Errhandler_free(&saved_);
    }
    ErrorsReturn(const ErrorsReturn&) = delete;
    ErrorsReturn& operator=(const ErrorsReturn&) = delete;

private:
    MPI_Comm comm_;
    MPI_Errhandler saved_ = MPI_ERRHANDLER_NULL;
};

// One image reduced over the communicator with `op` (the padding of the last
// strip filled with `pad`, the operation's identity) and gathered on the root.
template <class T>
Status reduceImage(MPI_Comm comm, int root, int size, std::vector<T>& pixels, MPI_Datatype type, MPI_Op op, T pad,
                   double& reduceMs, double& gatherMs) {
    const std::size_t n = pixels.size();
    const std::size_t strip = (n + std::size_t(size) - 1) / std::size_t(size);
    if (strip > std::size_t(std::numeric_limits<int>::max()))
        return makeError("", "sort-last compositing: an image of " + std::to_string(n) + " pixels is too large for MPI's counts");
    std::vector<T> send(strip * std::size_t(size), pad), mine(strip);
    std::copy(pixels.begin(), pixels.end(), send.begin());
    auto t0 = Clock::now();
    if (int rc = MPI_Reduce_scatter_block(send.data(), mine.data(), int(strip), type, op, comm); rc != MPI_SUCCESS)
        return makeError("", "sort-last compositing: MPI_Reduce_scatter_block failed: " + mpiMessage(rc));
    reduceMs += msSince(t0);
    t0 = Clock::now();
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    if (int rc = MPI_Gather(mine.data(), int(strip), type, rank == root ? send.data() : nullptr, int(strip), type, root,
                            comm);
        rc != MPI_SUCCESS)
        return makeError("", "sort-last compositing: MPI_Gather failed: " + mpiMessage(rc));
    gatherMs += msSince(t0);
    if (rank == root) std::copy(send.begin(), send.begin() + std::ptrdiff_t(n), pixels.begin());
    return okStatus();
}

}  // namespace

MpiCompositor::MpiCompositor(MPI_Comm comm, int root) : comm_(comm), root_(root) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
}

Status MpiCompositor::composite(SplatPartial& partial) {
    last_ = {};
    ErrorsReturn errors(comm_);
    // Every process must bring images of one size (the same camera): checked
    // first, since a mismatch would make the reduction read past a buffer.
    int dims[4] = {partial.depth.width, partial.depth.height, partial.chords.width, partial.chords.height};
    int low[4], high[4];
    if (int rc = MPI_Allreduce(dims, low, 4, MPI_INT, MPI_MIN, comm_); rc != MPI_SUCCESS)
        return makeError("", "sort-last compositing: MPI_Allreduce failed: " + mpiMessage(rc));
    if (int rc = MPI_Allreduce(dims, high, 4, MPI_INT, MPI_MAX, comm_); rc != MPI_SUCCESS)
        return makeError("", "sort-last compositing: MPI_Allreduce failed: " + mpiMessage(rc));
    if (!std::equal(low, low + 4, high))
        return makeError("", "sort-last compositing: the processes rendered images of different sizes (depth " +
                                 std::to_string(low[0]) + "x" + std::to_string(low[1]) + " to " +
                                 std::to_string(high[0]) + "x" + std::to_string(high[1]) + "): give them one camera");
    static_assert(sizeof(float) == 4 && std::numeric_limits<float>::has_infinity);
    if (auto st = reduceImage(comm_, root_, size_, partial.depth.pixels, MPI_FLOAT, MPI_MIN,
                              std::numeric_limits<float>::infinity(), last_.reduceScatterMs, last_.gatherMs);
        !st)
        return st;
    if (auto st = reduceImage<std::uint32_t>(comm_, root_, size_, partial.chords.pixels, MPI_UINT32_T, MPI_SUM, 0u,
                                             last_.reduceScatterMs, last_.gatherMs);
        !st)
        return st;
    last_.imageBytes = std::uint64_t(partial.depth.size()) * 4u + std::uint64_t(partial.chords.size()) * 4u;
    const std::uint64_t k = std::uint64_t(size_);
    last_.bytesSent = last_.imageBytes * (k - 1) / k + (root() ? 0u : last_.imageBytes / k);
    return okStatus();
}

}  // namespace meniscus
