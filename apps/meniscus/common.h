// What the subcommands that render (render, demo, view) share: the one-line
// messages, the render options and their parsing, the frames an input names,
// and the settings fixed once for a whole sequence.
#pragma once

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/camera_path.h"
#include "meniscus/params.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace CLI {
class App;
}

namespace meniscus::app {

// "meniscus: error: LINE" on stderr; returns the exit code 1.
int fail(const std::string& line);
void printWarnings(const ParticleSet& set);

bool isPng(const std::string& path);
bool isExr(const std::string& path);
bool isMp4(const std::string& path);

// How the isosurface path meshes (mesh, and render/compare with --surface mesh).
struct MesherOptions {
    float cubeSize = defaults::kCubeSizeRadii;
    float iso = defaults::kSurfaceIso;
    std::string field = "sph";
    float support = 0.0f;  // radii; 0 = the field's default
    int block = defaults::kBlockCubes;
};

struct RenderOptions {
    std::string input;
    std::string output;
    int width = defaults::kWidth;
    int height = defaults::kHeight;
    std::string eye, target, up = "0,1,0";
    float fov = defaults::kFovYDegrees;
    // The automatic camera's view direction and distance (0: fitted to the particles).
    float azimuth = defaults::kAutoAzimuthDegrees, elevation = defaults::kAutoElevationDegrees, distance = 0.0f;
    float radius = 0.0f;  // 0 = estimate
    float hPerSpacing = defaults::kHPerSpacing;  // a file's smoothing length h, in particle spacings
    std::string view = "final";
    std::string filter = defaults::kFilterName;
    int iterations = -1;  // -1 = the filter's default
    bool separable = false;
    std::string material = defaults::kMaterialName;
    // Custom material values over the preset(s), for every fluid; empty / NaN: the preset's.
    std::string fluidColor, absorption;  // "r,g,b": linear RGB; Beer-Lambert k per channel, 1/m
    float ior = NAN, refraction = NAN, specular = NAN, shininess = NAN, opacity = NAN;
    std::string light;  // "x,y,z": toward the key light, world space; empty: the default
    // auto: studio for a still camera, floor when the camera moves (runRender).
    std::string background = "auto";
    std::string backend = "auto";
    // Surface noise and foam (docs/pipeline.md#noise-and-foam): off unless --noise.
    bool noise = false;
    NoiseParams noiseParams;
    // Velocity whitening (docs/pipeline.md#noise-and-foam): off unless --whiten.
    bool whiten = false;
    WhiteningParams whitening;
    // Spray drops (docs/pipeline.md#classification): off unless --spray.
    bool spray = false;
    SprayParams sprayParams;
    // Silhouette reduction (docs/pipeline.md#silhouette-reduction): off unless
    // --silhouette.
    bool silhouette = false;
    SilhouetteParams silhouetteParams;
    // Anisotropic kernels (Yu & Turk 2013): --anisotropy on|off.
    std::string anisotropy = AnisotropyParams{}.enabled ? "on" : "off";
    AnisotropyParams anisotropyParams;
    // Hole filling (docs/pipeline.md#hole-filling): the widest gap filled, radii (0: off); the
    // thin-liquid floor, radii.
    float fillHoles = HoleFillParams{}.maxSpanRadii;
    float minThickness = ThicknessParams{}.minRadii;
    // Reduced-resolution processing (docs/pipeline.md#reduced-resolution): 1,
    // 0.5 or 0.25.
    float fluidScale = defaults::kFluidScale;
    // Diffuse particles (`meniscus whitewater`'s output) drawn as a layer:
    // a file, or a pattern filled with each input frame's number. Empty: none.
    std::string diffuse;
    std::string surface = "screen";  // screen (splat + smoothing), raycast (splat + SPH ray cast) or mesh
    RaycastParams raycastParams;     // --surface raycast (iso and support from --iso, --support)
    // Several fluids (docs/pipeline.md#several-fluids): the integer attribute
    // holding each particle's fluid index (0 .. 3); empty: the files' own
    // `fluid`, if any.
    std::string fluidAttribute;
    // Several fluids from one input per fluid (--fluid, repeatable): each a
    // file or sequence matching the input frame for frame, fluid 1, 2, ...
    std::vector<std::string> moreFluids;
    // Only the particles that match (--select, parseSelection), e.g.
    // "Type==fluid"; empty: all of them.
    std::string select;
    MesherOptions mesher;
    // Long runs (render): an .mp4 output's frame rate and quality; output
    // frames numbered 0, 1, ... (--renumber); on a frame's error stop or skip
    // it (--on-error); leave frames whose outputs are complete (--resume).
    double fps = defaults::kVideoFps;
    int crf = defaults::kVideoCrf;
    // A simulation scene as the input: seconds to simulate; < 0: the scene's.
    double duration = -1.0;
    bool renumber = false;
    std::string onError = "stop";
    bool resume = false;
    // Frame-parallel runs: "I/N" renders only the I-th of N
    // contiguous shares of the frames (job arrays); empty: all of them.
    std::string shard;
    // Under mpirun: split the frames of a sequence over the
    // processes ("frames"), or the particles of each frame, composited
    // sort-last ("particles"); "auto": frames for a sequence, particles for
    // one frame.
    std::string split = "auto";
    // Camera motion (render): turn about +y through the target, degrees per
    // second of sequence time; one whole turn over the sequence; a key-framed
    // path (--camera-path: a JSON file or the JSON array itself); a single
    // input file rendered as this many frames (0: as many as the input has).
    double orbit = 0.0;
    bool turntable = false;
    std::string cameraPath;
    std::size_t frames = 0;
    // A render scene file's name and, per option it set, its key (errors name the key).
    std::string sceneFile;
    std::vector<std::pair<std::string, std::string>> sceneKeys;
};

// Size, camera, radius and look (--width ... --background) on `cmd`; without
// --radius when `radiusOption` is false (simulate: the images use the
// simulation's own radius, which its --radius sets).
void addCameraOptions(CLI::App* cmd, RenderOptions& o, bool radiusOption = true);
// --fluid-attribute's alternative, --fluid (one more input per fluid), and
// --select (addSelectOption), the options on what each input frame holds, on `cmd`.
void addFluidInputOption(CLI::App* cmd, RenderOptions& o);
// --select EXPR on `cmd` (render, view, mesh, compare, whitewater): which particles of each
// file are drawn (parseSelection, include/meniscus/particles.h).
void addSelectOption(CLI::App* cmd, std::string& select);
// Particles of `more` appended to `set` as fluid `fluid` (set's own become
// fluid 0 when it has no fluid attribute yet): attributes both have with the
// same type are joined, others left out with a warning in set.warnings; ids
// are offset by fluid * 2^40 so the fluids' ids stay apart.
void appendFluid(ParticleSet& set, const ParticleSet& more, int fluid);
// --backend on `cmd`.
void addBackendOption(CLI::App* cmd, RenderOptions& o);

// The pipeline settings named by the options (camera and radius come later).
Result<RenderSettings> settingsFromOptions(const RenderOptions& o);

// A rendered frame to `path`: .exr with every AOV, else PNG of the colour
// (with alpha when `withAlpha`); a temporary name renamed, so never partial.
Status writeImage(const std::string& path, const Aovs& aovs, bool withAlpha);

// The frames to render: the files an input names, or the one embedded frame.
// The turn that takes a data set's up axis to +y, the renderer's up (the
// studio's floor, the sky, the automatic camera): Rodrigues' rotation about
// up x y, exact for the axes (z-up: (x, y, z) -> (x, z, -y)).
struct UpRotation {
    bool identity = true;
    glm::vec3 axis{1.0f, 0.0f, 0.0f};  // unit
    float c = 1.0f, s = 0.0f;          // cos, sin of the angle
    glm::vec3 apply(const glm::vec3& v) const;
    // Positions and the velocity attribute of `set` (other attributes are not directions).
    void apply(ParticleSet& set) const;
};
// --up X,Y,Z: an error unless three finite numbers, not all zero.
Result<UpRotation> upRotation(const std::string& up);

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
    Status addFluids(const RenderOptions& o);

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
Result<Renderer> makeRenderer(const RenderOptions& o);

// --camera-path's keys (readCameraPath) turned by --up into the renderer's
// coordinates, as --eye and --target are; empty without --camera-path.
Result<std::vector<CameraKey>> cameraPathFromOptions(const RenderOptions& o);

// "x,y,z": three finite numbers, or nothing.
std::optional<glm::vec3> parseVec3(const std::string& text);

// The camera for a whole sequence (fixForSequence; the Python module's
// render): the user's (--eye and --target in the data's frame, turned by
// --up; --camera-path's first key), or auto-framed on `samplePoints` (the
// particles of a few frames: first, last, three between). The sampled
// particles left outside the automatic frame are counted in *outsideCount,
// or said on stderr without it.
Result<Camera> chooseCamera(const RenderOptions& o, std::span<const glm::vec3> samplePoints, float radius,
                            std::size_t* outsideCount = nullptr);
// The positions of one frame fixForSequence samples for the automatic camera
// (an even stride, at most defaults::kSequenceFramePoints).
void sampleFramePoints(std::span<const glm::vec3> positions, std::vector<glm::vec3>& samples);

// Fixes radius, camera (the options', the camera path's first key, or
// auto-framed on a few frames) and the studio in `settings` once for the
// whole sequence, so an animation does not flicker; returns the first frame, already read. With --on-error skip the
// first frame that loads (its index in *firstIndex) and the frames that load.
Result<ParticleSet> fixForSequence(const RenderOptions& o, const Frames& frames, RenderSettings& settings,
                                   std::size_t* firstIndex = nullptr);

// The same for a simulation whose particles never leave `box` (its domain,
// the tank): radius `radiusM`, the camera the options' or auto-framed on the
// box's eight corners, the studio around the box. Every frame, the first
// (which an emitter may leave empty) included, is seen by the same camera.
Status fixForBox(const RenderOptions& o, const Bounds& box, float radiusM, RenderSettings& settings);

}  // namespace meniscus::app
