// bench: one line per stage with time (median of --repeat runs), size and
// thread count. Speed is measured here, never asserted in tests.
//   build/bench [INPUT] [--width 1280 --height 720 --repeat 9 --threads N --filter NAME --backend B]
//               [--mesh-only | --no-mesh] [--openvdb PATH] [--movie N]
// INPUT defaults to the real 117,649-particle dam-break frame in data/. The
// whole pipeline runs once per filter (all of them unless --filter is given)
// and per backend (cpu and gl by default); each stage line is the median over
// the repeats of that stage's own time -- wall clock on the CPU, GPU time from
// timer queries on GL -- with the CPU and GL lines of a stage side by side.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include "meniscus/camera.h"
#include "meniscus/geometry.h"
#include "meniscus/options.h"
#include "meniscus/io.h"
#include "meniscus/params.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "meniscus/surface.h"
#ifdef MENISCUS_HAVE_FFMPEG
#include "meniscus/video.h"
#endif

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

// A wavy ground of about `triangles` triangles, twice the particles' width,
// just under them (--geometry-triangles).
GeometryObject groundGrid(const std::vector<glm::vec3>& points, long triangles) {
    Bounds box;
    for (const glm::vec3& p : points) box.extend(p);
    const glm::vec3 c = box.center(), e = glm::max(box.extent(), glm::vec3(1e-3f));
    const int side = std::max(1, int(std::sqrt(double(triangles) / 2.0)));
    const float w = 2.0f * std::max(e.x, e.z), step = w / float(side), amp = 0.01f * w;
    GeometryObject g;
    g.name = "ground";
    TriangleMesh& m = g.mesh;
    for (int j = 0; j <= side; ++j)
        for (int i = 0; i <= side; ++i) {
            const float x = c.x - 0.5f * w + float(i) * step, z = c.z - 0.5f * w + float(j) * step;
            const float kx = 12.0f / w, kz = 9.0f / w;
            const float y = box.min.y - amp * (1.0f + std::sin(kx * x) * std::cos(kz * z));
            m.positions.push_back({x, y, z});
            const float dx = -amp * kx * std::cos(kx * x) * std::cos(kz * z);
            const float dz = amp * kz * std::sin(kx * x) * std::sin(kz * z);
            m.normals.push_back(glm::normalize(glm::vec3(-dx, 1.0f, -dz)));
        }
    for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i) {
            const std::uint32_t a = std::uint32_t(j * (side + 1) + i), b = a + 1, d = a + std::uint32_t(side + 1),
                                e2 = d + 1;
            m.indices.insert(m.indices.end(), {a, d, b, b, d, e2});
        }
    return g;
}

