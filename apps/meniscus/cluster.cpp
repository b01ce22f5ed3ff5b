// The processes of one `render` (cluster.h). MPI is started only when a
// launcher started this process: a plain `meniscus render` never touches MPI
// (a singleton MPI_Init costs time and, in some containers, fails).
#include "cluster.h"

#include <algorithm>
#include <cstdlib>
#include <iostream>

#ifdef MENISCUS_HAVE_MPI
#include <mpi.h>

#include "meniscus/mpi.h"
#endif

namespace meniscus::app {

int launcherSize() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
        const char* v = std::getenv(name);
        if (v && *v) {
            const int n = std::atoi(v);
            if (n > 0) return n;
        }
    }
    // srun starts tasks with SLURM_NTASKS but without PMI variables when no MPI plugin is asked for.
    if (std::getenv("SLURM_STEP_ID") && std::getenv("SLURM_NTASKS")) return std::max(1, std::atoi(std::getenv("SLURM_NTASKS")));
    return 0;
}

#ifdef MENISCUS_HAVE_MPI
struct Cluster::Mpi {
    std::unique_ptr<MpiCompositor> compositor;
};
#else
struct Cluster::Mpi {};
#endif

Result<std::unique_ptr<Cluster>> Cluster::start() {
    std::unique_ptr<Cluster> c(new Cluster());
    const int launched = launcherSize();
#ifdef MENISCUS_HAVE_MPI
    if (launched > 0) {
        int provided = 0;
        if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
            return makeError("", "MPI_Init_thread failed (started by mpirun, but MPI could not start)");
        c->started_ = true;
        MPI_Comm_rank(MPI_COMM_WORLD, &c->rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &c->size_);
        c->mpi_ = std::make_unique<Mpi>();
        c->mpi_->compositor = std::make_unique<MpiCompositor>(MPI_COMM_WORLD, 0);
    }
#else
    if (launched > 1)
        return makeError("", "this meniscus is not an MPI build (no MPI was found when it was configured: install "
                             "libopenmpi-dev and rebuild), so each of the " + std::to_string(launched) +
                             " processes would render the whole job: run one, or split a sequence with --shard I/N");
    if (launched == 1) std::cerr << "meniscus: note: started by mpirun, but this is not an MPI build: one process\n";
#endif
    return c;
}

Cluster::~Cluster() {
#ifdef MENISCUS_HAVE_MPI
    if (started_) {
        mpi_.reset();
        MPI_Finalize();
    }
#endif
}

bool Cluster::allOk(bool ok) {
#ifdef MENISCUS_HAVE_MPI
    if (started_) {
        int mine = ok ? 1 : 0, all = 0;
        MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
        return all == 1;
    }
#endif
    return ok;
}

void Cluster::abort(int code) {
#ifdef MENISCUS_HAVE_MPI
    if (started_) MPI_Abort(MPI_COMM_WORLD, code);
#endif
    std::exit(code);
}

Status Cluster::allGather(std::vector<glm::vec3>& points) {
#ifdef MENISCUS_HAVE_MPI
    if (started_ && size_ > 1) {
        static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
        const int mine = int(points.size() * 3);
        std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
        if (MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD) != MPI_SUCCESS)
            return makeError("", "MPI_Allgather failed");
        long long total = 0;
        for (int r = 0; r < size_; ++r) {
            offsets[std::size_t(r)] = int(total);
            total += counts[std::size_t(r)];
        }
        if (total > 0x7fffffff) return makeError("", "too many camera sample points for MPI's counts");
        std::vector<glm::vec3> all(std::size_t(total / 3));
        if (MPI_Allgatherv(points.data(), mine, MPI_FLOAT, all.data(), counts.data(), offsets.data(), MPI_FLOAT,
                           MPI_COMM_WORLD) != MPI_SUCCESS)
            return makeError("", "MPI_Allgatherv failed");
        points = std::move(all);
    }
#else
    (void)points;
#endif
    return okStatus();
}

Bounds Cluster::allBounds(const Bounds& mine) {
#ifdef MENISCUS_HAVE_MPI
    if (started_ && size_ > 1) {
        // Min of (min, -max): one reduction; +-inf of an empty share drop out.
        float in[6] = {mine.min.x, mine.min.y, mine.min.z, -mine.max.x, -mine.max.y, -mine.max.z}, out[6];
        MPI_Allreduce(in, out, 6, MPI_FLOAT, MPI_MIN, MPI_COMM_WORLD);
        Bounds b;
        b.min = {out[0], out[1], out[2]};
        b.max = {-out[3], -out[4], -out[5]};
        return b;
    }
#endif
    return mine;
}

SplatCompositor* Cluster::compositor() {
#ifdef MENISCUS_HAVE_MPI
    if (mpi_) return mpi_->compositor.get();
#endif
    return nullptr;
}

IndexRange shareRange(std::size_t count, std::size_t k, std::size_t n) {
    const auto at = [&](std::size_t j) {
        return std::size_t((unsigned long long)(count) * (unsigned long long)(j) / (unsigned long long)(n));
    };
    return {at(k), at(k + 1)};
}

Status appendParticles(ParticleSet& into, ParticleSet&& part, const std::string& partName,
                       const std::string& intoName) {
    if (into.positions.empty() && into.attributes.empty()) {
        into = std::move(part);
        return okStatus();
    }
    const auto describe = [](const ParticleSet& s) {
        std::string names;
        for (const Attribute& a : s.attributes) names += (names.empty() ? "" : ", ") + a.name;
        return names.empty() ? std::string("none") : names;
    };
    bool same = into.attributes.size() == part.attributes.size();
    for (std::size_t k = 0; same && k < into.attributes.size(); ++k) {
        const Attribute* p = part.find(into.attributes[k].name);
        same = p && p->type == into.attributes[k].type && p->components == into.attributes[k].components;
    }
    if (!same)
        return makeError(partName, "its attributes (" + describe(part) + ") are not those of " + intoName + " (" +
                                       describe(into) + "): the parts of one frame must carry the same attributes");
    into.positions.insert(into.positions.end(), part.positions.begin(), part.positions.end());
    for (Attribute& a : into.attributes) {
        const Attribute& p = *part.find(a.name);
        if (a.type == AttributeType::Float) a.floats.insert(a.floats.end(), p.floats.begin(), p.floats.end());
        else a.ints.insert(a.ints.end(), p.ints.begin(), p.ints.end());
    }
    for (std::string& w : part.warnings) into.warnings.push_back(std::move(w));
    return okStatus();
}

}  // namespace meniscus::app
