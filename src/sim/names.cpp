// Solver names as the CLI and the scene files spell them.
#include "meniscus/sim.h"

namespace meniscus::sim {

bool solverFromName(const std::string& name, Solver* out) {
    if (name == "dfsph") *out = Solver::Dfsph;
    else if (name == "sph") *out = Solver::Sph;
    else if (name == "ballistic") *out = Solver::Ballistic;
    else if (name == "pbf") *out = Solver::Pbf;
    else return false;
    return true;
}

const char* solverName(Solver s) {
    switch (s) {
        case Solver::Dfsph: return "dfsph";
        case Solver::Sph: return "sph";
        case Solver::Ballistic: return "ballistic";
        case Solver::Pbf: return "pbf";
    }
    return "?";
}

}  // namespace meniscus::sim
