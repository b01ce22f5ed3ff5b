#include "simulate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <vector>

#include <CLI/CLI.hpp>
#include <unistd.h>

#include "help_format.h"
#include "interrupt.h"
#include "meniscus/io.h"
#include "meniscus/particle_view.h"
#include "meniscus/renderer.h"
#include "progress.h"
#ifdef MENISCUS_HAVE_FFMPEG
#include "meniscus/video.h"
#endif

namespace meniscus::app {

namespace {

// --render: each frame written is also rendered, every one by the same camera
// (framed once on the domain: see fixForBox) into the same studio.
struct FrameImages {
    std::string pattern;
    RenderSettings settings;
    Renderer renderer;
#ifdef MENISCUS_HAVE_FFMPEG
    // --render out.mp4: every frame into one movie at the simulation's fps.
    std::optional<VideoWriter> movie;
#endif
};

// Everything --render needs, checked before anything is simulated: the
// pattern, the look, the camera and the backend.
Result<FrameImages> openImages(const SimulateJob& o, const sim::Scene& sc) {
    const bool movie = isMp4(o.render);
    if (!movie && o.render.find('%') == std::string::npos)
        return makeError(o.render, "--render needs a frame number pattern, e.g. out/img_%04d.png, or a movie, out.mp4");
    if (!movie && !isPng(o.render) && !isExr(o.render))
        return makeError(o.render, "--render images must end in .png or .exr, a movie in .mp4");
    if (movie && o.resume) return makeError(o.render, "--resume: a movie is written whole; render numbered images");
#ifndef MENISCUS_HAVE_FFMPEG
    if (movie)
        return makeError(o.render, "this build has no movies (FFmpeg's libraries were not found when it was "
                                   "configured); render numbered images (img_%04d.png)");
#endif
    if (!o.image.fluidAttribute.empty())
        return makeError("", "--fluid-attribute: the simulator's particles are one fluid");
    RenderJob look = o.image;
    look.radius = sc.params.radius;  // the simulation's particles, exactly
    auto settings = settingsFromOptions(look);
    if (!settings) return settings.error();
    if (auto st = fixForScene(look, sc, *settings); !st) return st.error();
    settings->colorOnly = !isExr(o.render);  // a PNG needs only the colour AOV
    auto renderer = makeRenderer(look);
    if (!renderer) return renderer.error();
    FrameImages images{o.render, std::move(*settings), std::move(*renderer)
#ifdef MENISCUS_HAVE_FFMPEG
                       , std::nullopt
#endif
    };
#ifdef MENISCUS_HAVE_FFMPEG
    if (movie) {
        if (auto st = prepareOutputFolder(o.render); !st) return st.error();  // a bad folder: exit 2
        const Camera& c = images.settings.camera;
        auto writer = VideoWriter::open(o.render, c.width, c.height, VideoParams{sc.fps, o.image.crf});
        if (!writer) return writer.error();
        images.movie.emplace(std::move(*writer));
    }
#endif
    return images;
}

// Frame k's image; returns its name.
Result<std::string> writeFrameImage(FrameImages& images, const ParticleSet& set, long k) {
    images.settings.frameIndex = k;  // the noise's turbulence compares consecutive frames
#ifdef MENISCUS_HAVE_FFMPEG
    if (images.movie) {
        auto aovs = images.renderer.render(ParticleView::of(set), images.settings);
        if (!aovs) return Error{images.pattern, aovs.error().message};
        if (auto st = images.movie->add(encodeSrgb8(aovs->color)); !st) return st.error();
        return images.pattern + " (frame " + std::to_string(images.movie->frames()) + ")";
    }
#endif
    auto name = formatFramePattern(images.pattern, k);
    if (!name) return name.error();
    auto aovs = images.renderer.render(ParticleView::of(set), images.settings);
    if (!aovs) return Error{*name, aovs.error().message};
    if (auto st = writeImage(*name, *aovs, !images.settings.scene.background); !st) return st.error();
    return *name;
}

// --resume with --render: the pictures of frames 0 .. last (whose particles
// were written) that are missing or cut short, rendered from the particle
// files. With the surface noise, whose turbulence compares consecutive
// frames, the frames before a missing one within the tracker's memory, and
// those before the first frame still to simulate, are drawn and dropped
// first, so each picture is the uninterrupted run's. Returns how many were
// written; stops early (with the count so far) when interrupted.
Result<long> renderMissingImages(FrameImages& images, const std::string& output, long last) {
    const long memory =
        images.settings.noise.enabled ? long(std::max(images.settings.noise.turbulence.holdFrames, 0)) + 1 : 0;
    std::vector<char> missing(std::size_t(last + 1), 0);
    for (long k = 0; k <= last; ++k) {
        auto name = formatFramePattern(images.pattern, k);
        if (!name) return name.error();
        missing[std::size_t(k)] = !imageComplete(*name);
    }
    long written = 0;
    for (long k = 0; k <= last && !interrupted(); ++k) {
        bool feeds = k > last - memory;  // the turbulence of the first frame simulated next
        for (long j = k + 1; j <= std::min(last, k + memory); ++j) feeds = feeds || missing[std::size_t(j)];
        if (!missing[std::size_t(k)] && !feeds) continue;
        auto particles = formatFramePattern(output, k);
        if (!particles) return particles.error();
        auto set = readParticles(*particles, ParticleFormat::Auto, true);  // an emitter's first frames are empty
        if (!set) return set.error();
        if (!missing[std::size_t(k)]) {  // drawn for the turbulence, not written
            images.settings.frameIndex = k;
            if (auto aovs = images.renderer.render(ParticleView::of(*set), images.settings); !aovs)
                return Error{*particles, aovs.error().message};
            continue;
        }
        auto image = writeFrameImage(images, *set, k);
        if (!image) return image.error();
        std::cerr << "meniscus: rendered the missing " << *image << " from " << *particles << "\n";
        ++written;
    }
    return written;
}

// The frames' times beside them, as a ParaView collection named after the
// pattern (out/fluid_%04d.vtu -> out/fluid.pvd): ParaView opens the run as one
// time series, and `render out/fluid.pvd -o movie.mp4` plays at the
// simulation's rate.
std::filesystem::path pvdBeside(const std::string& pattern) {
    const std::filesystem::path p(pattern);
    std::string stem = p.filename().string();
    stem = stem.substr(0, std::min(stem.find('%'), stem.find('.')));
    while (!stem.empty() && (stem.back() == '_' || stem.back() == '-' || stem.back() == ' ')) stem.pop_back();
    return p.parent_path() / ((stem.empty() ? std::string("frames") : stem) + ".pvd");
}

// The solver's checkpoint of the last frame written, hidden beside the frames
// and named as their .pvd (out/fluid_%04d.vtu -> out/.fluid.checkpoint): what
// --resume goes on from exactly (Simulator::saveCheckpoint).
std::filesystem::path checkpointBeside(const std::string& pattern) {
    const std::filesystem::path pvd = pvdBeside(pattern);
    return pvd.parent_path() / ("." + pvd.stem().string() + ".checkpoint");
}

// --resume: the checkpoint of a frame at most `last` loaded; its frame, or -1
// (said why) where there is none to use. A damaged or foreign checkpoint is
// not an error: the frames written are whole, and the run goes on from the
// last of them as a run without a checkpoint does (the same flow, not the
// same bits).
long resumeFromCheckpoint(sim::Simulator& simulator, const std::string& pattern, long last) {
    const std::filesystem::path path = checkpointBeside(pattern);
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
        std::cerr << "meniscus: no solver checkpoint " << path.string()
                  << ": resuming from the particle file (the same flow, not the same bits)\n";
        return -1;
    }
    auto frame = simulator.loadCheckpoint(path, last);
    if (!frame) {
        std::cerr << "meniscus: warning: " << frame.error().describe()
                  << "; resuming from the particle file (the same flow, not the same bits)\n";
        return -1;
    }
    return long(*frame);
}

}  // namespace

