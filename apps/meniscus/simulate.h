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

// The library's simulate options (simulateOptionTable: duration, fps,
// radius, solver, resume, stats, render), the scene and output, and the
// images' look.
struct SimulateJob : meniscus::SimulateOptions {
    std::string scene;
    std::string output;
    RenderJob image;  // the images' size, camera, look and backend; radius unused (the simulation's)
};

CLI::App* addSimulateCommand(CLI::App& app, SimulateJob& o);
// --solver (dfsph, sph, pbf, ballistic; simulateOptionTable's row) on `cmd`;
// view --simulate has it too.
CLI::Option* addSolverOption(CLI::App* cmd, std::string& solver);
int runSimulate(const SimulateJob& o);

// The scene file with the options' overrides (applySimulateOptions).
// `meniscus view --simulate` reads it so too.
Result<sim::Scene> sceneFromOptions(const SimulateJob& o);
// The scene's domain (the tank; particles never leave it) as a Bounds.
Bounds domainBounds(const sim::Scene& scene);

}  // namespace meniscus::app
