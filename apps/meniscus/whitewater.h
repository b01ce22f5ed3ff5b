// `meniscus whitewater`: a fluid sequence to a sequence of diffuse particles
// (spray, foam, air bubbles; Ihmsen et al. 2012, include/meniscus/whitewater.h)
// that `meniscus render --diffuse` draws as a layer.
#pragma once

#include <string>
#include <vector>

#include "meniscus/params.h"

namespace CLI {
class App;
}

namespace meniscus::app {

struct WhitewaterOptions {
    std::string input;
    std::string output;
    float radius = 0.0f;  // metres; 0 = estimate from the first frame
    double fps = 0.0;     // frames per second of the input; 0 = estimate from its first two frames
    std::vector<float> limits;    // ta min, max, wc min, max, ke min, max; empty = automatic
    std::vector<float> lifetime;  // min, max, s
    std::vector<float> gravity;   // x, y, z, m/s^2
    std::vector<float> box;       // min x, y, z, max x, y, z, metres
    std::string select;           // --select: only the fluid particles that match; empty: all
    WhitewaterParams params;
};

CLI::App* addWhitewaterCommand(CLI::App& app, WhitewaterOptions& o);
int runWhitewater(WhitewaterOptions o);

}  // namespace meniscus::app