// The isosurface path's phases (median of `repeat` extractions), then the
// OpenVDB peer (a small program outside this repository, built by
// scripts/build_openvdb_peer.sh: ParticlesToLevelSet + volumeToMesh)
// on the same particles at the same voxel size, in the same run.
int benchMesh(const ParticleSet& set, float radius, int repeat, int nThreads, const std::string& openvdb) {
    const std::size_t n = set.size();
    for (SurfaceField field : {SurfaceField::Sph, SurfaceField::Thesis}) {
        MeshParams p;
        p.radiusM = radius;
        p.field = field;
        std::vector<MeshStats> runs;
        TriangleMesh mesh;
        for (int i = 0; i < repeat; ++i) {
            MeshStats st;
            auto m = extractSurface(ParticleView::of(set), p, &st);
            if (!m) {
                std::fprintf(stderr, "bench: error: %s\n", m.error().describe().c_str());
                return 1;
            }
            mesh = std::move(*m);
            runs.push_back(st);
        }
        auto med = [&](double MeshStats::*field) {
            std::vector<double> v;
            for (const auto& r : runs) v.push_back(r.*field);
            return median(v);
        };
        const MeshStats& s = runs.front();
        const std::string tag = std::string("mesh ") + surfaceFieldName(field) + " ";
        char size[64];
        std::snprintf(size, sizeof size, "cube %.2gr", double(p.cubeSizeRadii));
        const std::string where = "cpu " + std::to_string(nThreads) + "t";
        auto line = [&](const std::string& phase, double ms) {
            std::printf("%-34s %-10s %9zu particles  %-6s %9.2f ms\n", (tag + phase).c_str(), size, n, where.c_str(), ms);
        };
        line("blocks", med(&MeshStats::msBlocks));
        line("extract (marching slices)", med(&MeshStats::msExtract));
        line("weld and normals", med(&MeshStats::msMerge));
        const double total = med(&MeshStats::msTotal);
        line("total", total);
        std::printf("%-34s %zu triangles, %zu vertices, %.2f M particles/s, peak %.1f MB (one block %.2f MB), "
                    "%zu blocks (%zu with surface), %zu rounds (%zu block reruns), %zu cubes, %zu corners, lookup cache %zu rows %zu entries, %d threads\n",
                    (tag + "size").c_str(), mesh.triangleCount(), mesh.vertexCount(), double(n) / total / 1e3,
                    double(s.peakBytes) / 1e6, double(s.peakBlockBytes) / 1e6, s.blocks, s.blocksWithSurface,
                    s.rounds, s.blocksRerun, s.cubesVisited, s.cornersEvaluated, s.cacheRows, s.cacheEntries, s.threads);
    }
    if (openvdb.empty()) {
        std::printf("%-34s (not run: pass --openvdb PATH, built by scripts/build_openvdb_peer.sh)\n", "openvdb peer");
        return 0;
    }
    // The peer reads raw particles: uint64 count, then float32 xyz.
    const auto raw = std::filesystem::temp_directory_path() / ("meniscus_bench_" + std::to_string(::getpid()) + ".bin");
    {
        std::FILE* f = std::fopen(raw.c_str(), "wb");
        if (!f) return 1;
        const std::uint64_t count = n;
        std::fwrite(&count, 8, 1, f);
        std::fwrite(set.positions.data(), sizeof(glm::vec3), n, f);
        std::fclose(f);
    }
    char cmd[1024];
    std::snprintf(cmd, sizeof cmd, "'%s' '%s' %.9g %.9g 2>&1", openvdb.c_str(), raw.c_str(),
                  double(defaults::kCubeSizeRadii * radius), double(2.0f * radius));
    std::vector<double> totals, levelsets, meshes;
    std::string last;
    for (int i = 0; i < repeat; ++i) {
        std::FILE* pipe = ::popen(cmd, "r");
        if (!pipe) break;
        char buf[512];
        std::string out;
        while (std::fgets(buf, sizeof buf, pipe)) out += buf;
        ::pclose(pipe);
        double ls = 0, sm = 0, me = 0, to = 0;
        const auto at = out.find("levelset_ms=");
        if (at == std::string::npos ||
            std::sscanf(out.c_str() + at, "levelset_ms=%lf smooth_ms=%lf mesh_ms=%lf total_ms=%lf", &ls, &sm, &me, &to) != 4) {
            std::fprintf(stderr, "bench: the OpenVDB peer said: %s\n", out.c_str());
            break;
        }
        levelsets.push_back(ls);
        meshes.push_back(me);
        totals.push_back(to);
        last = out.substr(0, out.find('\n'));
    }
    std::filesystem::remove(raw);
    if (totals.empty()) return 1;
    char size[64];
    std::snprintf(size, sizeof size, "voxel %.2gr", double(defaults::kCubeSizeRadii));
    auto line = [&](const char* phase, double ms) {
        std::printf("%-34s %-10s %9zu particles  %-6s %9.2f ms\n", phase, size, n, "peer", ms);
    };
    line("openvdb ParticlesToLevelSet", median(levelsets));
    line("openvdb volumeToMesh", median(meshes));
    line("openvdb total", median(totals));
    std::printf("%-34s %s\n", "openvdb size", last.c_str());
    return 0;
}

// The input repeated on an n x n grid in x and z, each copy shifted by the
// set's extent plus `gap` metres, for a bigger scene made of real frames
// (--tile 3 turns the 117,649-particle frame 21 into 1,058,841 particles).
// Attributes are repeated with their particles; ids are shifted so that
// every copy's are its own.
ParticleSet tiled(const ParticleSet& in, int n, float gap) {
    Bounds box;
    for (const glm::vec3& p : in.positions) box.extend(p);
    const glm::vec3 step = box.max - box.min + glm::vec3(gap);
    ParticleSet out;
    out.positions.reserve(in.positions.size() * std::size_t(n * n));
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < n; ++k)
            for (const glm::vec3& p : in.positions) out.positions.push_back(p + glm::vec3(float(i) * step.x, 0.0f, float(k) * step.z));
    for (const Attribute& a : in.attributes) {
        Attribute t = a;
        t.floats.clear();
        t.ints.clear();
        std::int64_t idSpan = 1;
        for (std::int64_t v : a.ints) idSpan = std::max(idSpan, v + 1);
        for (int c = 0; c < n * n; ++c) {
            t.floats.insert(t.floats.end(), a.floats.begin(), a.floats.end());
            for (std::int64_t v : a.ints) t.ints.push_back(a.name == kAttrId ? v + std::int64_t(c) * idSpan : v);
        }
        out.attributes.push_back(std::move(t));
    }
    return out;
}

