// `meniscus view`: a window showing particles rendered live by the GL backend.
#pragma once

#include <string>

#include "common.h"
#include "meniscus/types.h"
#include "simulate.h"

namespace meniscus::app {

// The viewer's options: the look and the input (as render's), its own
// (ViewerOptions: --simulate, screenshots, a scripted run), and the live
// simulation's solver and radius (the scene is ViewerOptions::simulate).
struct ViewOptions : ViewerOptions {
    RenderJob render;  // input (empty: the embedded demo frame), size, camera, look; output/backend unused
    SimulateJob live;  // the solver of --simulate (its radius is render.radius)
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
