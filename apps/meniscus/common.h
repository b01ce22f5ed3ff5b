// What the subcommands that render (render, demo, view) share: the one-line
// messages, the render options and their parsing, the frames an input names,
// and the settings fixed once for a whole sequence.
#pragma once

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/camera_path.h"
#include "meniscus/sim.h"
#include "meniscus/options.h"
#include "meniscus/params.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace CLI {
class App;
class Option;
}

namespace meniscus::app {

// "meniscus: error: LINE" on stderr; returns the exit code 1.
int fail(const std::string& line);
// The error, described, on stderr; returns its exit code: 2 for the
// caller's settings (Error::usage), else 1 (docs/usage.md#errors).
int fail(const Error& error);
// "meniscus: error: LINE" for a wrong option or setting; returns the exit code 2.
int failUsage(const std::string& line);
void printWarnings(const ParticleSet& set);

bool isPng(const std::string& path);
bool isExr(const std::string& path);
bool isMp4(const std::string& path);

// A render job: the look, camera and surface (meniscus::RenderOptions) and
// the job's backend, inputs, movie, moving camera and shares
// (meniscus::JobOptions), both declared by the library's tables
// (include/meniscus/options.h), and the input and output.
struct RenderJob : meniscus::RenderOptions, meniscus::JobOptions {
    std::string input;
    std::string output;
    // A render scene file's name and, per option it set, its key (errors name the key).
    std::string sceneFile;
    std::vector<std::pair<std::string, std::string>> sceneKeys;
};

// Size, camera, radius and look (--width ... --background) on `cmd`; without
// --radius when `radiusOption` is false (simulate: the images use the
// simulation's own radius, which its --radius sets).
void addCameraOptions(CLI::App* cmd, RenderJob& o, bool radiusOption = true);
// --surface screen|raycast|mesh, the mesher's options and the ray cast's
// (render, compare and Python's settings).
void addSurfaceOptions(CLI::App* cmd, RenderJob& o);
// --fluid-attribute's alternative, --fluid (one more input per fluid), and
// --select (addSelectOption), the options on what each input frame holds, on `cmd`.
void addFluidInputOption(CLI::App* cmd, RenderJob& o);
// --select EXPR on `cmd` (render, view, mesh, compare, whitewater): which particles of each
// file are drawn (parseSelection, include/meniscus/particles.h).
void addSelectOption(CLI::App* cmd, std::string& select);
// Particles of `more` appended to `set` as fluid `fluid` (set's own become
// fluid 0 when it has no fluid attribute yet): attributes both have with the
// same type are joined, others left out with a warning in set.warnings; ids
// are offset by fluid * 2^40 so the fluids' ids stay apart.
void appendFluid(ParticleSet& set, const ParticleSet& more, int fluid);
// --backend on `cmd`.
void addBackendOption(CLI::App* cmd, RenderJob& o);

// The pipeline settings named by the options (camera and radius come later):
// the library's renderSettings, and what only the command knows (--fluid,
// --diffuse).
Result<RenderSettings> settingsFromOptions(const RenderJob& o);

// The table's options (renderOptionTable; the mesher's with `mesher`) on
// `cmd`, each in its group with its help, unit, default and checks, bound to
// `o`; only those `keep` says.
void addTableOptions(CLI::App* cmd, meniscus::RenderOptions& o,
                     const std::function<bool(const RenderOptionSpec&)>& keep);
void addMesherTableOptions(CLI::App* cmd, MesherOptions& o);
// The job table's options of these names on `cmd`, in this order.
void addJobTableOptions(CLI::App* cmd, JobOptions& o, const std::vector<std::string>& names);
// One option of a table bound to `ref` (its own struct's field).
CLI::Option* addTableOption(CLI::App* cmd, const std::string& name, OptionGroup group, const std::string& help,
                            const OptionRef& ref, const OptionLimits& limits, bool flag, bool noDefault);
// A table's row on `cmd`, bound to `ref` (its own options' field, or another struct's).
template <class O>
CLI::Option* addRow(CLI::App* cmd, const OptionSpec<O>& s, const OptionRef& ref) {
    return addTableOption(cmd, s.name, s.group, s.help, ref, s.limits, s.flag, s.noDefault);
}
// Every row of `table` on `cmd`, in the table's order, bound to `o`.
template <class O>
void addRows(CLI::App* cmd, std::span<const OptionSpec<O>> table, std::type_identity_t<O>& o) {
    for (const OptionSpec<O>& s : table) addRow(cmd, s, s.field(o));
}

// A rendered frame to `path`: .exr with every AOV, else PNG of the colour
// (with alpha when `withAlpha`); a temporary name renamed, so never partial.
Status writeImage(const std::string& path, const Aovs& aovs, bool withAlpha);

// The turn of `up` applied to the positions and the velocity attribute of
// `set` (other attributes are not directions).
void applyUp(const UpRotation& up, ParticleSet& set);

// The frames to render: the files an input names, or the one embedded frame.
struct Frames {
    std::vector<std::filesystem::path> files;  // empty for the embedded frame
    const ParticleSet* embedded = nullptr;
    // Copied into each frame's `fluid` attribute on loading (useFluidAttribute); empty: none.
    std::string fluidAttribute;
    // One more sequence per further fluid (addFluids): frame i of each joins
    // frame i of `files` as fluid 1, 2, ... (the input being fluid 0).
    std::vector<std::vector<std::filesystem::path>> moreFluids;
    // Opens the sequences of --fluid (an error naming the one whose frame
    // count differs from the input's, or when --fluid-attribute is given too)
    // and takes --select (setSelection).
    Status addFluids(const RenderJob& o);

