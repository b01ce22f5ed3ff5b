// The processes one `render` runs on: MPI's world when this build has MPI and a
// launcher (mpirun, srun) started it, else this process alone. Every collective
// here is trivial on one process, so the code that uses it is the same for one
// process and for K, which is what keeps their pictures the same.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/result.h"
#include "meniscus/sort_last.h"
#include "meniscus/types.h"

namespace meniscus::app {

// How many processes a launcher started, from its environment (OpenMPI's
// OMPI_COMM_WORLD_SIZE, PMI's PMI_SIZE (MPICH, srun --mpi=pmi2), Slurm's
// SLURM_NTASKS under srun); 0 when none did.
int launcherSize();

class Cluster {
public:
    // Starts MPI when a launcher started this process and the build has MPI.
    // Without MPI, under a launcher of several processes, an error saying so
    // (each would render the whole job on its own).
    static Result<std::unique_ptr<Cluster>> start();
    ~Cluster();  // MPI_Finalize when it was started here
    Cluster(const Cluster&) = delete;
    Cluster& operator=(const Cluster&) = delete;

    int rank() const { return rank_; }
    int size() const { return size_; }
    bool root() const { return rank_ == 0; }

    // Collective: whether every process passes `ok`.
    bool allOk(bool ok);
    // Ends every process of the job with `code` (MPI_Abort; exit on one).
    [[noreturn]] void abort(int code);
    // Collective: every process's points, in rank order, on every process.
    Status allGather(std::vector<glm::vec3>& points);
    // Collective: the union of every process's bounds.
    Bounds allBounds(const Bounds& mine);
    // The sort-last compositor over the world (null on one process without MPI).
    SplatCompositor* compositor();

private:
    Cluster() = default;
    int rank_ = 0, size_ = 1;
    [[maybe_unused]] bool started_ = false;  // read only where MPI is built in
    struct Mpi;
    std::unique_ptr<Mpi> mpi_;
};

// The index range [begin, end) of share `k`'s of `count` items split into
// `n` contiguous shares as even as whole items allow (a process's share of a
// frame's particles or parts; --shard's of the frames).
struct IndexRange {
    std::size_t begin = 0, end = 0;
};
IndexRange shareRange(std::size_t count, std::size_t k, std::size_t n);

// Appends `part` to `into` (empty: becomes it); an error naming `partName`
// when its attributes (names, types, components) are not `into`'s.
Status appendParticles(ParticleSet& into, ParticleSet&& part, const std::string& partName, const std::string& intoName);

}  // namespace meniscus::app
