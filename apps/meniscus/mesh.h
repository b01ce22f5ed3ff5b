// `meniscus mesh`: particles to a triangle mesh file (the isosurface path,
// include/meniscus/surface.h), one frame or a numbered sequence.
#pragma once

#include <string>

#include "meniscus/params.h"

namespace CLI {
class App;
}

namespace meniscus::app {

struct MeshOptions {
    std::string input;
    std::string output;
    float radius = 0.0f;  // metres; 0 = estimate from the first frame
    float cubeSize = defaults::kCubeSizeRadii;
    float iso = defaults::kSurfaceIso;
    std::string field = "sph";
    float support = 0.0f;  // radii; 0 = the field's default
    int block = defaults::kBlockCubes;
    bool stats = false;
};

// Adds the subcommand and its options to `app`.
CLI::App* addMeshCommand(CLI::App& app, MeshOptions& o);
// Runs it; `threads` = the global --threads (0 = all cores). Returns the exit code.
int runMesh(const MeshOptions& o, int threads);

}  // namespace meniscus::app