CLI::Option* addSolverOption(CLI::App* cmd, std::string& solver) {
    return addRow(cmd, *findIn(simulateOptionTable(), "solver"), &solver);
}

CLI::App* addSimulateCommand(CLI::App& app, SimulateJob& o) {
    auto* cmd = app.add_subcommand(
        "simulate",
        "Simulate a scene file (scenes/*.json; every field in docs/scenes.md) with the built-in SPH solver "
        "(DFSPH by default) and write a numbered particle sequence with id, velocity (m/s), density (kg/m^3) and "
        "pressure (Pa): frame k holds the particles at t = k / fps. The same frames for the same --threads");
    cmd->add_option("scene", o.scene, "Scene file (.json)")
        ->group(group::kInput)
        ->required();
    cmd->add_option("-o,--output", o.output,
                    "Output pattern with a frame number: out/frame_%04d.bgeo (.bgeo, .bgeo.gz, .vtk, .vtu or .ply)")
        ->group(group::kOutput)
        ->required();
    addRows(cmd, simulateOptionTable(), o);
    // The look of those images: the render command's own options and defaults,
    // in render's groups marked "(with --render)".
    const std::size_t imageOptions = cmd->get_options().size();
    addCameraOptions(cmd, o.image, false);
    o.image.backend = "cpu";  // the reference, on any machine; gl on request
    addBackendOption(cmd, o.image);
    const std::string withRender = " (with --render)";
    suffixGroups(cmd, imageOptions, withRender);
    HelpLayout layout = renderHelpLayout();
    layout.groups = {group::kInput, group::kSimulation, group::kOutput, group::kPerformance};
    for (const std::string& g : renderHelpLayout().groups)
        if (g != group::kInput && g != group::kMovie && g != group::kCluster) layout.groups.push_back(g + withRender);
    useGroupedHelp(cmd, std::move(layout));
    return cmd;
}

