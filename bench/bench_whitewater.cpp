// bench_whitewater: the whitewater generator's speed (Ihmsen et al. 2012,
// include/meniscus/whitewater.h) over a fluid sequence (default: the small
// SPlisHSPlasH dam break's frames 19-23 in data/demo, 6,859 particles at
// 15 fps), one line per phase: the median per frame of the fluid potentials,
// the diffuse particles' classification and advection, and the generation,
// with the particle counts and the threads. The automatic limits' measuring
// pass is timed as its own line.
//   bench_whitewater [INPUT...] [--fps F] [--radius R] [--repeat N] [--threads N]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "meniscus/io.h"
#include "meniscus/options.h"
#include "meniscus/particles.h"
#include "meniscus/whitewater.h"

using namespace meniscus;

namespace {
double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}
double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"bench_whitewater: per-phase timings of `meniscus whitewater` (medians per frame)"};
    std::vector<std::string> inputs;
    double fps = 15.0;
    float radius = 0.0f;
    int repeat = 3, threads = 0;
    app.add_option("input", inputs, "Fluid frames in order, with velocities (default: data/demo, frames 19-23)");
    app.add_option("--fps", fps, "Frames per second of the input")->capture_default_str();
    app.add_option("--radius", radius, "Particle radius in metres (0: estimated from the first frame)");
    app.add_option("--repeat", repeat, "Runs over the whole sequence; the medians are over every frame of every run")
        ->capture_default_str();
    app.add_option("--threads", threads, "Worker threads (default: all cores)");
    CLI11_PARSE(app, argc, argv);
    if (inputs.empty())
        for (int k = 19; k <= 23; ++k)
            inputs.push_back(std::string(MENISCUS_BENCH_DEMO) + "/ParticleData_Fluid_" + std::to_string(k) + ".bgeo");
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
    const int usedThreads = threads > 0 ? threads : tbb::info::default_concurrency();

    std::vector<ParticleSet> frames;
    for (const std::string& in : inputs) {
        auto set = readParticles(in);
        if (!set) {
            std::fprintf(stderr, "bench_whitewater: %s\n", set.error().describe().c_str());
            return 1;
        }
        frames.push_back(std::move(*set));
    }
    const auto resolved = resolveRadius(radius, [&] { return defaultRadius(frames[0]); });
    if (!resolved) {
        std::fprintf(stderr, "bench_whitewater: %s\n", resolved.error().describe().c_str());
        return 1;
    }
    radius = *resolved;

    std::vector<double> measure, potentials, advect, generate, total;
    std::size_t alive = 0, made = 0;
    for (int run = 0; run < repeat; ++run) {
        auto t0 = std::chrono::steady_clock::now();
        std::vector<sim::PotentialMaxima> maxima;
        for (const ParticleSet& f : frames) {
            auto pot = sim::computePotentials(ParticleView::of(f), radius, WhitewaterParams{});
            if (!pot) {
                std::fprintf(stderr, "bench_whitewater: %s\n", pot.error().describe().c_str());
                return 1;
            }
            maxima.push_back(sim::maximaOf(*pot));
        }
        measure.push_back(msSince(t0) / double(frames.size()));
        auto gen = sim::WhitewaterGenerator::create(sim::withAutomaticLimits(WhitewaterParams{}, maxima), radius);
        if (!gen) return 1;
        made = 0;
        for (const ParticleSet& f : frames) {
            t0 = std::chrono::steady_clock::now();
            auto s = gen->step(ParticleView::of(f), 1.0 / fps);
            total.push_back(msSince(t0));
            if (!s) {
                std::fprintf(stderr, "bench_whitewater: %s\n", s.error().describe().c_str());
                return 1;
            }
            potentials.push_back(s->msPotentials);
            advect.push_back(s->msAdvect);
            generate.push_back(s->msGenerate);
            made += s->generated;
        }
        alive = gen->particles().size();
    }
    const std::size_t n = frames[0].size();
    std::printf("input                 %zu frames, %zu fluid particles, r = %.4g m, %.4g fps, %d threads\n",
                frames.size(), n, radius, fps, usedThreads);
    std::printf("measure (auto limits) %8.2f ms/frame  %zu fluid particles\n", median(measure), n);
    std::printf("potentials            %8.2f ms/frame  %zu fluid particles\n", median(potentials), n);
    std::printf("classify+advect       %8.2f ms/frame  %zu diffuse alive at the end\n", median(advect), alive);
    std::printf("generate              %8.2f ms/frame  %zu made over the sequence\n", median(generate), made);
    std::printf("step total            %8.2f ms/frame\n", median(total));
    return 0;
}
