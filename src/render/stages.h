// The stages of a frame, declared once (docs/pipeline.md has each one's
// math): its name (the timing line and the error that names a failed stage),
// where in the frame it runs (its scope), the images it reads and writes,
// when it runs, the check of its parameters, and its call. Renderer::runStages
// checks a frame's settings through this list before anything runs, then runs
// each scope's stages in the list's order (docs/conventions.md#data-flow):
// the order is this list and nothing else. Each stage's call is one Backend
// method, a function of src/cpu/ and a shader pass of src/gl/.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/backend.h"
#include "meniscus/camera.h"
#include "meniscus/renderer.h"
#include "meniscus/result.h"
#include "meniscus/sort_last.h"

namespace meniscus {

// Where in a frame a stage runs.
enum class StageScope {
    Host,     // on the host before the images, in the Renderer (the particles' own work)
    Frame,    // once, before the surfaces (the scene)
    Surface,  // per surface (the one fluid, or each fluid's layer), at the splat's resolution
    Layer,    // per surface, at full resolution: its upsampling and shading
    Finish,   // once, after every surface (the layers composited, the passes over the picture)
    Readback  // the images render() returns, read back to the host
};

// What decides whether a stage runs: the settings, and what the particles
// add (several fluids).
struct StageWhen {
    const RenderSettings& settings;
    bool severalFluids = false;
};

// What a stage's call reads: the backend, the frame's settings, the surface
// being drawn (io.at), and what passes between the sort-last stages and the
// layers.
struct StageRun {
    Backend& backend;
    const RenderSettings& settings;
    const FrameSettings& frame;
    Camera splatCamera;          // the surface's camera (the low one at reduced resolution)
    StageIo io;                  // the surface's images; the partial, the layers' fluids
    std::string tag;             // the timing lines' prefix: "fluid 1: " for a layer, else ""
    SplatPartial partial;        // sort-last: this share's splat, then the combination
    bool handedOver = false;     // sort-last, not the root: the frame ended after the composite
    std::vector<int> fluidOfLayer;  // each layer's fluid index, in drawing order
    const struct StageDecl* stage = nullptr;  // the stage running (drive() runs its driver)
    // Runs the running stage's driver for this backend on io.
    void drive();
};

// What the Host stages read and write: the frame's settings and particles,
// and the Renderer's host state (HostFrame, render/pipeline.cpp), which they
// fill for the stages on the images.
struct HostFrame;
struct HostRun {
    const RenderSettings& settings;
    const ParticleView& all;  // every particle of the frame
    HostFrame& host;
};

// The host stages' work (render/pipeline.cpp), named by their rows.
Status hostSprayClassify(HostRun& r);
Status hostFluidSplit(HostRun& r);
Status hostSphField(HostRun& r);
Status hostShapes(HostRun& r);

struct StageDecl {
    const char* name;    // "silhouette"; per fluid prefixed "fluid 1: "
    StageScope scope;
    const char* reads;   // the images (Slot names) and inputs it reads
    const char* writes;  // the images it writes
    // Whether it runs.
    bool (*runs)(const StageWhen&);
    // Its parameters and what the chosen view needs of it; nullptr: nothing to check.
    Status (*check)(const RenderSettings&);
    // Its drivers, one per kind of backend (defined in src/cpu/<stage>.cpp
    // and src/gl/<stage>.cpp); nullptr for the Host stages (their `host`
    // work), the read-back (the Renderer's) and work on the host alone.
    const StageDriver* cpu;
    const StageDriver* gl;
    // Host work around the driver (the renderer's side of the stage: a
    // camera change, the compositor); nullptr: the driver alone. It calls
    // r.drive() where the driver runs; an error stops the frame.
    Status (*run)(StageRun&) = nullptr;
    // A Host stage's work; nullptr for the others.
    Status (*host)(HostRun&) = nullptr;
};

// Every stage, host stages (before the images) first, in the order they run.
std::span<const StageDecl> frameStages();

// The stage's driver on `b`'s kind of backend (null: none there).
const StageDriver* driverFor(const StageDecl& stage, const Backend& b);

// The checks of every stage that runs for `s`, in order: the first error.
Status checkStages(const RenderSettings& s);

// Makes every stage's driver ready on `b` (GL: compiles the stages'
// programs); the first error. Done once per backend, before its first frame
// (again is cheap: each driver's objects are made once).
Status prepareStages(Backend& b);

// Runs one stage's driver by name on `b`, on the images `io` names (a test
// of a stage on its own); an error when no stage has that name.
Status runStage(Backend& b, std::string_view name, const StageIo& io);

// Runs the Host stages that run for `when`, in the list's order; the
// first error.
Status runHostStages(const StageWhen& when, HostRun& r);

// Runs the stages of `scope` that run for `when`, in the list's order: each
// bracketed by the backend's timing when `timed`, its failure (the call's
// error, or the backend's: a GL error, out of memory) named by its stage.
// Stops early once r.handedOver.
Status runScope(StageScope scope, const StageWhen& when, StageRun& r, bool timed);

// Whether the spray stage runs: it draws the spray's drops, the diffuse
// layer's, or both.
bool drawsDrops(const RenderSettings& s);

}  // namespace meniscus
