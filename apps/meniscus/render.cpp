// `meniscus render`: frames in order through one Renderer into numbered images
// or one movie. Choices where the docs are silent:
//  - --on-error skip: a frame that cannot be read, rendered or written is
//    listed and left out (of a movie too); the run goes on, says which frames
//    failed and why at the end, and exits 1. The default, stop, ends at the
//    first error as before.
//  - --resume: a frame whose output already exists and is complete (a PNG
//    ending in its IEND chunk, an EXR with its magic number; every output is
//    written under a temporary name and renamed, so a file there was written
//    whole) is not rendered again. Not for a movie, which is written whole.
//  - Ctrl-C (SIGINT, SIGTERM; interrupt.h): the frame in progress finishes,
//    the run stops there with exit 130 (143 for SIGTERM); finished frames
//    stay, a movie is not written (its temporary file is removed). Further
//    Ctrl-Cs change nothing (a tool may signal the process and its group
//    both), so no partial file is ever left.
//  - A sequence's steps overlap (renderFrames, overlapOutput): frame k + 1 is
//    read on a worker (FramePrefetch, one frame ahead; not with --resume or
//    --shard, whose frames are read or not as the loop decides) and frame
//    k - 1 converted and written (or encoded into the movie) on another while
//    frame k renders. Frame k - 1 is settled (counted, logged, or failed as
//    --on-error says) before frame k is handed over, so the order, the
//    messages, the exit codes and the bytes are those of one step after
//    another (MENISCUS_RENDER_OVERLAP=0); Ctrl-C waits for the frame being
//    written. Only warnings read with frame k may come before frame k - 1's
//    progress line.
//  - A moving camera (--orbit, --turntable, --camera-path): frame i is at
//    i / --fps seconds; the path gives eye, target and fov, then --orbit or
//    --turntable turns the eye about the vertical through the target. The
//    default background (auto) is then the floor alone, centred under the
//    particles (two walls would jump sides as the camera goes round); an
//    explicit --background studio keeps its walls where the first frame's
//    camera puts them, for the whole run.
//  - --shard I/N renders the I-th of N contiguous shares of the frames
//    (frames I*count/N up to (I+1)*count/N), named as in the whole run, for
//    job arrays; a movie cannot be split. Frames left out (another shard's, or
//    kept by --resume) still warm the noise's turbulence for the frames that
//    follow: the holdFrames + 1 frames before a rendered frame are drawn and
//    dropped, so its boost is what an unbroken run gives (the tracker's
//    memory ends there), and a simulation is stepped through every frame time
//    before the share, as the whole run steps it. Each share's output is then
//    byte for byte the whole run's.
//  - --frames N renders a single input file as N frames (the turntable of a
//    still); without camera motion that is N identical frames, a held shot.
//    A sequence renders its own frames: --frames with one is an error.
//  - Under mpirun (cluster.h), --split frames gives process k of K
//    the frames of --shard k/K; --split particles gives it the k-th of K
//    contiguous index ranges of each frame's particles (after --select),
//    or, for an input with %r, its share of the part files (one per rank of
//    the simulation that wrote them), splatted there and composited sort-last
//    on process 0, which alone shades and writes. auto: frames for a
//    sequence (or --frames N), particles for one frame. Radius, camera and
//    studio are chosen as the one-process run chooses them (every process
//    reads the whole file for that; with %r: the radius of part 0, the camera
//    on samples of every part, the studio around all of them), so the
//    pictures are that run's, byte for byte. Any process's error ends the
//    whole job (MPI_Abort) with that error; the picture being composited is
//    not written.
#include "render.h"

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <cmath>
#include <fstream>
#include <functional>
#include <future>
#include <iostream>
#include <optional>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "cluster.h"
#include "frame_prefetch.h"
#include "help_format.h"
#include "interrupt.h"
#include "mesh.h"
#include "meniscus/boundary.h"
#include "meniscus/io.h"
#include "meniscus/memory_budget.h"
#include "meniscus/particle_view.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "meniscus/surface.h"
#include "progress.h"
#include "scene_file.h"
#include "simulate.h"
#ifdef MENISCUS_HAVE_FFMPEG
#include "meniscus/video.h"
#endif

