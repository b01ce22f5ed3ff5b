// The options a user sets, declared once: every face (the CLI's options and
// its --help, Python's keywords and meniscus.settings(), render scene files'
// keys, the viewer's saved scenes, docs/cli.md) is made from the tables here.
// `renderSettings` turns the render options' typed values into the
// pipeline's RenderSettings, `applySimulateOptions` the simulator's into a
// scene, `whitewaterParams` the whitewater generator's into its parameters.
// Defaults are the structs' initialisers, which take them from params.h.
//
// An option's name is its command-line spelling without the dashes
// ("noise-bump"); Python and scene files spell it with underscores
// ("noise_bump"), and findOption accepts either.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "meniscus/result.h"
#include "meniscus/surface.h"

namespace meniscus {

namespace sim {
struct Scene;
}

// Where an option is listed (--help, docs/cli.md), in the order people set things.
// Simulation, Generation, Classes and Motion are simulate's and whitewater's.
enum class OptionGroup {
    Input,
    Camera,
    Look,
    Surface,
    Extras,
    Output,
    Movie,
    Performance,
    Cluster,
    Simulation,
    Generation,
    Classes,
    Motion,
    Scripting
};
// "Input", "Camera", ... (the help's group titles).
const char* optionGroupTitle(OptionGroup group);

// How the isosurface path meshes (mesh, and render with --surface mesh; the
// ray cast takes iso and support from here too).
struct MesherOptions {
    float cubeSize = defaults::kCubeSizeRadii;
    float iso = defaults::kSurfaceIso;
    std::string field = "sph";
    float support = 0.0f;  // radii; 0 = the field's default
    int block = defaults::kBlockCubes;
};

// The look, camera and surface of a render: what `render`, `view` and
// `simulate --render` take on the command line, Python's render() as
// keywords and a render scene file as keys (renderOptionTable). Unset
// (std::nullopt, NaN, -1, 0 where said) means "the default's own".
struct RenderOptions {
    int width = defaults::kWidth;
    int height = defaults::kHeight;
    std::optional<glm::vec3> eye, target;  // metres, in the data's coordinates; unset: the automatic camera
    glm::vec3 up{0.0f, 1.0f, 0.0f};         // the data's up axis (turned to +y)
    float fov = defaults::kFovYDegrees;
    // The automatic camera's view direction and distance (0: fitted to the particles).
    float azimuth = defaults::kAutoAzimuthDegrees, elevation = defaults::kAutoElevationDegrees, distance = 0.0f;
    float radius = 0.0f;                         // metres; 0 = the file's radii, else estimated (resolveRadius)
    float hPerSpacing = defaults::kHPerSpacing;  // a file's smoothing length h, in particle spacings
    std::string view = "final";
    std::string filter = defaults::kFilterName;
    int iterations = -1;  // -1 = the filter's default
    bool separable = false;
    std::string material = defaults::kMaterialName;  // a preset, or one per fluid, comma-separated
    // Custom material values over the preset(s), for every fluid; unset / NaN: the preset's.
    std::optional<glm::vec3> fluidColor;  // linear RGB
    std::optional<glm::vec3> absorption;  // Beer-Lambert k per channel, 1/m
    float ior = NAN, refraction = NAN, specular = NAN, shininess = NAN, opacity = NAN;
    std::optional<glm::vec3> light;  // toward the key light, world space; unset: ShadingParams' default
    // auto: studio for a still camera, floor when the camera moves (the caller decides).
    std::string background = "auto";
    // The HDR environment map (readEnvironmentMap; empty: the procedural sky),
    // its turn about the vertical in degrees and its radiance multiplier.
    std::string environment;
    float environmentRotation = 0.0f;
    float environmentIntensity = 1.0f;
    // A backdrop (readBackdrop, docs/compositing.md): another renderer's picture
    // of the set (colour, and its depth in the same file or in backdropDepth),
    // made by this camera at this size, drawn in the studio's place; its depth
    // values' meaning (parseBackdropDepth). Empty: the studio.
    // A run of '#' in either file's name makes a sequence, as Blender names an
    // animation's frames: frame i of a sequence is drawn over the files whose
    // last run of '#' is backdropFirst + i, zero-padded to the run's length.
    std::string backdrop;
    std::string backdropDepth;
    std::string backdropDepthKind = "linear";
    int backdropFirst = 1;  // frame number of the sequence's first file (Blender's default start)
    // Scene geometry drawn around the liquid (readGeometry, docs/geometry.md):
    // each a mesh file, a SPlisHSPlasH scene file, or geometry objects as JSON.
    std::vector<std::string> geometry;
    // on: containers' walls between the camera and the liquid are not drawn
    // (GeometryObject::cutaway: a SPlisHSPlasH scene's walls, a simulation's
    // domain); off: every wall drawn.
    std::string cutAway = "on";
    // The key light's shadows (RenderSettings::shadows, docs/geometry.md#shadows):
    // auto (on with visible scene geometry), on, off.
    std::string shadows = "auto";
    // DualSPHysics' boundary particles (Type 0 to 2, include/meniscus/boundary.h)
    // of a frame that has the Type attribute: walls (meshed, drawn as opaque
    // scene geometry), liquid (drawn as the liquid) or hidden (dropped).
    std::string boundaryParticles = "walls";
    // The stages' own parameters (params.h), as the pipeline takes them: the
    // surface noise and foam, the whitening, the spray, the silhouette
    // (each off unless its `enabled`), the thickness floor, the ray cast's
    // steps. The filter, the shading, the hole filling and whether the ray
    // cast runs come from the options above and below, not from here.
    StageParams stages;
    // Anisotropic kernels (Yu & Turk 2013): on or off.
    std::string anisotropy = AnisotropyParams{}.enabled ? "on" : "off";
    AnisotropyParams anisotropyParams;
    // Hole filling (docs/pipeline.md#hole-filling): the widest gap filled,
    // radii (0: off).
    float fillHoles = HoleFillParams{}.maxSpanRadii;
    // Reduced-resolution processing (docs/pipeline.md#reduced-resolution): 1, 0.5 or 0.25.
    float fluidScale = defaults::kFluidScale;
    std::string surface = "screen";  // screen (splat + smoothing), raycast (splat + SPH ray cast) or mesh
    MesherOptions mesher;
    // Several fluids (docs/pipeline.md#several-fluids): the integer attribute
    // holding each particle's fluid index; empty: the files' own `fluid`, if any.
    std::string fluidAttribute;
};

// What a render job reads and writes besides the look (render's and view's
// own options, scene files' keys): the backend, more inputs, the movie, the
// moving camera, the cluster's shares (jobOptionTable). The input and the
// output are the command's positional and -o.
struct JobOptions {
    std::string backend = "auto";  // cpu, gl or auto
    // Diffuse particles (`meniscus whitewater`'s output) drawn as a layer:
    // a file, or a pattern filled with each input frame's number. Empty: none.
    std::string diffuse;
    // Several fluids from one input per fluid: each a file or sequence
    // matching the input frame for frame, fluid 1, 2, ...
    std::vector<std::string> moreFluids;
    // Only the particles that match (parseSelection), e.g. "Type==fluid"; empty: all.
    std::string select;
    // An .mp4 output's frame rate and quality, and a moving camera's clock.
    double fps = defaults::kVideoFps;
    int crf = defaults::kVideoCrf;
    double duration = -1.0;  // a simulation scene as the input: seconds to simulate; < 0: the scene's
    bool renumber = false;   // output frames numbered 0, 1, ...
    std::string onError = "stop";  // a frame's error: stop or skip
    bool resume = false;     // leave frames whose outputs are complete
    std::string shard;       // "I/N": only the I-th of N contiguous shares of the frames; empty: all
    std::string split = "auto";  // under mpirun: frames, particles, or auto
    // Camera motion: degrees per second about +y through the target; one whole
    // turn over the sequence; a key-framed path (a JSON file or the JSON text);
    // a single input file rendered as this many frames (0: as many as the input has).
    double orbit = 0.0;
    bool turntable = false;
    std::string cameraPath;
    int frames = 0;
};

// `mesh`'s own options besides the mesher's, --h-per-spacing and --select
// (meshOptionTable). The input and the output are the command's positional
// and -o.
struct MeshOptions {
    float radius = 0.0f;  // metres; 0 = the file's radii, else estimated (resolveRadius)
    bool stats = false;   // each frame's phases, sizes and peak memory on stderr
    bool resume = false;  // leave outputs that are already complete (convert's --resume too)
    // Particle attributes interpolated onto the vertices (interpolateAttributes),
    // each a name or a comma-separated list of names.
    std::vector<std::string> interpolate;
    // Weighted Laplacian smoothing (smoothMesh): iterations (0: none) and
    // whether the particles' weights keep splashes (on) or not (off).
    int smoothingIterations = 0;
    std::string smoothingWeights = "on";
};

// `simulate`'s options besides the images' look (simulateOptionTable); view
// --simulate takes the solver, Python's simulate() the scene's overrides.
// Unset ones (< 0, 0, "") leave the scene's (applySimulateOptions).
struct SimulateOptions {
    double duration = -1.0;  // simulated seconds; < 0: the scene's
    double fps = -1.0;       // frames per simulated second; < 0: the scene's
    float radius = 0.0f;     // metres; 0: the scene's
    std::string solver;      // dfsph, sph, pbf or ballistic; empty: the scene's
    bool resume = false;     // go on after the last frame already written
    bool stats = false;      // each frame's steps, iterations and phase times on stderr
    std::string render;      // also render each frame to this pattern or movie; empty: no images
};

// `view`'s own options besides the look and the camera (viewerOptionTable):
// a simulation shown live instead of an input, what is saved on exit, and
// a scripted run for tests and scripts.
struct ViewerOptions {
    std::string simulate;          // a simulation scene (.json) run live; empty: show the input
    std::string screenshot;        // on exit: the picture the window shows, without the panels (.png)
    std::string screenshotWindow;  // on exit: the whole window, panels included (.png)
    int frames = 0;                // > 0: render and show this many frames, then exit
    std::string inputScript;       // input events replayed one per frame (runView)
};

// `whitewater`'s options (whitewaterOptionTable): the fluid sequence's radius
// and rate, and the generator's parameters (WhitewaterParams, whose
// initialisers give the defaults; whitewaterParams makes them). The lists
// hold their numbers as given, checked there.
struct WhitewaterOptions {
    float radius = 0.0f;  // metres; 0 = estimated from the first frame
    double fps = 0.0;     // frames per second of the input; 0 = estimated from its first two frames
    // Potential limits: trapped air min, max, wave crest min, max, kinetic energy min, max; empty: automatic.
    std::vector<float> limits;
    float scale = WhitewaterParams{}.scale;
    float trappedAirRate = WhitewaterParams{}.trappedAirRate;
    float waveCrestRate = WhitewaterParams{}.waveCrestRate;
    std::vector<float> lifetime{WhitewaterParams{}.lifetimeMinS, WhitewaterParams{}.lifetimeMaxS};  // min, max, s
    float buoyancy = WhitewaterParams{}.buoyancy;
    float drag = WhitewaterParams{}.drag;
    std::vector<float> gravity{WhitewaterParams{}.gravity.x, WhitewaterParams{}.gravity.y,
                               WhitewaterParams{}.gravity.z};  // m/s^2
    std::vector<float> box;  // min x, y, z, max x, y, z, metres; empty: the fluid's region so far
    int sprayBelow = WhitewaterParams{}.sprayBelow;
    int bubbleAbove = WhitewaterParams{}.bubbleAbove;
    std::uint64_t maxParticles = WhitewaterParams{}.maxParticles;
    std::uint64_t seed = WhitewaterParams{}.seed;
    bool resume = false;  // leave output frames that are already complete
};

// ---------------------------------------------------------------- the table

// Where an option's value lands in its options struct.
// A list of numbers (std::vector<float>) holds OptionLimits::count of them,
// or none (unset).
using OptionRef = std::variant<bool*, int*, float*, double*, std::string*, std::vector<std::string>*,
                               std::optional<glm::vec3>*, glm::vec3*, std::uint64_t*, std::vector<float>*>;

// A value given by a face that has types (Python, JSON): a whole number, a
// number, true/false, a text, three numbers, a list of texts, or a list of
// numbers.
using OptionValue =
    std::variant<bool, std::int64_t, double, std::string, glm::vec3, std::vector<std::string>, std::vector<double>>;

// What values an option accepts.
struct OptionLimits {
    double min = NAN, max = NAN;       // a number's range (each of a vector's), inclusive; NaN: unbounded
    bool positive = false;             // > 0
    double unset = NAN;                // a number meaning "not given" (--iterations -1): always accepted
    std::vector<std::string> choices;  // a text's accepted values; empty: any text
    bool emptyUnset = false;           // a text's "" means "not given" (--solver: the scene's)
    std::size_t count = 0;             // a list of numbers: how many it holds when given
};

// How the viewer's panels show an option (apps/meniscus/view_ui.cpp): under
// which header, a number's slider range, and when it is shown. A bool is a
// checkbox, a text with two choices on/off a checkbox too, a text or number
// with choices a combo, a number a slider, three numbers a drag (a colour
// picker for a colour).
struct PanelWidget {
    std::string panel;                 // the header it is under; "" : not in the panels
    float lo = 0.0f, hi = 0.0f;        // a slider's range (times the value in use when `relative`)
    bool log = false, relative = false, colour = false;
    std::vector<std::string> choices;  // a combo's items when they differ from the option's
    std::string shownWith;             // "surface=raycast": only while that option has that value
};

// One option: everything its faces need.
template <class Options>
struct OptionSpec {
    std::string name;   // "noise-bump"
    OptionGroup group;
    std::string unit;   // "m", "radii", "m/s", "degrees", "px", "1/m", "kg/m^3", "s"; "" for none
    std::string help;   // one line (the unit said in it)
    OptionRef (*field)(Options&);
    OptionLimits limits;
    PanelWidget widget;
    // A bool given as a bare flag (--noise) rather than on/off; a value
    // without a default worth printing (a sentinel such as --iterations -1);
    // a path (a scene file's is relative to the file's folder).
    bool flag = false, noDefault = false, path = false;
};

using RenderOptionSpec = OptionSpec<RenderOptions>;
using MesherOptionSpec = OptionSpec<MesherOptions>;
using JobOptionSpec = OptionSpec<JobOptions>;
using MeshOptionSpec = OptionSpec<MeshOptions>;
using SimulateOptionSpec = OptionSpec<SimulateOptions>;
using WhitewaterOptionSpec = OptionSpec<WhitewaterOptions>;
using ViewerOptionSpec = OptionSpec<ViewerOptions>;

// `render`'s look, camera and surface options, in the order --help lists
// them inside a group. The mesher's options (mesherOptionTable) are not in
// it; render adds both.
std::span<const RenderOptionSpec> renderOptionTable();
// The mesher's: cube-size, iso, field, support, block.
std::span<const MesherOptionSpec> mesherOptionTable();
// The job's: backend, diffuse, fluid, select, fps, crf, duration, renumber,
// on-error, resume, shard, split, orbit, turntable, camera-path, frames.
std::span<const JobOptionSpec> jobOptionTable();
// mesh's: radius, stats, resume (convert binds its resume too).
std::span<const MeshOptionSpec> meshOptionTable();
// simulate's: duration, fps, radius, solver, resume, stats, render.
std::span<const SimulateOptionSpec> simulateOptionTable();
// `view`'s own: simulate, screenshot, screenshot-window, frames, input-script.
std::span<const ViewerOptionSpec> viewerOptionTable();
// whitewater's: radius, fps, limits, scale, trapped-air-rate, wave-crest-rate,
// lifetime, buoyancy, drag, gravity, box, spray-below, bubble-above,
// max-particles, seed, resume.
std::span<const WhitewaterOptionSpec> whitewaterOptionTable();

// "noise_bump" or "noise-bump" -> the table's entry; nullptr when none.
const RenderOptionSpec* findRenderOption(std::string_view name);
const MesherOptionSpec* findMesherOption(std::string_view name);
const JobOptionSpec* findJobOption(std::string_view name);
// "noise_bump" (Python's and scene files' spelling of "noise-bump").
std::string keywordName(std::string_view optionName);
// "noise-bump" (the tables' spelling of "noise_bump").
std::string optionName(std::string_view keyword);
// The row of `table` named `name` ('-' or '_' alike); nullptr when none.
template <class Options>
const OptionSpec<Options>* findIn(std::span<const OptionSpec<Options>> table, std::string_view name) {
    const std::string n = optionName(name);
    for (const OptionSpec<Options>& s : table)
        if (s.name == n) return &s;
    return nullptr;
}
// A widget's label: "noise bump (sprite radii)", "radius (m)".
std::string widgetLabel(const std::string& optionName, const std::string& unit);

// The value's text as the command line writes it ("0.25", "on", "0,0,1";
// "" for an unset vector; "true"/"false" for a flag).
std::string optionText(const OptionRef& ref);
// The default's text as --help shows it; "" when the spec has noDefault.
template <class Options>
std::string defaultText(const OptionSpec<Options>& spec) {
    if (spec.noDefault) return {};
    Options fresh;
    return optionText(spec.field(fresh));
}

// An error naming --NAME unless `ref` holds a value `spec`'s range and
// choices accept (an unset value always passes).
Status checkOptionValue(const std::string& name, const OptionRef& ref, const OptionLimits& limits);
template <class Options>
Status checkOption(const OptionSpec<Options>& spec, Options& o) {
    return checkOptionValue(spec.name, spec.field(o), spec.limits);
}

// Sets one option from a typed value (a number where a number is wanted, a
// bool for a flag or for on/off, three numbers for a vector, a text for a
// text); an error naming the option when the type, range or choice is wrong.
// `o` is unchanged on an error.
Status setOptionValue(const std::string& name, const OptionRef& ref, const OptionValue& value,
                      const OptionLimits& limits);
template <class Options>
Status setOption(const OptionSpec<Options>& spec, Options& o, const OptionValue& value) {
    return setOptionValue(spec.name, spec.field(o), value, spec.limits);
}
// By name, over both tables (render's, then the mesher's inside o.mesher);
// an error listing the names when there is no such option.
Status setRenderOption(RenderOptions& o, std::string_view name, const OptionValue& value);
// By name in the job's table.
Status setJobOption(JobOptions& o, std::string_view name, const OptionValue& value);
// By name in `table`; an error listing the table's names when there is no such option.
template <class Options>
Status setOptionIn(std::span<const OptionSpec<Options>> table, Options& o, std::string_view name,
                   const OptionValue& value) {
    if (const OptionSpec<Options>* s = findIn(table, name)) return setOption(*s, o, value);
    std::string names;
    for (const OptionSpec<Options>& s : table) names += (names.empty() ? "" : ", ") + keywordName(s.name);
    return makeError("", "unknown option '" + std::string(name) + "' (the options are: " + names + ")");
}
// Every option of `table` in its range; the first error names the option.
template <class Options>
Status checkOptions(std::span<const OptionSpec<Options>> table, const Options& o) {
    Options copy = o;
    for (const OptionSpec<Options>& s : table)
        if (auto st = checkOption(s, copy); !st) return st;
    return okStatus();
}

// "x,y,z" as the command line writes it ("0,0,1").
std::string vec3Text(const glm::vec3& v);
// "x,y,z": three finite numbers, or nothing.
std::optional<glm::vec3> parseVec3(const std::string& text);

// ---------------------------------------------------------------- policies

// Every option in its range (the tables' checks, as the CLI applies them);
// the first error names the option.
Status checkRenderOptions(const RenderOptions& o);

// The pipeline settings the options name; camera, radius and studio come
// later (chooseCamera, resolveRadius). An error names the option at fault.
// `diffuse`: a diffuse layer will be drawn (so view spray needs no spray).
Result<RenderSettings> renderSettings(const RenderOptions& o, bool diffuse = false);

// The scene geometry of `specs` (RenderOptions::geometry: readGeometry of
// each, appended in order), turned from the data's up axis to +y as the
// particles are; `cutAway` false (--cut-away off) draws containers whole. The last list read is kept (keyed by the texts, the files'
// sizes and modification times, and the axis), so asking again is free.
// Errors name the option and the file.
// The environment map of --environment (readEnvironmentMap), the last one read
// kept while the file stays the same.
Result<std::shared_ptr<const EnvironmentImage>> renderEnvironment(const std::string& path);
// The backdrop of --backdrop (readBackdrop), the last one read kept while its
// files and depth kind stay the same.
Result<std::shared_ptr<const BackdropImage>> renderBackdrop(const std::string& color, const std::string& depth,
                                                            const std::string& depthKind);
// A backdrop sequence (RenderOptions::backdrop or backdropDepth naming a run
// of '#'): whether `o` has one; the name of the file of frame number
// `number` (the last run of '#' replaced by it, zero-padded to the run's
// length; a name without '#' is returned as it is); and the backdrop of
// frame i of a render (backdropFirst + i) read (renderBackdrop) and checked
// against the picture's size into settings.scene.backdrop. Errors name the
// option, the frame and the file.
bool backdropSequence(const RenderOptions& o);
std::string backdropFrameName(const std::string& pattern, std::int64_t number);
Status backdropForFrame(const RenderOptions& o, std::size_t i, RenderSettings& settings);

Result<std::shared_ptr<const SceneGeometry>> renderGeometry(const std::vector<std::string>& specs,
                                                            const glm::vec3& upAxis, bool cutAway = true);
// Scene geometry in the automatic camera's framing and the studio's box (the
// CLI, Python and the viewer alike): each visible object's box is added to
// *studioBox (the floor goes under a tank, not through it) and its corners to
// `samplePoints`, each as many times as a hundredth of the points (so the
// framing does not leave them out as outliers); a container (cut-away) only
// across its width and up to a quarter above the points' top, so a tall tank
// does not make the water small. Null geometry: nothing changes.
void frameGeometry(const SceneGeometry* geometry, std::vector<glm::vec3>& samplePoints, Bounds* studioBox);

// `settings`' geometry with `more`'s objects after its own (a simulation's
// colliders and domain); `cutAway` false draws every wall of them.
void addGeometry(RenderSettings& settings, SceneGeometry more, bool cutAway);

// A frame read from a file made ready for rendering with the options
// (render, view and every face alike): when it has DualSPHysics' Type
// attribute and --boundary-particles is not liquid, its boundary particles
// are taken out of `set` (takeBoundaryParticles); as walls they are meshed
// (the fixed ones once per sequence, kept by their positions) and the
// returned geometry is `base` with their objects after its own, else `base`
// itself. The fixed walls are a cut-away container under --cut-away on.
// Errors name `name` (the file).
Result<std::shared_ptr<const SceneGeometry>> prepareBoundary(ParticleSet& set, const RenderOptions& o,
                                                             std::shared_ptr<const SceneGeometry> base,
                                                             const std::string& name);

// The scene with the options' overrides (duration, fps, radius, solver; unset
// ones leave the scene's); an error naming the option at fault.
Status applySimulateOptions(const SimulateOptions& o, sim::Scene& scene);

// The whitewater generator's parameters the options name (the lists turned
// into limits, lifetime, gravity and the box); an error naming the option at
// fault, or the generator's own check (sim::checkWhitewaterParams).
Result<WhitewaterParams> whitewaterParams(const WhitewaterOptions& o);

// The mesher's parameters for particles of radius `radiusM`.
MeshParams mesherParams(const MesherOptions& o, float radiusM, int threads);

// The turn that takes a data set's up axis to +y, the renderer's up (the
// studio's floor, the sky, the automatic camera): Rodrigues' rotation about
// up x y, exact for the axes (z-up: (x, y, z) -> (x, z, -y)).
struct UpRotation {
    bool identity = true;
    glm::vec3 axis{1.0f, 0.0f, 0.0f};  // unit
    float c = 1.0f, s = 0.0f;          // cos, sin of the angle
    glm::vec3 apply(const glm::vec3& v) const;
    // The turn back (the renderer's coordinates to the data's).
    UpRotation inverse() const;
};
// An error unless `up` is a finite vector, not zero.
Result<UpRotation> upRotation(const glm::vec3& up);

// The radius policy, said once: the option's radius when given (> 0), else
// the particles' own (their radius attribute, or a smoothing length turned
// into one), else estimated from the bulk number density (defaultRadius).
// `estimate` computes the last two; *note gets the line saying where the
// radius came from ("" for a given one). An error when the result is out of
// range (checkRadius), naming the option or saying to set it.
Result<float> resolveRadius(float optionRadius, const std::function<RadiusEstimate()>& estimate,
                            std::string* note = nullptr);

// The positions of one frame sampled for the automatic camera (an even
// stride, at most defaults::kSequenceFramePoints) appended to `samples`.
void sampleFramePoints(std::span<const glm::vec3> positions, std::vector<glm::vec3>& samples);

// The camera the options name: eye and target (in the data's coordinates,
// turned by up), or auto-framed on `samplePoints` (in the renderer's) from
// azimuth, elevation and distance. The sampled particles left outside the
// automatic frame are counted in *outsideCount.
Result<Camera> chooseCamera(const RenderOptions& o, std::span<const glm::vec3> samplePoints, float radius,
                            std::size_t* outsideCount = nullptr);

}  // namespace meniscus
