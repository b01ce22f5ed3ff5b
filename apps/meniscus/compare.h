// `meniscus compare`: the thesis's closing comparison (§4.2 vs §4.1): one
// frame rendered by the screen-space path and by the mesh path, side by side,
// each labelled with its time.
#pragma once

#include "common.h"

namespace CLI {
class App;
}

namespace meniscus::app {

CLI::App* addCompareCommand(CLI::App& app, RenderJob& o);
int runCompare(const RenderJob& o);

}  // namespace meniscus::app
