// `render`'s command line, declared in one place: main.cpp parses it, and the
// viewer builds a private copy to read and write scene files (whose keys are
// `render`'s options) with the same checks.
#pragma once

#include "common.h"

namespace CLI {
class App;
}

namespace meniscus::app {

// Adds the `render` subcommand with every option, bound to `o`, to `parent`.
CLI::App* addRenderCommand(CLI::App& parent, RenderJob& o);

}  // namespace meniscus::app
