// bench_mpi: sort-last rendering over MPI, one frame split over the K processes
// of `mpirun -n K bench_mpi [INPUT]`. Each process takes the k-th of K
// contiguous index ranges of the particles; per process the splat time (its
// share of the particles), the composite time (MPI's reduce-scatter and the
// gather of the strips on process 0) and the bytes a binary swap sends; on
// process 0 the finish (thickness, filters, normals, shading on the combined
// image) and the whole frame. Medians over --repeat runs, each started together
// (MPI_Barrier). One thread per process by default, as on a cluster where each
// rank has its own cores; on one machine the processes share its cores and its
// memory bus (loopback only). scripts/bench_mpi.sh runs K = 1 .. 4.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <mpi.h>
#include <tbb/global_control.h>

#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/mpi.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"

using namespace meniscus;

namespace {

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

double stageMs(const std::vector<StageTime>& times, const std::string& name) {
    double ms = 0.0;
    for (const StageTime& t : times)
        if (t.stage == name) ms += t.ms;
    return ms;
}

int run(int rank, int size, int argc, char** argv) {
    CLI::App app{"bench_mpi: sort-last rendering of one frame over the processes of mpirun"};
    std::string input = MENISCUS_BENCH_INPUT;
    int width = 1920, height = 1080, repeat = 5, threads = 1;
    app.add_option("input", input, "Particle file")->capture_default_str();
    app.add_option("--width", width, "Image width in pixels")->capture_default_str();
    app.add_option("--height", height, "Image height in pixels")->capture_default_str();
    app.add_option("--repeat", repeat, "Runs; medians are printed")->capture_default_str()->check(CLI::PositiveNumber);
    app.add_option("--threads", threads, "Worker threads per process")->capture_default_str()->check(CLI::PositiveNumber);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return rank == 0 ? app.exit(e) : 1;
    }
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));

    auto set = readParticles(input);
    if (!set) {
        std::fprintf(stderr, "bench_mpi: error: %s\n", set.error().describe().c_str());
        return 1;
    }
    // The whole frame's radius, camera and studio on every process; then its share.
    RenderSettings s;
    s.radiusM = estimateRadius(set->positions).radius;
    Camera base;
    base.width = width;
    base.height = height;
    s.camera = autoFrameCamera(set->positions, s.radiusM, base);
    s.scene.studioBounds = computeBounds(set->positions);
    s.colorOnly = true;
    // Spheres: the anisotropic kernels need every neighbour of a particle,
    // which sort-last gets by each process computing them for the whole frame
    // (not split, so not what this bench measures).
    s.anisotropy.enabled = false;
    const std::size_t n = set->size();
    const std::size_t begin = n * std::size_t(rank) / std::size_t(size), end = n * std::size_t(rank + 1) / std::size_t(size);
    const std::vector<glm::vec3> mine(set->positions.begin() + std::ptrdiff_t(begin),
                                      set->positions.begin() + std::ptrdiff_t(end));
    MpiCompositor compositor(MPI_COMM_WORLD);
    s.compositor = &compositor;  // on one process too, so every K times the same stages
    auto renderer = Renderer::create(BackendChoice::Cpu);
    if (!renderer) {
        std::fprintf(stderr, "bench_mpi: error: %s\n", renderer.error().describe().c_str());
        return 1;
    }

    std::vector<double> splat, reduce, gather, finish, frame;
    CompositeStats last;
    for (int k = 0; k < repeat + 1; ++k) {  // the first run warms caches and is not counted
        std::vector<StageTime> times;
        MPI_Barrier(MPI_COMM_WORLD);
        const double t0 = MPI_Wtime();
        auto aovs = renderer->render(ParticleView(std::span<const glm::vec3>(mine)), s, &times);
        const double ms = (MPI_Wtime() - t0) * 1e3;
        if (!aovs) {
            std::fprintf(stderr, "bench_mpi: error (process %d): %s\n", rank, aovs.error().describe().c_str());
            MPI_Abort(MPI_COMM_WORLD, 1);
        }
        if (k == 0) continue;
        last = compositor.last();
        const double split = stageMs(times, "depth-splat");
        splat.push_back(split);
        reduce.push_back(last.reduceScatterMs);
        gather.push_back(last.gatherMs);
        finish.push_back(ms - split - stageMs(times, "composite") - stageMs(times, "scene"));
        frame.push_back(ms);
    }
    // One line per process, printed by process 0 in rank order.
    const double mineLine[6] = {double(end - begin), median(splat), median(reduce), median(gather),
                                double(last.bytesSent), double(last.imageBytes)};
    std::vector<double> all(std::size_t(6 * size));
    MPI_Gather(mineLine, 6, MPI_DOUBLE, all.data(), 6, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (rank == 0) {
        const std::string res = std::to_string(width) + "x" + std::to_string(height);
        for (int r = 0; r < size; ++r) {
            const double* l = &all[std::size_t(6 * r)];
            std::printf("sort-last K=%d rank %d  %-9s %9.0f particles  splat %8.2f ms  composite %7.2f ms "
                        "(reduce-scatter %6.2f, gather %6.2f)  sent %7.2f MB of %5.2f MB  %dt\n",
                        size, r, res.c_str(), l[0], l[1], l[2] + l[3], l[2], l[3], l[4] / 1e6, l[5] / 1e6, threads);
        }
        std::printf("sort-last K=%d root  %-9s %9zu particles  finish %7.2f ms  frame %8.2f ms  %dt\n", size,
                    res.c_str(), n, median(finish), median(frame), threads);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    const int rc = run(rank, size, argc, argv);
    if (rc != 0) MPI_Abort(MPI_COMM_WORLD, rc);
    MPI_Finalize();
    return 0;
}
