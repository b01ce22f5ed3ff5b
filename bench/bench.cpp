// bench: one line per stage with time (median of --repeat runs), size and
// thread count. Speed is measured here, never asserted in tests.
//   build/bench [INPUT] [--width 1280 --height 720 --repeat 9 --threads N --filter NAME --backend B]
// INPUT defaults to the real 117,649-particle dam-break frame in data/. The
// whole pipeline runs once per filter (all of them unless --filter is given)
// and per backend (cpu and gl by default); each stage line is the median over
// the repeats of that stage's own time -- wall clock on the CPU, GPU time from
// timer queries on GL -- with the CPU and GL lines of a stage side by side.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/params.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"

using namespace meniscus;

namespace {

double median(std::vector<double> ms) {
    std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
    return ms[ms.size() / 2];
}

double medianMs(int repeat, const std::function<void()>& fn) {
    std::vector<double> ms;
    for (int i = 0; i < repeat; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        fn();
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    return median(ms);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"bench: per-stage timings of the Meniscus pipeline (median of repeated runs)"};
    std::string input = MENISCUS_BENCH_INPUT;
    int width = defaults::kWidth, height = defaults::kHeight, repeat = 9, threads = 0;
    app.add_option("input", input, "Particle file")->capture_default_str();
    app.add_option("--width", width)->capture_default_str();
    app.add_option("--height", height)->capture_default_str();
    app.add_option("--repeat", repeat, "Runs per stage; the median is printed")->capture_default_str()->check(CLI::PositiveNumber);
    app.add_option("--threads", threads, "Worker threads (default: all cores)");
    std::vector<std::string> filters;
    bool separable = false;
    app.add_option("--filter", filters, "Smoothing filter(s) to time: " + filterNames() + " (default: all)");
    app.add_flag("--separable", separable, "narrow-range: time the separable 1-D approximation as well");
    bool allAovs = false;
    app.add_flag("--all-aovs", allAovs, "Read back every AOV (as for an EXR); default: the colour only (as for a PNG)");
    int thicknessDivisor = 1;
    app.add_option("--thickness-divisor", thicknessDivisor, "Thickness on a 1/n resolution grid: 1, 2 or 4")
        ->capture_default_str()
        ->check(CLI::IsMember({1, 2, 4}));
    std::string backendOpt = "both";
    app.add_option("--backend", backendOpt, "cpu, gl, auto, or both (cpu and gl side by side; gl skipped with a note when no context)")
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);

    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
    const int nThreads = int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));

    auto printOn = [&](const char* stage, const std::string& size, std::size_t particles, const std::string& where,
                       double ms) {
        std::printf("%-34s %-10s %9zu particles  %-6s %9.2f ms\n", stage, size.c_str(), particles, where.c_str(), ms);
    };
    const std::string cpuLabel = "cpu " + std::to_string(nThreads) + "t";
    auto print = [&](const char* stage, const std::string& size, std::size_t particles, double ms) {
        printOn(stage, size, particles, cpuLabel, ms);
    };
    const std::string res = std::to_string(width) + "x" + std::to_string(height);

    Result<ParticleSet> set = makeError(input, "not read");
    const double readMs = medianMs(std::max(1, repeat / 3), [&] { set = readParticles(input); });
    if (!set) {
        std::fprintf(stderr, "bench: error: %s\n", set.error().describe().c_str());
        return 1;
    }
    const std::size_t n = set->size();
    print("read", "-", n, readMs);

    RadiusEstimate radius;
    print("radius-estimate", "-", n, medianMs(repeat, [&] { radius = estimateRadius(set->positions); }));

    Camera base;
    base.width = width;
    base.height = height;
    RenderSettings settings;
    print("auto-camera", res, n, medianMs(repeat, [&] { settings.camera = autoFrameCamera(set->positions, radius.radius, base); }));
    settings.radiusM = radius.radius;

    // Each configuration: filter name, parameters.
    std::vector<std::pair<std::string, FilterParams>> configs;
    if (filters.empty()) filters = {"none", "gaussian", "bilateral", "binomial", "curvature-flow", "narrow-range"};
    for (const auto& name : filters) {
        FilterParams f;
        if (!filterFromName(name, &f)) {
            std::fprintf(stderr, "bench: error: --filter %s: expected one of %s\n", name.c_str(), filterNames().c_str());
            return 2;
        }
        configs.emplace_back(name + "(" + std::to_string(filterIterations(f)) + ")", f);
        if (name == "narrow-range" && (separable || filters.size() > 1)) {
            std::get<NarrowRangeParams>(f).separable = true;
            configs.emplace_back(name + "-1d(" + std::to_string(filterIterations(f)) + ")", f);
        }
    }

    // The scene layer depends only on camera and studio, so a Renderer casts it
    // once per sequence; its uncached cost is printed once here.
    {
        std::vector<double> ms;
        for (int i = 0; i < repeat; ++i) {
            std::vector<StageTime> times;
            settings.filter = NoFilter{};
            if (!renderFrame(set->positions, settings, &times)) return 1;
            ms.push_back(times.front().ms);
        }
        print("scene (uncached)", res, n, median(ms));
    }

    // The renderers, one per backend (each keeps its scene cast across runs).
    std::vector<std::pair<std::string, Renderer>> renderers;
    auto addRenderer = [&](BackendChoice choice) {
        std::string note;
        auto r = Renderer::create(choice, &note);
        if (!note.empty()) std::fprintf(stderr, "bench: %s\n", note.c_str());
        if (!r) {
            std::fprintf(stderr, "bench: %s; GL lines skipped\n", r.error().describe().c_str());
            return;
        }
        const std::string label = r->backendName() == "cpu" ? cpuLabel : "gl";
        if (label == "gl") std::fprintf(stderr, "bench: %s\n", r->backendName().c_str());
        renderers.emplace_back(label, std::move(*r));
    };
    if (backendOpt == "both") {
        addRenderer(BackendChoice::Cpu);
        addRenderer(BackendChoice::Gl);
    } else {
        BackendChoice choice;
        if (!backendFromName(backendOpt, &choice)) {
            std::fprintf(stderr, "bench: error: --backend %s: expected cpu, gl, auto or both\n", backendOpt.c_str());
            return 2;
        }
        addRenderer(choice);
    }
    if (renderers.empty()) return 1;

    for (const auto& [label, filter] : configs) {
        settings.filter = filter;
        settings.colorOnly = !allAovs;
        settings.thickness.resolutionDivisor = thicknessDivisor;
        // Per backend: stage -> run times, and the stage order.
        std::vector<std::map<std::string, std::vector<double>>> perStage(renderers.size());
        std::vector<std::string> order;
        std::vector<std::vector<double>> totals(renderers.size());
        for (std::size_t b = 0; b < renderers.size(); ++b) {
            for (int i = 0; i < repeat; ++i) {
                std::vector<StageTime> times;
                const auto t0 = std::chrono::steady_clock::now();
                auto aovs = renderers[b].second.render(set->positions, settings, &times);
                totals[b].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
                if (!aovs) {
                    std::fprintf(stderr, "bench: error: %s\n", aovs.error().describe().c_str());
                    return 1;
                }
                for (const auto& t : times) {
                    if (std::find(order.begin(), order.end(), t.stage) == order.end()) order.push_back(t.stage);
                    perStage[b][t.stage].push_back(t.ms);
                }
            }
        }
        for (const auto& stage : order) {
            const std::string name = stage == "smooth" ? "smooth " + label : stage == "scene" ? "scene (cached)" : stage;
            for (std::size_t b = 0; b < renderers.size(); ++b)
                if (perStage[b].count(stage)) printOn(name.c_str(), res, n, renderers[b].first, median(perStage[b][stage]));
        }
        // The stages alone (GL: rendered on the GPU, nothing copied back, as a
        // viewer or another GL renderer's timing), then the whole call.
        for (std::size_t b = 0; b < renderers.size(); ++b) {
            std::vector<double> sums(repeat, 0.0);
            for (const auto& [stage, runs] : perStage[b])
                if (stage != "readback")
                    for (std::size_t i = 0; i < runs.size() && i < sums.size(); ++i) sums[i] += runs[i];
            printOn(("pipeline stages (sum), " + label).c_str(), res, n, renderers[b].first, median(sums));
        }
        for (std::size_t b = 0; b < renderers.size(); ++b)
            printOn(("pipeline total (wall), " + label).c_str(), res, n, renderers[b].first, median(totals[b]));
    }
    return 0;
}