#ifdef MENISCUS_HAVE_FFMPEG
// --movie N: a movie of N frames made as `meniscus render -o out.mp4` makes
// one: each frame read from the input file (a sequence's reading: the same
// file N times), rendered, converted to 8-bit sRGB and encoded by
// VideoWriter (x264, its settings) into a temporary MP4, removed at the end.
// First one phase after another, each timed; then overlapped as the CLI
// overlaps them (render.cpp: frame k + 1 read and frame k - 1 converted and
// encoded on workers while frame k renders). One line per phase, its mean per
// frame in wall time and in the process's CPU time (the encoder's drain at the
// end counted in "encode"), then the wall time per frame and the frames per
// second of both runs.
int benchMovie(const std::string& input, Renderer& renderer, const RenderSettings& settings, int frames,
               const std::string& res, const std::string& where) {
    using Clock = std::chrono::steady_clock;
    const auto ms = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
    };
    const std::filesystem::path out =
        std::filesystem::temp_directory_path() / ("meniscus_bench_movie_" + std::to_string(::getpid()) + ".mp4");
    const auto check = [](const Status& st) {
        if (!st) std::fprintf(stderr, "bench: error: %s\n", st.error().describe().c_str());
        return bool(st);
    };
    const auto open = [&]() { return VideoWriter::open(out, settings.camera.width, settings.camera.height); };
    std::size_t n = 0;

    // The process's CPU time (every thread's), in ms: on a machine shared with
    // other work a phase's wall time is whatever the scheduler gives it, its
    // CPU time is its own.
    const auto cpuMs = [] {
        timespec t{};
        ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
        return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
    };
    // One after another.
    double readMs = 0, renderMs = 0, readbackMs = 0, srgbMs = 0, encodeMs = 0;
    double readCpu = 0, renderCpu = 0, srgbCpu = 0, encodeCpu = 0;
    auto movie = open();
    if (!check(movie ? okStatus() : Status(movie.error()))) return 1;
    const auto s0 = Clock::now();
    const double sequentialCpu0 = cpuMs();
    for (int k = 0; k < frames; ++k) {
        const double c0 = cpuMs();
        const auto t0 = Clock::now();
        auto set = readParticles(input);
        const auto t1 = Clock::now();
        const double c1 = cpuMs();
        if (!check(set ? okStatus() : Status(set.error()))) return 1;
        n = set->size();
        std::vector<StageTime> times;
        auto aovs = renderer.render(ParticleView::of(*set), settings, &times);
        const auto t2 = Clock::now();
        const double c2 = cpuMs();
        if (!check(aovs ? okStatus() : Status(aovs.error()))) return 1;
        double readback = 0;
        for (const StageTime& t : times)
            if (t.stage == "readback") readback += t.ms;
        const Image<glm::u8vec4> srgb = encodeSrgb8(aovs->color);
        const auto t3 = Clock::now();
        const double c3 = cpuMs();
        if (!check(movie->add(srgb))) return 1;
        const auto t4 = Clock::now();
        readCpu += c1 - c0;
        renderCpu += c2 - c1;
        srgbCpu += c3 - c2;
        encodeCpu += cpuMs() - c3;
        readMs += ms(t0, t1);
        renderMs += ms(t1, t2) - readback;
        readbackMs += readback;
        srgbMs += ms(t2, t3);
        encodeMs += ms(t3, t4);
    }
    const auto f0 = Clock::now();
    if (!check(movie->finish())) return 1;
    const auto s1 = Clock::now();
    encodeMs += ms(f0, s1);
    const double sequentialMs = ms(s0, s1), sequentialCpu = cpuMs() - sequentialCpu0;
    // (x264 encodes on its own threads too: what they do after add() returns
    // is counted in the phase that runs meanwhile; the total is exact.)

    // Overlapped.
    movie = open();
    if (!check(movie ? okStatus() : Status(movie.error()))) return 1;
    const auto o0 = Clock::now();
    const double overlappedCpu0 = cpuMs();
    std::future<Result<ParticleSet>> reading = std::async(std::launch::async, [&] { return readParticles(input); });
    std::future<Status> writing;
    for (int k = 0; k < frames; ++k) {
        auto set = reading.get();
        if (!check(set ? okStatus() : Status(set.error()))) return 1;
        if (k + 1 < frames) reading = std::async(std::launch::async, [&] { return readParticles(input); });
        auto aovs = renderer.render(ParticleView::of(*set), settings);
        if (!check(aovs ? okStatus() : Status(aovs.error()))) return 1;
        if (writing.valid() && !check(writing.get())) return 1;
        writing = std::async(std::launch::async, [&movie, a = std::move(*aovs)] { return movie->add(encodeSrgb8(a.color)); });
    }
    if (writing.valid() && !check(writing.get())) return 1;
    if (!check(movie->finish())) return 1;
    const double overlappedMs = ms(o0, Clock::now()), overlappedCpu = cpuMs() - overlappedCpu0;
    std::error_code ec;
    std::filesystem::remove(out, ec);

    const auto line = [&](const char* phase, double total, double cpu) {
        std::printf("%-34s %-10s %9zu particles  %-6s %9.2f ms", phase, res.c_str(), n, where.c_str(), total / frames);
        if (cpu >= 0) std::printf("  (CPU %.2f ms)", cpu / frames);
        std::printf("\n");
    };
    line("movie read", readMs, readCpu);
    line("movie render", renderMs, renderCpu);
    line("movie readback", readbackMs, -1);
    line("movie 8-bit sRGB", srgbMs, srgbCpu);
    line("movie encode (H.264)", encodeMs, encodeCpu);
    line("movie sequential (wall)", sequentialMs, sequentialCpu);
    line("movie overlapped (wall)", overlappedMs, overlappedCpu);
    std::printf("movie: %d frames, %.2f frames/s one after another, %.2f frames/s overlapped\n", frames,
                1000.0 * frames / sequentialMs, 1000.0 * frames / overlappedMs);
    return 0;
}
#endif

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
    int iterations = -1;
    app.add_option("--iterations", iterations, "Filter iterations (default: each filter's own)");
    bool allAovs = false;
    app.add_flag("--all-aovs", allAovs, "Read back every AOV (as for an EXR); default: the colour only (as for a PNG)");
    int thicknessDivisor = 1;
    app.add_option("--thickness-divisor", thicknessDivisor, "Thickness on a 1/n resolution grid: 1, 2 or 4")
        ->capture_default_str()
        ->check(CLI::IsMember({1, 2, 4}));
    std::string backendOpt = "both";
    app.add_option("--backend", backendOpt, "cpu, gl, auto, or both (cpu and gl side by side; gl skipped with a note when no context)")
        ->capture_default_str();
    bool meshOnly = false, noMesh = false, noise = false, whiten = false, spray = false, silhouette = false;
    std::string openvdb;
    float benchRadius = 0.0f;
    int tile = 1;
    float fluidScale = 1.0f;
    app.add_option("--fluid-scale", fluidScale,
                   "Reduced-resolution processing: splat, smoothing, normals and noise at 1, 0.5 or 0.25 of the "
                   "width and height (adds the reduce-scene-depth, upsample and fluid-edges lines)")
        ->capture_default_str()
        ->check(CLI::IsMember({1.0f, 0.5f, 0.25f}));
    int fluids = 1;
    app.add_option("--fluids", fluids,
                   "Several fluids: split the particles by x into N equal slabs of the frame's x range, fluid 0 to "
                   "N-1, each drawn with its own material (water, lava, milk, murky) and composited (per-fluid lines "
                   "and composite-fluids)")
        ->capture_default_str()
        ->check(CLI::Range(1, kMaxFluids));
    app.add_option("--tile", tile,
                   "Repeat the input on an N x N grid in x and z (a bigger scene from a real frame: --tile 3 makes "
                   "frame 21 1,058,841 particles); the radius is estimated on the input itself")
        ->capture_default_str()
        ->check(CLI::Range(1, 16));
    app.add_option("--radius", benchRadius, "Particle radius in metres (default: estimated)");
    app.add_flag("--mesh-only", meshOnly, "Time only the isosurface path (and its peer)");
    app.add_flag("--no-mesh", noMesh, "Skip the isosurface path");
    app.add_flag("--noise", noise, "Also run the surface-noise stage (and foam in the shading), seeded by the file's ids");
    app.add_flag("--silhouette", silhouette, "Also run the silhouette reduction stage (Instant Liquids' silhouette map)");
    std::string anisotropy = AnisotropyParams{}.enabled ? "on" : "off";
    app.add_option("--anisotropy", anisotropy,
                   "Anisotropic kernels (Yu & Turk 2013), on or off: the anisotropy line (the host's on the CPU "
                   "backend, the GPU's passes on GL, whose host part is the 'host: anisotropy' line) and the "
                   "ellipsoid splat")
        ->capture_default_str()
        ->check(CLI::IsMember({"on", "off"}));
    bool raycast = false;
    app.add_flag("--raycast", raycast,
                 "The ray-cast SPH surface (--surface raycast) in place of the smoothing and normals: the sph-field "
                 "line (host, both backends) and the raycast stage");
    app.add_flag("--spray", spray,
                 "Also split off the spray (density below half the median, estimated from neighbours) and run the "
                 "spray-drop stage (the split's time is part of the frame's own)");
    app.add_flag("--whiten", whiten,
                 "Also run the velocity whitening stage (and white water in the shading), from the file's velocities");
    std::vector<std::string> geometry;
    app.add_option("--geometry", geometry,
                   "Scene geometry drawn around the liquid (as render's --geometry: a mesh file, a SPlisHSPlasH "
                   "scene, JSON objects); the geometry stage's line times it");
    long groundTriangles = 0;
    app.add_option("--geometry-triangles", groundTriangles,
                   "Also a generated ground of about this many triangles (a wavy grid twice the particles' width "
                   "under them): the geometry stage's cost per triangle")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--openvdb", openvdb,
                   "The OpenVDB peer binary (scripts/build_openvdb_peer.sh builds build/openvdb_mesh), run on the same "
                   "frame at the same voxel size");
    int movie = 0;
    app.add_option("--movie", movie,
                   "Time a movie of N frames instead (the input read N times, rendered with the first --filter, "
                   "converted to 8 bits and encoded to H.264): each phase, then the frames/s of wall one after "
                   "another and overlapped as `meniscus render -o out.mp4` does")
        ->check(CLI::NonNegativeNumber);
    CLI11_PARSE(app, argc, argv);
