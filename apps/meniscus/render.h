// `meniscus render` (and `demo`): a frame or a sequence to PNG, EXR or an MP4
// movie, with the long-run options (--on-error, --resume, --renumber) and a
// progress line per frame.
#pragma once

#include "common.h"
#include "meniscus/types.h"

namespace CLI {
class App;
}

namespace meniscus::app {

// -o's movie options (--fps, --crf) and the long-run options on `cmd`.
void addSequenceOptions(CLI::App* cmd, RenderJob& o);
// Renders o.input (or `embedded`, the demo frame) to o.output. Returns the exit code.
int runRender(const RenderJob& o, const ParticleSet* embedded);

}  // namespace meniscus::app
