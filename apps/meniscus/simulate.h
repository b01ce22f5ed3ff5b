// `meniscus simulate`: a scene file (scenes/*.json, docs/scenes.md) to a
// numbered particle sequence with id, velocity, density and pressure.
#pragma once

#include <string>

namespace CLI {
class App;
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
};

CLI::App* addSimulateCommand(CLI::App& app, SimulateOptions& o);
int runSimulate(const SimulateOptions& o);

}  // namespace meniscus::app
