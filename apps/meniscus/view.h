// `meniscus view`: a window showing particles rendered live by the GL backend.
#pragma once

#include <string>

#include "common.h"
#include "meniscus/types.h"

namespace meniscus::app {

struct ViewOptions {
    RenderOptions render;    // input (empty: the embedded demo frame), size, camera, look; output/backend unused
    std::string screenshot;  // when set: what the window shows on exit, saved as PNG
    int frames = 0;          // > 0: render and show this many frames, then exit (no interaction needed)
};

// Runs the viewer until the window is closed (Esc, Q) or `frames` are shown;
// `embedded` is the demo frame when there is no input. Returns the exit code;
// 1 with a one-line error when no window can be opened (no display, no GL 4.3)
// or the build has no viewer.
int runView(const ViewOptions& options, const ParticleSet* embedded);

}  // namespace meniscus::app
