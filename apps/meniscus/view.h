// `meniscus view`: a window showing particles rendered live by the GL backend.
#pragma once

#include <string>

#include "common.h"
#include "meniscus/types.h"
#include "simulate.h"

namespace meniscus::app {

struct ViewOptions {
    RenderJob render;    // input (empty: the embedded demo frame), size, camera, look; output/backend unused
    std::string screenshot;  // when set: the picture the window shows on exit (without the panels), saved as PNG
    std::string screenshotWindow;  // when set: the whole window on exit, panels included, saved as PNG
    int frames = 0;          // > 0: render and show this many frames, then exit (no interaction needed)
    std::string inputScript; // for tests and scripts: input events replayed one per frame (see runView)
    // --simulate: simulate.scene (with its solver; the radius is render.radius)
    // runs live on a worker thread instead of showing an input.
    SimulateJob simulate;
};

// Runs the viewer until the window is closed (Esc, Q) or `frames` are shown;
// `embedded` is the demo frame when there is no input. Returns the exit code;
// 1 with a one-line error when no window can be opened (no display, no GL 4.3)
// or the build has no viewer. `inputScript` ("drag:DX,DY;scroll:N;key:right",
// keys left, right, q, escape) adds one event to the window's own input in
// each of the first frames, through the same code as a real drag, wheel step
// or key press; with `frames`, the viewer exits only once the script is done.
int runView(const ViewOptions& options, const ParticleSet* embedded);

}  // namespace meniscus::app