#ifndef MENISCUS_HAVE_FFMPEG
    if (movie > 0) {
        std::fprintf(stderr, "bench: error: --movie: this build has no movies (FFmpeg was not found)\n");
        return 2;
    }
#endif
    if (movie > 0 && (tile > 1 || fluids > 1)) {
        std::fprintf(stderr, "bench: error: --movie renders the input as read: leave out --tile and --fluids\n");
        return 2;
    }

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
    std::size_t n = set->size();
    print("read", "-", n, readMs);

    RadiusEstimate radius;
    print("radius-estimate", "-", n, medianMs(repeat, [&] { radius = estimateRadius(set->positions); }));
    if (benchRadius > 0.0f) radius.radius = benchRadius;
    if (tile > 1) {
        set = tiled(*set, tile, 8.0f * radius.radius);
        n = set->size();
        std::printf("%-34s %-10s %9zu particles\n", ("tile " + std::to_string(tile) + "x" + std::to_string(tile)).c_str(), "-", n);
    }

    if (!noMesh && movie == 0) {
        if (int rc = benchMesh(*set, radius.radius, std::max(1, repeat / 3), nThreads, openvdb); rc != 0) return rc;
        if (meshOnly) return 0;
    }

    // --fluids: the index by x, replacing any `fluid` attribute of the file.
    if (fluids > 1) {
        Bounds box;
        for (const glm::vec3& p : set->positions) box.extend(p);
        Attribute index;
        index.name = std::string(kAttrFluid);
        index.type = AttributeType::Int;
        for (const glm::vec3& p : set->positions)
            index.ints.push_back(std::min<std::int64_t>(
                fluids - 1, std::int64_t(float(fluids) * (p.x - box.min.x) / std::max(box.max.x - box.min.x, 1e-30f))));
        std::erase_if(set->attributes, [](const Attribute& a) { return a.name == kAttrFluid; });
        set->attributes.push_back(std::move(index));
    }

    Camera base;
    base.width = width;
    base.height = height;
    RenderSettings settings;
    print("auto-camera", res, n, medianMs(repeat, [&] { settings.camera = autoFrameCamera(set->positions, radius.radius, base); }));
    settings.radiusM = radius.radius;
    if (!geometry.empty()) {
        auto g = renderGeometry(geometry, {0.0f, 1.0f, 0.0f});
        if (!g) {
            std::fprintf(stderr, "bench: error: %s\n", g.error().describe().c_str());
            return 2;
        }
        settings.geometry = *g;
    }
    if (groundTriangles > 0) {
        SceneGeometry more = settings.geometry ? *settings.geometry : SceneGeometry{};
        more.objects.push_back(groundGrid(set->positions, groundTriangles));
        settings.geometry = std::make_shared<SceneGeometry>(std::move(more));
    }
    if (settings.geometry)
        std::printf("%-34s %-10s %9zu triangles\n", "geometry", "-", settings.geometry->triangleCount());

    // Each configuration: filter name, parameters.
    std::vector<std::pair<std::string, FilterParams>> configs;
    // The ray cast takes the filters' place: one configuration, named for it.
    if (raycast) filters = {"none"};
    if (filters.empty()) filters = {"none", "gaussian", "bilateral", "binomial", "curvature-flow", "narrow-range"};
    for (const auto& name : filters) {
        FilterParams f;
        if (!filterFromName(name, &f)) {
            std::fprintf(stderr, "bench: error: --filter %s: expected one of %s\n", name.c_str(), filterNames().c_str());
            return 2;
        }
        if (iterations >= 0) setFilterIterations(f, iterations);
        configs.emplace_back(raycast ? std::string("raycast") : name + "(" + std::to_string(filterIterations(f)) + ")", f);
        if (raycast) break;
        if (name == "narrow-range" && (separable || filters.size() > 1)) {
            std::get<NarrowRangeParams>(f).separable = true;
            configs.emplace_back(name + "-1d(" + std::to_string(filterIterations(f)) + ")", f);
        }
    }

    // The scene layer depends only on camera and studio, so a Renderer casts it
    // once per sequence; its uncached cost is printed once here.
    // So is the geometry drawn over it. A moving camera pays both every
    // frame: one CPU Renderer, its camera moved a hair between runs (its
    // images reused, as in a movie with a moving camera).
    if (movie == 0) {
        std::map<std::string, std::vector<double>> ms;
        Renderer moving;
        RenderSettings nudged = settings;
        nudged.filter = NoFilter{};
        for (int i = 0; i <= repeat; ++i) {
            std::vector<StageTime> times;
            nudged.camera.eye.x = settings.camera.eye.x + 1e-4f * float(i % 2 == 0 ? 1 : -1);
            if (!moving.render(ParticleView::of(*set), nudged, &times)) return 1;
            if (i == 0) continue;  // the first run allocates the images
            for (const StageTime& t : times)
                if (t.stage == "scene" || t.stage == "geometry") ms[t.stage].push_back(t.ms);
        }
        for (const auto& [stage, runs] : ms) print((stage + " (moving camera)").c_str(), res, n, median(runs));
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
        settings.noise.enabled = noise;
        settings.whitening.enabled = whiten;
        settings.spray.enabled = spray;
        settings.silhouette.enabled = silhouette;
        settings.anisotropy.enabled = anisotropy == "on";
        settings.raycast.enabled = raycast;
        settings.fluidScale = fluidScale;
        settings.fluidMaterials.clear();
        for (const char* m : {"water", "lava", "milk", "murky"}) {
            if (int(settings.fluidMaterials.size()) == fluids) break;
            settings.fluidMaterials.emplace_back();
            materialPreset(m, &settings.fluidMaterials.back());
        }
#ifdef MENISCUS_HAVE_FFMPEG
        if (movie > 0) return benchMovie(input, renderers.front().second, settings, movie, res, renderers.front().first);
#endif
        // Per backend: stage -> run times, and the stage order.
        std::vector<std::map<std::string, std::vector<double>>> perStage(renderers.size());
        std::vector<std::string> order;
        std::vector<std::vector<double>> totals(renderers.size());
        for (std::size_t b = 0; b < renderers.size(); ++b) {
            for (int i = 0; i < repeat; ++i) {
                std::vector<StageTime> times;
                const auto t0 = std::chrono::steady_clock::now();
                auto aovs = renderers[b].second.render(ParticleView::of(*set), settings, &times);
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
            const std::string name = stage == "smooth" ? "smooth " + label : stage == "scene"      ? "scene (still camera)"
                                    : stage == "geometry" ? "geometry (still camera)"
                                                          : stage;
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
