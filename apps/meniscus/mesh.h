// `meniscus mesh`: particles to a triangle mesh file (the isosurface path,
// include/meniscus/surface.h), one frame or a numbered sequence.
#pragma once

#include <string>

#include "common.h"
#include "meniscus/params.h"
#include "meniscus/result.h"

namespace CLI {
class App;
}

namespace meniscus::app {

// The library's mesh options (radius, stats: meshOptionTable), the mesher's,
// and the input and output.
struct MeshJob : meniscus::MeshOptions {
    std::string input;
    std::string output;
    float hPerSpacing = defaults::kHPerSpacing;  // a file's smoothing length h, in particle spacings
    std::string select;  // --select: only the particles that match (parseSelection); empty: all
    MesherOptions mesher;
};


// Adds the subcommand and its options to `app`.
CLI::App* addMeshCommand(CLI::App& app, MeshJob& o);
// Runs it; `threads` = the global --threads (0 = all cores). Returns the exit code.
int runMesh(const MeshJob& o, int threads);

}  // namespace meniscus::app