Result<sim::Scene> sceneFromOptions(const SimulateJob& o) {
    auto scene = sim::readScene(o.scene);
    if (!scene) return scene.error();
    if (auto st = applySimulateOptions(o, *scene); !st) return st.error();
    return scene;
}

Bounds domainBounds(const sim::Scene& scene) {
    Bounds b;
    b.min = scene.domain.min;
    b.max = scene.domain.max;
    return b;
}

int runSimulate(const SimulateJob& o) {
    if (auto up = upRotation(o.image.up); !up || !up->identity)
        return failUsage("--up " + vec3Text(o.image.up) + ": the simulator's up is +y (gravity along -y); --up turns files for render");
    auto scene = sceneFromOptions(o);
    if (!scene) return fail(scene.error());
    sim::Scene& sc = *scene;
    if (o.output.find('%') == std::string::npos)
        return fail(o.output + ": the output needs a frame number pattern, e.g. out/frame_%04d.bgeo");
    auto format = writableFormatOf(o.output);
    if (!format) return fail(format.error());
    std::optional<FrameImages> images;
    if (!o.render.empty()) {
        auto opened = openImages(o, sc);
        if (!opened) return fail(opened.error());
        images.emplace(std::move(*opened));
        const Camera& c = images->settings.camera;
        std::fprintf(stderr,
                     "meniscus: rendering each frame to %s on %s, %d x %d, one camera for all: eye (%g, %g, %g) "
                     "target (%g, %g, %g)\n",
                     o.render.c_str(), images->renderer.backendName().c_str(), c.width, c.height, c.eye.x, c.eye.y,
                     c.eye.z, c.target.x, c.target.y, c.target.z);
    }

    // The outputs' folders, checked (and a killed run's temporaries swept) before anything is simulated.
    for (const std::string* pattern : {&o.output, &o.render})
        if (!pattern->empty())
            if (auto st = prepareOutputFolder(*pattern); !st) return fail(st.error());

    auto made = sim::Simulator::create(sc);
    if (!made) return fail(made.error());
    sim::Simulator& simulator = **made;
    installInterruptHandler("frame");  // from here on Ctrl-C stops between the simulator's steps
    const long frames = long(std::floor(sc.duration * sc.fps + 1e-9));  // after frame 0
    auto nameOf = [&](long k) { return formatFramePattern(o.output, k); };

    long first = 0;
    if (o.resume) {
        // The last frame already there (0, 1, ... without a gap).
        long last = -1;
        for (long k = 0; k <= frames; ++k) {
            auto name = nameOf(k);
            if (!name) return fail(name.error());
            if (!std::filesystem::exists(*name)) break;
            last = k;
        }
        // The solver's checkpoint, exact; frames after its own are simulated again (the same bytes).
        const long exact = last >= 0 ? resumeFromCheckpoint(simulator, o.output, last) : -1;
        if (exact >= 0) {
            last = exact;
            std::cerr << "meniscus: resuming exactly after frame " << last << " from the solver's checkpoint (t = "
                      << simulator.time() << " s)\n";
            first = last + 1;
        } else if (last >= 0) {
            auto name = nameOf(last);
            auto set = readParticles(*name, ParticleFormat::Auto, true);  // an emitter's first frames are empty
            if (!set) return fail(set.error());
            if (auto st = simulator.restore(*set, double(last) / sc.fps); !st)
                return fail(Error{*name, st.error().message}.describe());
            std::cerr << "meniscus: resuming after " << *name << " (t = " << double(last) / sc.fps << " s)\n";
            first = last + 1;
        }
        // The pictures an interrupted run had not rendered yet for the frames it wrote.
        if (images && last >= 0) {
            auto rendered = renderMissingImages(*images, o.output, last);
            if (!rendered) return fail(rendered.error());
        }
    }
    // Where the run stopped and how to go on (Ctrl-C, SIGTERM).
    const auto stopped = [&](long k) {
        const std::string then = images && isMp4(o.render)
                                     ? "no movie written (a movie is written whole: run it again)"
                                     : "the frames written are whole: the same command with --resume goes on";
        if (k == 0) return stopInterrupted("before frame 0", then);
        auto name = nameOf(k - 1);
        char time[32];
        std::snprintf(time, sizeof time, "%g", double(k - 1) / sc.fps);
        return stopInterrupted("after frame " + std::to_string(k - 1) + " (" + (name ? *name : o.output) + ", t = " +
                                   time + " s); frame " + std::to_string(k) + ", in progress, is not written",
                               then);
    };
    if (interrupted()) return stopped(first);
    std::cerr << "meniscus: " << sc.name << ": " << simulator.size() << " particles, r = " << sc.params.radius
              << " m, " << sim::solverName(sc.params.solver) << ", " << sc.duration << " s at " << sc.fps << " fps\n";
    const bool tty = ::isatty(STDERR_FILENO) == 1;
    ProgressBar progress(std::size_t(frames + 1), "simulating");
    const auto start = std::chrono::steady_clock::now();
    for (long k = first; k <= frames; ++k) {
        const std::size_t stepsBefore = simulator.totals().steps;
        // Step by step, so a signal stops the run between two steps: the frame
        // in progress is dropped whole (--resume simulates it again).
        const double t = double(k) / sc.fps;
        while (simulator.time() < t) {
            if (interrupted()) return stopped(k);
            if (auto st = simulator.step(t); !st) return fail(st.error());
        }
        auto name = nameOf(k);
        if (!name) return fail(name.error());
        const ParticleSet set = simulator.particles();
        if (auto st = writeParticles(*name, set, *format); !st) return fail(st.error());
        if (auto st = simulator.saveCheckpoint(checkpointBeside(o.output), k); !st) return fail(st.error());
        std::string imageNote;
        if (images) {
            auto image = writeFrameImage(*images, set, k);
            if (!image) return fail(image.error());
            imageNote = " and " + *image;
        }
        const sim::Totals& T = simulator.totals();
        if (o.stats) {
            const double steps = double(std::max<std::size_t>(T.steps, 1));
            std::fprintf(stderr,
                         "meniscus: t = %.3f s: %zu steps (%zu this frame), mean iterations %.2f density / %.2f "
                         "divergence, per step: neighbours %.2f ms, density %.2f ms, pressure %.2f ms, forces %.2f "
                         "ms, advect %.2f ms\n",
                         simulator.time(), T.steps, T.steps - stepsBefore, double(T.densityIterations) / steps,
                         double(T.divergenceIterations) / steps, T.msNeighbours / steps, T.msDensity / steps,
                         T.msPressure / steps, T.msForces / steps, T.msAdvect / steps);
        }
        if (tty) progress.update(std::size_t(k + 1));
        else
            std::cerr << "meniscus: wrote " << *name << imageNote << " (t = " << simulator.time() << " s, " << simulator.size()
                      << " particles, " << T.steps << " steps)\n";
    }
#ifdef MENISCUS_HAVE_FFMPEG
    if (images && images->movie) {
        if (auto st = images->movie->finish(); !st) return fail(st.error());
        std::cerr << "meniscus: wrote " << o.render << " (" << images->movie->frames() << " frames, H.264, " << sc.fps
                  << " fps)\n";
    }
#endif
    std::vector<std::filesystem::path> written;
    std::vector<double> times;
    for (long k = 0; k <= frames; ++k) {
        auto name = nameOf(k);
        if (!name) return fail(name.error());
        written.emplace_back(*name);
        times.push_back(double(k) / sc.fps);
    }
    const std::filesystem::path pvd = pvdBeside(o.output);
    if (auto st = writePvd(pvd, written, times); !st) return fail(st.error());
    std::cerr << "meniscus: wrote " << pvd.string() << " (the frames' times, " << sc.fps
              << " fps: a time series for ParaView, and render's movie rate)\n";
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cerr << "meniscus: simulated " << simulator.time() << " s in " << wall << " s wall ("
              << simulator.totals().steps << " steps)\n";
    return 0;
}

}  // namespace meniscus::app
