// `meniscus convert`: particle files from any format Meniscus reads to any it
// writes, attributes kept, so the tool also moves data between SPlisHSPlasH,
// DualSPHysics, PySPH, Houdini and ParaView.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace meniscus::app {

struct ConvertOptions {
    std::string input;
    std::string output;
    std::string pvd;     // --pvd: a ParaView collection of the outputs
    std::string select;  // --select: only the particles that match
    bool resume = false; // --resume: outputs already complete stay (mesh's option, meshOptionTable)
};

CLI::App* addConvertCommand(CLI::App& app, ConvertOptions& o);
int runConvert(const ConvertOptions& o);

}  // namespace meniscus::app
