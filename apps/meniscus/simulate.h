// `meniscus simulate`: a scene file (scenes/*.json, docs/scenes.md) to a
// numbered particle sequence with id, velocity, density and pressure, and
// with --render each frame as an image too.
#pragma once

#include <string>

#include "common.h"
#include "meniscus/result.h"
#include "meniscus/sim.h"

namespace CLI {
class App;
class Option;
}

namespace meniscus::app {

struct SimulateOptions {
    std::string scene;
    std::string output;
    double duration = -1.0;  // s; < 0: the scene's
    double fps = -1.0;       // frames per simulated second; < 0: the scene's
    float radius = 0.0f;     // m; 0: the scene's
    std::string solver;      // empty: the scene's
    bool resume = false;
    bool stats = false;
    std::string render;   // image pattern (out/img_%04d.png or .exr); empty: no images
    RenderJob image;  // the images' size, camera, look and backend; radius unused (the simulation's)
};

CLI::App* addSimulateCommand(CLI::App& app, SimulateOptions& o);
// --solver (dfsph, sph, pbf, ballistic) on `cmd`; view --simulate has it too.
CLI::Option* addSolverOption(CLI::App* cmd, std::string& solver);
int runSimulate(const SimulateOptions& o);

// The scene file with the options' overrides (duration, fps, radius, solver;
// unset ones leave the scene's). `meniscus view --simulate` reads it so too.
Result<sim::Scene> sceneFromOptions(const SimulateOptions& o);
// The scene's domain (the tank; particles never leave it) as a Bounds.
Bounds domainBounds(const sim::Scene& scene);

}  // namespace meniscus::app
