// `meniscus whitewater`: a fluid sequence to a sequence of diffuse particles
// (spray, foam, air bubbles; Ihmsen et al. 2012, include/meniscus/whitewater.h)
// that `meniscus render --diffuse` draws as a layer.
#pragma once

#include <string>

#include "meniscus/options.h"

namespace CLI {
class App;
}

namespace meniscus::app {

// The library's whitewater options (whitewaterOptionTable), the input and
// output, and --select.
struct WhitewaterJob : meniscus::WhitewaterOptions {
    std::string input;
    std::string output;
    std::string select;  // --select: only the fluid particles that match; empty: all
};

CLI::App* addWhitewaterCommand(CLI::App& app, WhitewaterJob& o);
int runWhitewater(const WhitewaterJob& o);

}  // namespace meniscus::app
