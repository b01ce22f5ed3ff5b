// bench_sim: the simulator's speed on a scene (default: the r = 0.01 dam
// break, SPlisHSPlasH's DamBreakModel), one line per phase.
//   bench_sim [SCENE] [--radius R] [--seconds S] [--threads N] [--peer-log SPH_log.txt]
// With --seconds shorter than the scene's duration the run is that long and
// the lines say so; nothing is extrapolated unless a line says "extrapolated".
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <regex>
#include <string>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "meniscus/sim.h"

using namespace meniscus;

namespace {

// SPlisHSPlasH's own summary: "Time sum: SimStep: 405107 ms", "Average number: Time step size: 0.0019".
void printPeer(const std::string& path) {
    std::ifstream in(path);
    if (!in) {
        std::printf("peer        : cannot read %s\n", path.c_str());
        return;
    }
    std::string line, particles = "?", total = "?", dt = "?", it = "?", itV = "?", simulated = "?";
    auto grab = [&](const char* key, std::string& out) {
        const auto at = line.find(key);
        if (at != std::string::npos) out = line.substr(at + std::string(key).size());
    };
    while (std::getline(in, line)) {
        grab("Number of fluid particles: ", particles);
        grab("Time sum: SimStep: ", total);
        grab("Average number: Time step size: ", dt);
        grab("Average number: DFSPH - iterations: ", it);
        grab("Average number: DFSPH - iterationsV: ", itV);
        grab("Total number: Time step size: ", simulated);
    }
    std::printf("peer        : SPlisHSPlasH log %s: %s particles, %s s simulated in %s wall, mean dt %s s, mean "
                "iterations %s density / %s divergence\n",
                path.c_str(), particles.c_str(), simulated.c_str(), total.c_str(), dt.c_str(), it.c_str(), itV.c_str());
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"bench_sim: time the built-in SPH simulator, one line per phase"};
    std::string scenePath = MENISCUS_BENCH_SCENE;
    float radius = 0.01f;
    double seconds = 0.0;
    int threads = 0;
    std::string peerLog;
    app.add_option("scene", scenePath, "Scene file")->capture_default_str();
    app.add_option("--radius", radius, "Particle radius in metres (0: the scene's)")->capture_default_str();
    app.add_option("--seconds", seconds, "Simulated seconds (0: the scene's duration)")->capture_default_str();
    app.add_option("--threads", threads, "Worker threads (default: all cores)");
    app.add_option("--peer-log", peerLog, "SPlisHSPlasH's SPH_log.txt of the same scene, printed for comparison");
    CLI11_PARSE(app, argc, argv);
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
    const int used = threads > 0 ? threads : tbb::info::default_concurrency();

    auto scene = sim::readScene(scenePath);
    if (!scene) {
        std::fprintf(stderr, "bench_sim: %s\n", scene.error().describe().c_str());
        return 1;
    }
    if (radius > 0.0f) scene->params.radius = radius;
    const double duration = seconds > 0.0 ? seconds : scene->duration;
    const auto t0 = std::chrono::steady_clock::now();
    auto made = sim::Simulator::create(*scene);
    if (!made) {
        std::fprintf(stderr, "bench_sim: %s\n", made.error().describe().c_str());
        return 1;
    }
    sim::Simulator& s = **made;
    const double setupMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const auto t1 = std::chrono::steady_clock::now();
    if (auto st = s.advanceTo(duration); !st) {
        std::fprintf(stderr, "bench_sim: %s\n", st.error().describe().c_str());
        return 1;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    const sim::Totals& T = s.totals();
    const double steps = double(std::max<std::size_t>(T.steps, 1));
    std::printf("scene       : %s, %s, r = %g m, %zu particles, %d threads, %s loops, setup %.0f ms\n",
                scene->name.c_str(), sim::solverName(scene->params.solver), double(scene->params.radius), s.size(), used,
                sim::vectorPath(), setupMs);
    std::printf("run         : %.3f s simulated in %.1f s wall: %.1f s wall per simulated second, %zu steps, mean dt "
                "%.3f ms, %.3f M particle-steps/s\n",
                T.simulatedS, wall, wall / T.simulatedS, T.steps, 1e3 * T.simulatedS / steps, double(T.particleSteps) / wall / 1e6);
    std::printf("iterations  : %.2f density, %.2f divergence (mean per step)\n", double(T.densityIterations) / steps,
                double(T.divergenceIterations) / steps);
    std::printf("neighbours  : %8.2f ms/step\n", T.msNeighbours / steps);
    std::printf("density     : %8.2f ms/step\n", T.msDensity / steps);
    std::printf("pressure    : %8.2f ms/step\n", T.msPressure / steps);
    std::printf("forces      : %8.2f ms/step\n", T.msForces / steps);
    std::printf("advection   : %8.2f ms/step\n", T.msAdvect / steps);
    if (T.simulatedS < 4.0 - 1e-9)
        std::printf("4 s         : %.0f s wall (extrapolated from %.2f s at this run's wall per simulated second)\n",
                    4.0 * wall / T.simulatedS, T.simulatedS);
    if (!peerLog.empty()) printPeer(peerLog);
    return 0;
}