namespace meniscus::app {
namespace {

// A diffuse particle set as the renderer's layer: its positions, velocities
// (copied into `velocity`) and kinds (the whitewater `type`), as views.
DiffuseLayer layerOf(const ParticleSet& set, std::vector<glm::vec3>& velocity) {
    DiffuseLayer layer;
    layer.positions = set.positions;
    const ParticleView view = ParticleView::of(set);
    velocity.clear();
    for (std::size_t k = 0; k < view.velocity.count; ++k) velocity.push_back(view.velocity[k]);
    layer.velocities = velocity;
    const Attribute* type = set.find("type");
    if (type && type->type == AttributeType::Int && type->components == 1 && type->count() == set.size())
        layer.kind = type->ints;
    return layer;
}

// Where the frames go: numbered images, or one movie opened before the first.
class Outputs {
public:
    // `writer`: this process writes (one that only splats for another does not).
    static Result<Outputs> open(const RenderJob& o, const RenderSettings& s, const Frames& frames, bool writer) {
        Outputs out(o, frames);
        if (!isMp4(o.output) || !writer) return out;
#ifdef MENISCUS_HAVE_FFMPEG
        if (auto st = makeOutputFolders(o.output); !st) return st.error();
        auto movie = VideoWriter::open(o.output, s.camera.width, s.camera.height, VideoParams{o.fps, o.crf});
        if (!movie) return movie.error();
        out.movie_.emplace(std::move(*movie));
        return out;
#else
        return makeError(o.output, "this build has no movies (FFmpeg's libavcodec-dev, libavformat-dev and "
                                   "libswscale-dev were not found when it was configured); write numbered PNGs "
                                   "(-o frame_%04d.png)");
#endif
    }

    bool movie() const { return isMp4(o_.output); }
    // Frame i's image file, or the movie's name.
    Result<std::string> name(std::size_t i) const { return movie() ? o_.output : frames_.outputName(o_.output, i); }

    Status write(std::size_t i, const Aovs& aovs, bool withAlpha) {
#ifdef MENISCUS_HAVE_FFMPEG
        if (movie_) return movie_->add(encodeSrgb8(aovs.color));
#endif
        auto n = name(i);
        if (!n) return n.error();
        if (auto st = makeOutputFolders(*n); !st) return st;
        return writeImage(*n, aovs, withAlpha);
    }

    // Frame i written (encoded into the movie, or its image file) on a
    // worker while the caller renders the next frame; collect() waits for it
    // and gives its status. One at a time: collect() before the next submit.
    // Without `overlap` it is written here, at once.
    void submit(std::size_t i, Aovs&& aovs, bool withAlpha, bool overlap) {
        pendingFrame_ = i;
        if (!overlap) {
            done_ = write(i, aovs, withAlpha);
            return;
        }
        pending_ = std::async(std::launch::async, [this, i, withAlpha, a = std::move(aovs)] {
            return write(i, a, withAlpha);
        });
    }
    // The submitted frame and its write's status, once written; nothing when
    // none is pending.
    std::optional<std::pair<std::size_t, Status>> collect() {
        if (pending_.valid()) done_ = pending_.get();
        if (!done_) return std::nullopt;
        std::pair<std::size_t, Status> out{pendingFrame_, std::move(*done_)};
        done_.reset();
        return out;
    }