    // Only the particles matching this are kept of each file as it is read
    // (the input's and each --fluid's, before --up turns them; applySelection),
    // so every command that loads frames through load() honours --select.
    ParticleFilter selection;
    // Parses --select's text into `selection`; an error naming the option.
    Status setSelection(const std::string& text);

    // A file's smoothing length in particle spacings (addRadiusFromSmoothingLength).
    float hPerSpacing = defaults::kHPerSpacing;
    // Turns each frame so its up axis (--up) is +y.
    UpRotation up;

    // A single input rendered as this many frames (--frames), or the frames of
    // a simulation; 0: the input's own.
    std::size_t repeat = 0;
    // A simulation scene rendered as it runs (render with a simulation scene
    // as input): its file, which names the frames in messages; no files.
    std::string simulation;
    std::size_t count() const { return repeat ? repeat : embedded ? 1 : files.size(); }
    // The input file (or embedded frame) of output frame i.
    std::size_t source(std::size_t i) const { return repeat ? 0 : i; }
    // Frame i, with a `radius` attribute from the file's smoothing length when it
    // has one and no radius (whose name then goes to *smoothingLength).
    Result<ParticleSet> load(std::size_t i, std::string* smoothingLength = nullptr) const;
    // load, and its coordinates checked (checkCoordinates) against frame i's name.
    Result<ParticleSet> loadChecked(std::size_t i, std::string* smoothingLength = nullptr) const;
    // Frame i's file, or "the demo frame".
    std::string name(std::size_t i) const;
    // Output frames numbered 0, 1, 2, ... in order instead of by their input's numbers.
    bool renumber = false;
    // An error unless `output` can name every frame: several frames need a
    // printf pattern (`example` shows one).
    Status checkOutput(const std::string& output, const char* example) const;
    // The output name of frame i: `output`, or the pattern filled with the
    // frame's own number (its file name's last digits), else its position
    // (always its position for a repeated input).
    Result<std::string> outputName(const std::string& output, std::size_t i) const;
    // The number outputName gives frame i.
    long outputNumber(std::size_t i) const;
};
Result<Frames> openFrames(const std::string& input, const ParticleSet* embedded,
                          float hPerSpacing = defaults::kHPerSpacing);
// --h-per-spacing, and the line saying radii came from a smoothing length.
void addSmoothingLengthOption(CLI::App* cmd, float& hPerSpacing);
void printSmoothingLengthNote(const std::string& attribute, float hPerSpacing);

// Makes attribute `name` of `set` its fluid index (the `fluid` attribute the
// renderer reads): integers, or floats holding whole numbers (DualSPHysics and
// ParaView write type ids as floats). An error naming the problem (no such
// attribute, listing those there are; not one component; a fraction).
Status useFluidAttribute(ParticleSet& set, const std::string& name);

// The renderer on --backend; Auto falling back to the CPU says why on stderr.
Result<Renderer> makeRenderer(const RenderJob& o);

// --camera-path's keys (readCameraPath) turned by --up into the renderer's
// coordinates, as --eye and --target are; empty without --camera-path.
Result<std::vector<CameraKey>> cameraPathFromOptions(const RenderJob& o);

// The camera for a whole sequence (fixForSequence; the Python module's
// render): the user's (--eye and --target in the data's frame, turned by
// --up; --camera-path's first key), or auto-framed on `samplePoints` (the
// particles of a few frames: first, last, three between). The sampled
// particles left outside the automatic frame are counted in *outsideCount,
// or said on stderr without it.
Result<Camera> chooseCamera(const RenderJob& o, std::span<const glm::vec3> samplePoints, float radius,
                            std::size_t* outsideCount = nullptr);
// Fixes radius, camera (the options', the camera path's first key, or
// auto-framed on a few frames) and the studio in `settings` once for the
// whole sequence, so an animation does not flicker; returns the first frame, already read. With --on-error skip the
// first frame that loads (its index in *firstIndex) and the frames that load.
Result<ParticleSet> fixForSequence(const RenderJob& o, const Frames& frames, RenderSettings& settings,
                                   std::size_t* firstIndex = nullptr);

// The same for a simulation whose particles never leave `box` (its domain,
// the tank): radius `radiusM`, the camera the options' or auto-framed on the
// box's eight corners, the studio around the box. Every frame, the first
// (which an emitter may leave empty) included, is seen by the same camera.
Status fixForBox(const RenderJob& o, const Bounds& box, float radiusM, RenderSettings& settings);
// The simulation's world drawn (its colliders, its domain's walls cut away
// unless --cut-away off: simulationGeometry) added to `settings`' geometry,
// then the camera and the studio fixed for the domain (fixForBox).
Status fixForScene(const RenderJob& o, const sim::Scene& scene, RenderSettings& settings);

}  // namespace meniscus::app
