// The stages of a frame, declared once (docs/pipeline.md has each one's
// math): its name (the timing line and the error that names a failed stage),
// the images it reads and writes, when it runs, and the check of its
// parameters. Renderer::runStages checks a frame's settings through this
// list before anything runs, and runs the stages in their order
// (docs/conventions.md#data-flow); each runs as one Backend method, a
// function of src/cpu/ and a shader pass of src/gl/.
#pragma once

#include <span>

#include "meniscus/renderer.h"
#include "meniscus/result.h"

namespace meniscus {

struct StageDecl {
    const char* name;    // "silhouette"; per fluid prefixed "fluid 1: "
    const char* reads;   // the images (Slot names) and inputs it reads
    const char* writes;  // the images it writes
    // Whether it runs for these settings (the particles may add conditions:
    // several fluids, a compositor).
    bool (*runs)(const RenderSettings&);
    // Its parameters and what the chosen view needs of it; nullptr: nothing to check.
    Status (*check)(const RenderSettings&);
};

// Every stage, host stages (before the images) first, in the order they run.
std::span<const StageDecl> frameStages();

// The checks of every stage that runs for `s`, in order: the first error.
Status checkStages(const RenderSettings& s);

// Whether the spray stage runs: it draws the spray's drops, the diffuse
// layer's, or both.
bool drawsDrops(const RenderSettings& s);

}  // namespace meniscus