    // The movie's end (nothing for images): the file appears under its name.
    Status finish() {
#ifdef MENISCUS_HAVE_FFMPEG
        if (movie_) return movie_->finish();
#endif
        return okStatus();
    }
    std::size_t movieFrames() const {
#ifdef MENISCUS_HAVE_FFMPEG
        if (movie_) return movie_->frames();
#endif
        return 0;
    }

private:
    Outputs(const RenderJob& o, const Frames& frames) : o_(o), frames_(frames) {}
    const RenderJob& o_;
    const Frames& frames_;
#ifdef MENISCUS_HAVE_FFMPEG
    std::optional<VideoWriter> movie_;
#endif
    std::size_t pendingFrame_ = 0;
    std::optional<Status> done_;     // the submitted frame's status, written at once
    std::future<Status> pending_;    // the submitted frame's write on a worker (last: joined first)
};

// One frame: its particles (`set`, already read for the first), the mesh or
// the diffuse layer when asked for, the render, its picture in `picture`
// when this process writes it.
Status renderFrame(const RenderJob& o, const Frames& frames, std::size_t i, Result<ParticleSet> set,
                   Renderer& renderer, RenderSettings& settings, std::optional<Aovs>& picture) {
    if (!set) return set.error();
    printWarnings(*set);
    // The mesh path: this frame's isosurface replaces splat smoothing and normals.
    TriangleMesh mesh;
    if (o.surface == "mesh") {
        auto made = extractSurface(ParticleView::of(*set), mesherParams(o.mesher, settings.radiusM, 0));
        if (!made) return Error{frames.name(i), made.error().message};
        mesh = std::move(*made);
        settings.mesh = &mesh;
    }
    // The diffuse layer of this frame (its own file when a pattern).
    ParticleSet diffuse;
    std::vector<glm::vec3> diffuseVelocity;
    if (!o.diffuse.empty()) {
        std::string path = o.diffuse;
        if (o.diffuse.find('%') != std::string::npos) {
            const long number =
                frames.files.empty() ? -1 : frameNumberOf(frames.files[frames.source(i)]);
            auto name = formatFramePattern(o.diffuse, number < 0 ? long(i) : number);
            if (!name) return name.error();
            path = *name;
        }
        auto read = readParticles(path, ParticleFormat::Auto, true);  // a frame may have none yet
        if (!read) return read.error();
        diffuse = std::move(*read);
        applyUp(frames.up, diffuse);
        settings.diffuse = layerOf(diffuse, diffuseVelocity);
    }
    settings.frameIndex = std::int64_t(i);  // the noise's turbulence compares consecutive frames
    auto aovs = renderer.render(ParticleView::of(*set), settings);
    settings.mesh = nullptr;
    settings.diffuse = {};
    if (!aovs) return Error{aovs.error().file.empty() ? frames.name(i) : aovs.error().file, aovs.error().message};
    if (settings.compositor && !settings.compositor->root()) return okStatus();  // the root writes the picture
    picture = std::move(*aovs);
    return okStatus();
}

// Whether a sequence's reading, rendering and writing overlap (frame k + 1
// read ahead and frame k - 1 written on workers while frame k renders),
// holding `held` bytes beside the frame rendering: on, unless
// MENISCUS_RENDER_OVERLAP=0 (the same bytes, one after another; the tests
// compare the two), or unless `held` does not fit in half of the budget's
// share that the memory checks leave over (1 - kJobShare): a run that close
// to its limit goes one step after another, as before.
bool overlapOutput(std::uint64_t held) {
    const char* v = std::getenv("MENISCUS_RENDER_OVERLAP");
    if (v && std::string(v) == "0") return false;
    const MemoryBudget budget = availableMemory();
    return budget.bytes == 0 || double(held) <= 0.5 * (1.0 - kJobShare) * double(budget.bytes);
}

// The last frame's colour while it is written (float RGBA and its 8-bit sRGB
// copy), and a frame's particles as read (the reader's arrays).
std::uint64_t colourBytes(const Camera& c) { return std::uint64_t(c.width) * std::uint64_t(c.height) * (16 + 4); }
std::uint64_t particleBytes(const ParticleSet& set) {
    std::uint64_t b = set.positions.size() * sizeof(glm::vec3);
    for (const Attribute& a : set.attributes) b += a.floats.size() * sizeof(float) + a.ints.size() * sizeof(std::int64_t);
    return b;
}

// `e` naming the scene file's key when the option came from one; still the
// same kind of error (Error::usage).
Error keyed(const Error& e, const RenderJob& o) {
    return Error{"", withSceneKey(e.describe(), o.sceneFile, o.sceneKeys), e.usage};
}

// The camera's motion over `count` frames at `fps` (--orbit, --turntable,
// --camera-path), shared by files and simulations; errors name the scene
// file's key when the option came from one.
Result<CameraMotion> motionFromOptions(const RenderJob& o, std::size_t count, double fps) {
    const auto failure = [&](const std::string& message) {
        return makeUsageError("", withSceneKey(message, o.sceneFile, o.sceneKeys));
    };
    if (o.orbit != 0.0 && o.turntable) return failure("--orbit and --turntable: give one or the other");
    if (o.turntable && count == 1)
        return failure("--turntable turns once over the sequence: for a single file give --frames N");
    auto path = cameraPathFromOptions(o);
    if (!path) return keyed(path.error(), o);
    return CameraMotion{std::move(*path), o.orbit, o.turntable, count, fps};
}

// --shard I/N as the frames [begin, end) of `count` it renders.
Result<IndexRange> shareOf(const std::string& shard, std::size_t count) {
    if (shard.empty()) return IndexRange{0, count};
    long long i = -1, n = 0;
    char slash = 0, extra = 0;
    if (std::sscanf(shard.c_str(), "%lld %c %lld %c", &i, &slash, &n, &extra) != 3 || slash != '/' || n < 1 ||
        i < 0 || i >= n)
        return makeUsageError("", "--shard " + shard + ": give I/N with 0 <= I < N (e.g. --shard 3/8, or "
                             "$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT)");
    return shareRange(count, std::size_t(i), std::size_t(n));
}

// Frames 0 .. frames.count() - 1, their particles from `next` (called once
// per frame, in order), rendered through `motion` from the camera in
// `settings` to o.output. Returns the exit code.
int renderFrames(Cluster& cluster, const RenderJob& o, const Frames& frames, const CameraMotion& motion,
                 RenderSettings& settings, const std::function<Result<ParticleSet>(std::size_t)>& next) {
    const std::size_t count = frames.count();
    // Composited sort-last: every process reads and splats each frame, the root writes it.
    const bool composited = settings.compositor != nullptr;
    const bool writer = !composited || cluster.root();
    const Camera start = settings.camera;
    if (motion.moves() && o.background == "auto") {
        settings.scene.walls = false;
        std::cerr << "meniscus: the camera moves: the floor alone as background (--background studio keeps the "
                     "walls, fixed where the first frame sees them)\n";
    } else if (motion.moves() && o.background == "studio") {
        settings.scene.wallsSeenFrom = cameraForFrame(start, motion, 0).eye;
    }
    // The output's folder, checked (and a killed run's temporaries swept)
    // before the renderer starts; with shards or processes on other machines
    // writing there too, only temporaries an hour old are swept.
    if (writer && count > 0) {
        auto first = isMp4(o.output) ? Result<std::string>(o.output) : frames.outputName(o.output, 0);
        if (!first) return fail(first.error());
        if (auto st = prepareOutputFolder(*first, !o.shard.empty() || cluster.size() > 1); !st) return fail(st.error());
    }
    auto made = makeRenderer(o);
    if (!made) return fail(made.error());
    Renderer renderer = std::move(*made);
    auto outputs = Outputs::open(o, settings, frames, writer);
    if (!outputs) return fail(outputs.error());

    auto share = shareOf(o.shard, count);
    if (!share) return fail(share.error());
    if (!o.shard.empty())
        std::cerr << "meniscus: shard " << o.shard << ": frames " << share->begin + 1 << " to " << share->end << " of "
                  << count << "\n";
    // Which frames are rendered: the share's, less those --resume keeps.
    std::vector<char> rendered(share->end, 0);
    for (std::size_t i = share->begin; i < share->end; ++i) {
        auto name = outputs->name(i);
        if (!name) return fail(name.error());
        rendered[i] = !(o.resume && imageComplete(*name));
    }
    // The turbulence tracker's memory, in frames (0: nothing carries over):
    // a frame not rendered is drawn and dropped when one of the `memory`
    // frames after it is rendered.
    const std::size_t memory =
        settings.noise.enabled ? std::size_t(std::max(settings.noise.turbulence.holdFrames, 0)) + 1 : 0;
    const auto remembered = [&](std::size_t i) {
        for (std::size_t j = i + 1; j <= i + memory && j < share->end; ++j)
            if (rendered[j]) return true;
        return false;
    };

    std::vector<std::pair<std::size_t, std::string>> failed;  // frame, error
    std::size_t written = 0, resumed = 0;
    ProgressBar progress(share->end - share->begin, "rendering");
    // Frame i failed (read, render or write): the run stops with the exit
    // code, or, with --on-error skip, the frame is listed and left out.
    const auto failedFrame = [&](std::size_t i, const Error& e) -> std::optional<int> {
        if (o.onError != "skip") {
            if (count <= 1) return fail(e);
            // Of a sequence: say how to go on past such frames.
            return fail(e.describe() + " (frame " + std::to_string(i + 1) + " of " + std::to_string(count) +
                        "; --on-error skip renders the others and lists the failed ones)");
        }
        failed.emplace_back(i, e.describe());
        std::cerr << "meniscus: frame " << i + 1 << "/" << count << " skipped: " << e.describe() << "\n";
        return std::nullopt;
    };
    // The frame submitted to the output, once written: counted and shown, or failed.
    const auto settle = [&]() -> std::optional<int> {
        auto done = outputs->collect();
        if (!done) return std::nullopt;
        if (!done->second) return failedFrame(done->first, done->second.error());
        ++written;
        if (writer) progress.step(done->first + 1 - share->begin, *outputs->name(done->first));
        return std::nullopt;
    };
    // Overlapped (overlapOutput): frame i is written on a worker while frame
    // i + 1 renders, and settled before frame i + 1 is submitted, so frames
    // are written, counted, shown and failed in order, as sequentially.
    const bool overlap = !composited && share->end - share->begin > 1 && overlapOutput(colourBytes(settings.camera));
    for (std::size_t i = 0; i < share->end; ++i) {
        // Ctrl-C or SIGTERM: stop before the next frame (the one in progress
        // finished, its output written). Composited, the processes agree
        // first (mpirun signals each at its own moment; one stopping alone
        // would leave the others waiting in the composite).
        if (composited ? !cluster.allOk(!interrupted()) : interrupted()) {
            if (auto code = settle()) return *code;
            const int code =
                stopInterrupted(i > share->begin ? "after frame " + std::to_string(i) + " of " + std::to_string(count)
                                                 : "before the first frame",
                                outputs->movie() ? "no movie written (a movie is written whole: run it again)"
                                                 : "the frames written are whole: the same command with --resume "
                                                   "renders the rest");
            return code ? code : 128 + SIGINT;  // another process was signalled
        }
        auto name = outputs->name(i);
        if (!name) return fail(name.error());
        if (!rendered[i]) {
            if (auto code = settle()) return *code;
            if (i >= share->begin) {
                ++resumed;
                if (writer) progress.step(i + 1 - share->begin, *name + " (complete, kept)");
            }
            if (remembered(i)) {
                if (auto set = next(i)) {
                    settings.camera = cameraForFrame(start, motion, i);
                    settings.frameIndex = std::int64_t(i);
                    (void)renderer.render(ParticleView::of(*set), settings);
                }
            } else if (!frames.simulation.empty()) {
                (void)next(i);  // stepped through, as the whole run steps it
            }
            continue;
        }
        settings.camera = cameraForFrame(start, motion, i);
        // A backdrop sequence: this frame's picture of the set (as Blender
        // rendered it from the camera path's key of this frame).
        if (backdropSequence(o))
            if (auto st = backdropForFrame(o, i, settings); !st) {
                if (auto code = settle()) return *code;
                if (auto code = failedFrame(i, st.error())) return *code;
                continue;
            }
        Result<ParticleSet> set = next(i);
        // Composited: a frame one process cannot read is a failure on all (they
        // would otherwise wait for its splat).
        bool readFailed = !set;
        if (composited && !cluster.allOk(bool(set))) {
            if (set) set = makeError(frames.name(i), "could not be read by another process (its error is above)");
            readFailed = true;
        }
        std::optional<Aovs> picture;
        Status st = renderFrame(o, frames, i, std::move(set), renderer, settings, picture);
        // The frame before, written meanwhile: settled first, in order.
        if (auto code = settle()) return *code;
        if (st && picture) {
            outputs->submit(i, std::move(*picture), !settings.scene.background, overlap);
            if (!overlap) {
                auto done = outputs->collect();  // written at once: part of the frame, as before
                st = std::move(done->second);
            }
        }
        if (!st && composited && cluster.size() > 1 && !readFailed) {
            // Past the reading, a process's error leaves the others in the composite: end the job.
            std::cerr << "meniscus: error: " << st.error().describe() << " (process " << cluster.rank() << " of "
                      << cluster.size() << ")\n";
            cluster.abort(1);
        }
        if (!st) {
            if (auto code = failedFrame(i, st.error())) return *code;
        } else if (!overlap || !picture) {
            ++written;
            if (writer) progress.step(i + 1 - share->begin, *name);
        }
    }
    if (auto code = settle()) return *code;
    if (auto st = outputs->finish(); !st) return fail(st.error());

    if (!writer) {
        return failed.empty() ? 0 : 1;
    } else if (outputs->movie()) {
        std::cerr << "meniscus: wrote " << o.output << " (" << outputs->movieFrames() << " frames, H.264, " << o.fps
                  << " fps)\n";
    } else if (count == 1 && written == 1) {
        // A symlinked output is written through the link (the link stays).
        const std::string out = *outputs->name(0);
        std::error_code ec;
        const bool link = std::filesystem::is_symlink(std::filesystem::symlink_status(out, ec));
        std::cerr << "meniscus: wrote " << out
                  << (link ? " (through the link, to " + std::filesystem::weakly_canonical(out, ec).string() + ")"
                           : std::string())
                  << "\n";
    } else if (count > 1 || resumed > 0) {
        std::cerr << "meniscus: wrote " << written << " frames to " << o.output
                  << (resumed ? " (" + std::to_string(resumed) + " already complete, kept)" : std::string()) << "\n";
    }
    if (!failed.empty()) {
        std::cerr << "meniscus: error: " << failed.size() << " of " << count << " frames failed:\n";
        for (const auto& [i, why] : failed) std::cerr << "  frame " << i + 1 << ": " << why << "\n";
        return 1;
    }
    return 0;
}

// A simulation scene as the input (a render scene file's "particles" may
// name one): simulated here, each frame rendered as it is reached (every
// 1/fps simulated seconds, the scene's fps), framed once on the scene's
// domain as `simulate --render` frames its images; the particle radius is
// the simulation's (--radius sets it).
int renderSimulation(Cluster& cluster, const RenderJob& o, RenderSettings& settings) {
    if (auto up = upRotation(o.up); !up || !up->identity)
        return fail(makeUsageError("", "--up " + vec3Text(o.up) + ": a simulation's up is +y (gravity along -y); --up turns files"));
    if (o.frames > 0) return fail(makeUsageError("", "--frames: " + o.input + " is a simulation, whose frames are its own"));
    SimulateJob so;
    if (!o.select.empty())
        return fail(makeUsageError("", "--select " + o.select + ": picks particles of files; " + o.input +
                                           " is a simulation scene, whose particles are all its fluid"));
    so.scene = o.input;
    so.radius = o.radius;
    so.duration = o.duration;
    auto scene = sceneFromOptions(so);
    if (!scene) return fail(scene.error());
    auto made = sim::Simulator::create(*scene);
    if (!made) return fail(made.error());
    sim::Simulator& simulator = **made;
    Frames frames;
    frames.simulation = o.input;
    frames.repeat = std::size_t(std::floor(scene->duration * scene->fps + 1e-9)) + 1;
    frames.renumber = true;
    // The movie and a moving camera keep the simulation's time: --fps is the scene's unless given otherwise.
    RenderJob timed = o;
    if (o.fps == defaults::kVideoFps) timed.fps = scene->fps;
    auto motion = motionFromOptions(o, frames.count(), timed.fps);
    if (!motion) return fail(motion.error());
    if (!isMp4(o.output))
        if (auto st = frames.checkOutput(o.output, "out_%04d.png"); !st) return fail(st.error());
    if (auto st = fixForScene(o, *scene, settings); !st)
        return fail(keyed(st.error(), o));
    settings.colorOnly = !isExr(o.output);
    std::cerr << "meniscus: simulating " << o.input << ": " << simulator.size() << " particles, r = "
              << scene->params.radius << " m, " << sim::solverName(scene->params.solver) << ", " << scene->duration
              << " s, a frame every " << 1.0 / scene->fps << " s\n";
    return renderFrames(cluster, timed, frames, *motion, settings, [&](std::size_t i) -> Result<ParticleSet> {
        if (auto st = simulator.advanceTo(double(i) / scene->fps); !st) return Error{o.input, st.error().message};
        return simulator.particles();
    });
}

}  // namespace

void addSequenceOptions(CLI::App* cmd, RenderJob& o) {
    addJobTableOptions(cmd, o, {"fps", "crf", "duration", "renumber", "on-error", "resume", "shard", "split", "orbit",
                                "turntable", "camera-path", "frames"});
}

namespace {

// The part files of a %r pattern (%r or %0Nr: the rank of the process that
// wrote it), r = 0, 1, ... while they exist.
std::vector<std::string> expandParts(const std::string& pattern) {
    static const std::regex rank("%(0[0-9]+)?r");
    std::vector<std::string> parts;
    for (int r = 0; r < 1000000; ++r) {
        std::string name;
        std::smatch m;
        std::string rest = pattern;
        while (std::regex_search(rest, m, rank)) {
            char digits[32];
            const int width = m[1].matched ? std::atoi(m[1].str().c_str()) : 0;
            std::snprintf(digits, sizeof digits, "%0*d", std::min(width, 20), r);
            name += m.prefix().str() + digits;
            rest = m.suffix().str();
        }
        name += rest;
        if (!std::filesystem::exists(name)) break;
        parts.push_back(name);
    }
    return parts;
}

// The split over the processes (--split: frames or particles) for `count`
// frames on `processes`.
Result<std::string> splitMode(const RenderJob& o, std::size_t count, bool parts) {
    if (o.split != "auto" && o.split != "frames" && o.split != "particles")
        return makeError("", "--split " + o.split + ": expected auto, frames or particles");
    if (parts) {
        if (o.split == "frames") return makeError("", "--split frames: " + o.input + " names the parts of one frame (%r)");
        return std::string("particles");
    }
    if (o.split != "auto") return o.split;
    return std::string(count > 1 ? "frames" : "particles");
}

// One frame written as part files (a %r pattern): process k of K reads its
// share of the parts, joined in part order; the radius is estimated on part
// 0, the camera framed on samples of every part, the studio built around all
// of them, the same on one process as on K.
int renderParts(Cluster& cluster, const RenderJob& o, RenderSettings& settings) {
    if (o.input.find('%') != o.input.rfind('%') && std::regex_search(o.input, std::regex("%[^r0-9]|%0[0-9]+[^0-9r]")))
        return fail(o.input + ": a %r pattern names the part files of one frame; a sequence of parts is not supported "
                              "(render each frame's parts on their own)");
    if (o.frames > 0) return failUsage("--frames: " + o.input + " names the parts of one frame (%r)");
    // What needs every particle on one process (a neighbourhood, or the
    // root drawing all of them after the composite) is not there with parts.
    const std::pair<bool, const char*> whole[] = {{settings.anisotropy.enabled, "--anisotropy on"},
                                                  {settings.noise.enabled, "--noise"},
                                                  {settings.whitening.enabled, "--whiten"},
                                                  {settings.spray.enabled, "--spray"},
                                                  {!o.diffuse.empty(), "--diffuse"}};
    for (const auto& [on, option] : whole)
        if (on)
            return fail(std::string(option) + ": needs every particle of the frame in one process (the anisotropic "
                        "kernels their neighbours; the noise, whitening and drops all of them on process 0), and with "
                        "part files (" + o.input + ") a process holds only its own parts: join the parts into one "
                        "file, which every process reads" +
                        (settings.anisotropy.enabled ? std::string(", or add --anisotropy off") : std::string()));
    const std::vector<std::string> parts = expandParts(o.input);
    if (parts.empty()) {
        const std::string first = std::regex_replace(o.input, std::regex("%(0[0-9]+)?r"), "0");
        return fail(first + ": no such file (the first part of " + o.input + ", %r = 0)");
    }
    auto frames = openFrames(parts[0], nullptr, o.hPerSpacing);
    if (!frames) return fail(frames.error());
    if (auto st = frames->addFluids(o); !st) return fail(st.error());
    if (!frames->moreFluids.empty()) return failUsage("--fluid: " + o.input + " names the parts of one frame (%r)");
    auto up = upRotation(o.up);
    if (!up) return fail(keyed(up.error(), o));
    frames->up = *up;
    auto motion = motionFromOptions(o, 1, o.fps);
    if (!motion) return fail(motion.error());
    // Radius (part 0's), and a first camera and studio that the parts' own replace below.
    auto first = fixForSequence(o, *frames, settings, nullptr);
    if (!first) return fail(keyed(first.error(), o));
    // This process's parts, joined; their samples and bounds.
    const IndexRange mine = shareRange(parts.size(), cluster.rank(), cluster.size());
    ParticleSet set;
    std::vector<glm::vec3> samples;
    Bounds box;
    bool ok = true;
    for (std::size_t p = mine.begin; p < mine.end && ok; ++p) {
        Frames one = *frames;
        one.files = {parts[p]};
        auto part = one.loadChecked(0);
        if (part) {
            sampleFramePoints(part->positions, samples);
            for (const glm::vec3& q : part->positions) box.extend(q);
        }
        const Status st = part ? appendParticles(set, std::move(*part), parts[p], parts[mine.begin]) : Status(part.error());
        if (!st) {
            std::cerr << "meniscus: error: " << st.error().describe() << "\n";
            ok = false;
        }
    }
    if (!cluster.allOk(ok)) return 1;
    if (auto st = cluster.allGather(samples); !st) return fail(st.error());
    box = cluster.allBounds(box);
    if (!o.eye && o.cameraPath.empty()) {
        auto camera = chooseCamera(o, samples, settings.radiusM);
        if (!camera) return fail(camera.error());
        settings.camera = *camera;
    }
    settings.scene.studioBounds = box;
    if (cluster.size() > 1) settings.compositor = cluster.compositor();
    settings.colorOnly = !isExr(o.output);
    if (cluster.root())
        std::cerr << "meniscus: " << parts.size() << " part" << (parts.size() == 1 ? "" : "s") << " of " << o.input
                  << (cluster.size() > 1 ? " over " + std::to_string(cluster.size()) + " processes" : std::string())
                  << "\n";
    // DualSPHysics' boundary particles (--boundary-particles) taken out of
    // this process's parts; as walls, every process's gathered and meshed
    // (the root draws the geometry of the composited picture).
    if (o.boundaryParticles != "liquid") {
        auto taken = takeBoundaryParticles(set, o.input);
        if (!cluster.allOk(bool(taken))) return taken ? 1 : fail(taken.error().describe());
        if (auto st = cluster.allGather(taken->fixed); !st) return fail(st.error().describe());
        if (auto st = cluster.allGather(taken->moving); !st) return fail(st.error().describe());
        const Bounds liquid = cluster.allBounds(computeBounds(set.positions));
        if (o.boundaryParticles == "walls" && !taken->empty()) {
            Bounds all = liquid;
            for (const glm::vec3& p : taken->fixed) all.extend(p);
            const glm::vec3 centre = liquid.empty() ? all.center() : liquid.center();
            auto walls = boundaryGeometry(*taken, o.cutAway == "on", centre, nullptr);
            if (!walls) return fail(Error{o.input, walls.error().message}.describe());
            addGeometry(settings, std::move(*walls), o.cutAway == "on");
        }
    }
    return renderFrames(cluster, o, *frames, *motion, settings,
                        [&](std::size_t) -> Result<ParticleSet> { return std::move(set); });
}

int runRenderOn(Cluster& cluster, const RenderJob& options, const ParticleSet* embedded) {
    RenderJob o = options;
    if (!isPng(o.output) && !isExr(o.output) && !isMp4(o.output))
        return fail(o.output + ": output must end in .png, .exr or .mp4");
    if (o.resume && isMp4(o.output)) return failUsage("--resume: a movie is written whole; resume numbered images");
    if (!o.shard.empty() && isMp4(o.output))
        return fail(makeUsageError("", "--shard: a movie is written whole; shard numbered images (and join them with ffmpeg)"));
    installInterruptHandler("frame");  // from here on Ctrl-C stops after the frame in progress
    auto parsed = settingsFromOptions(o);
    if (!parsed) return fail(keyed(parsed.error(), o));
    RenderSettings settings = std::move(*parsed);
    const bool parts = !embedded && std::regex_search(o.input, std::regex("%(0[0-9]+)?r"));
    const bool simulation = !parts && isJsonFile(o.input);

    auto frames = simulation || parts ? Result<Frames>(Frames{}) : openFrames(o.input, embedded, o.hPerSpacing);
    if (!frames) return fail(frames.error());
    // Several processes (mpirun): frames or particles to each (--split).
    const std::size_t inputFrames = o.frames > 0 ? o.frames : frames->count();
    auto split = splitMode(o, simulation ? 2 : inputFrames, parts);
    if (!split) return fail(split.error());
    if (cluster.size() > 1 && cluster.root())
        std::cerr << "meniscus: " << cluster.size() << " processes, split by " << *split << "\n";
    if (cluster.size() > 1 && *split == "frames") {
        if (!o.shard.empty())
            return fail(makeUsageError("", "--shard: under mpirun the processes split the frames themselves; leave it out"));
        if (isMp4(o.output))
            return fail("-o " + o.output + ": a movie is written whole by one process; under mpirun write numbered "
                        "images (and join them with ffmpeg), or --split particles");
        o.shard = std::to_string(cluster.rank()) + "/" + std::to_string(cluster.size());
    }
    if (o.duration >= 0.0 && !simulation)
        return failUsage("--duration: sets how long a simulation scene runs; " +
                    (o.input.empty() ? std::string("the demo frame") : o.input) +
                    " is particle data, whose frames are its own");
    if (simulation) {
        if (cluster.size() > 1 && *split != "frames") return failUsage("--split particles: " + o.input + " is a simulation; split its frames");
        return renderSimulation(cluster, o, settings);
    }
    if (parts) return renderParts(cluster, o, settings);
    if (cluster.size() > 1 && *split == "particles") settings.compositor = cluster.compositor();
    if (auto st = frames->addFluids(o); !st) return fail(st.error());
    frames->renumber = o.renumber;
    auto up = upRotation(o.up);
    if (!up) return fail(keyed(up.error(), o));
    frames->up = *up;
    if (o.frames > 0) {
        if (frames->count() != 1)
            return fail(makeUsageError("", withSceneKey("--frames renders a single input file as N frames; " + o.input +
                                                            " has " + std::to_string(frames->count()) +
                                                            ", each rendered once (leave out --frames)",
                                                        o.sceneFile, o.sceneKeys)));
        frames->repeat = o.frames;
    }
    const std::size_t count = frames->count();
    // A movie plays at --fps when given, else at the rate its data carries (a
    // .pvd's timesteps), else at the default, which the log says.
    if (isMp4(o.output) && o.fps == defaults::kVideoFps && !embedded && o.frames == 0) {
        auto rate = frameRateOfInput(o.input);
        if (!rate) return fail(rate.error());
        const bool usable = *rate && **rate >= 0.001 && **rate <= 1000.0;
        if (usable) o.fps = **rate;
        if (cluster.root())
            std::cerr << "meniscus: the movie plays at " << o.fps << " fps"
                      << (usable ? " (the rate of the input's timesteps; --fps sets another)"
                                 : " (the frames carry no time; --fps sets the rate)")
                      << "\n";
    }
    auto motion = motionFromOptions(o, count, o.fps);
    if (!motion) return fail(motion.error());
    if (!isMp4(o.output))
        if (auto st = frames->checkOutput(o.output, "out_%04d.png"); !st) return fail(st.error());

    // Radius and camera are fixed once per sequence, so the animation does not flicker.
    std::size_t firstIndex = 0;
    auto first = fixForSequence(o, *frames, settings, &firstIndex);
    if (!first) return fail(keyed(first.error(), o));
    // A repeated file is read once.
    std::optional<ParticleSet> still;
    if (frames->repeat) still = *first;
    settings.colorOnly = !isExr(o.output);  // a PNG or a movie needs only the colour AOV
    if (o.stages.whitening.enabled && !ParticleView::of(*first).velocity.present())
        std::cerr << "meniscus: warning: " << frames->name(firstIndex)
                  << " has no velocity attribute: --whiten leaves the colour as it is\n";

    // Split by particles: every process reads the whole frame (its neighbours
    // give the anisotropic kernels) and splats its index range of it.
    const bool byParticles = settings.compositor != nullptr;
    // Each frame's DualSPHysics boundary particles (--boundary-particles) are
    // taken out of the liquid as it is read; as walls, drawn with the options'
    // geometry (prepareBoundary).
    const std::shared_ptr<const SceneGeometry> optionGeometry = settings.geometry;
    // A sequence rendered whole, in order (not --resume, not a shard, whose
    // frames are read or not as the loop decides): frame i + 1 is read on a
    // worker while frame i renders (one frame ahead: memory for one more
    // frame's particles). The reader's result and error are the same.
    std::optional<FramePrefetch> prefetch;
    if (!still && !o.resume && o.shard.empty() && count > 1 &&
        overlapOutput(colourBytes(settings.camera) + particleBytes(*first)))
        prefetch.emplace(*frames, nullptr, 1, nullptr, firstIndex, false);
    return renderFrames(cluster, o, *frames, *motion, settings, [&](std::size_t i) -> Result<ParticleSet> {
        // (Frames before firstIndex did not load when fixForSequence tried them.)
        Result<ParticleSet> set = i == firstIndex ? std::move(*first)
                                  : still         ? Result<ParticleSet>(*still)
                                  : prefetch      ? prefetch->take(i)
                                                  : frames->loadChecked(i);
        if (set) {
            auto geometry = prepareBoundary(*set, o, optionGeometry, frames->name(i));
            if (!geometry) return geometry.error();
            settings.geometry = std::move(*geometry);
        }
        if (set && byParticles) {
            const IndexRange r = shareRange(set->size(), cluster.rank(), cluster.size());
            settings.share = ParticleRange{r.begin, r.end};
        }
        return set;
    });
}

}  // namespace

int runRender(const RenderJob& o, const ParticleSet* embedded) {
    auto cluster = Cluster::start();
    if (!cluster) return fail(cluster.error());
    const int code = runRenderOn(**cluster, o, embedded);
    // One process's failure ends the job: the others would wait for it in a
    // composite, or go on rendering frames of a run that failed. Not an
    // interrupted one: the others, signalled too, finish their frames in
    // progress (an abort would kill them mid-write).
    if (code != 0 && !interrupted() && (*cluster)->size() > 1) {
        std::cerr.flush();
        (*cluster)->abort(code);
    }
    return code;
}

}  // namespace meniscus::app
