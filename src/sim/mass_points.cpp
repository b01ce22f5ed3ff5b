// Ballistic mass points (Instant Liquids §4, its waterfalls): particles under
// gravity only, no neighbours and no pressure solve, so millions stay cheap;
// the colliders and the domain still hold them (the guard in colliders.cpp,
// applied by the driver after the positions move). The density written is rho0.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sim/state.h"
#include "sim/timer.h"

namespace meniscus::sim {

void stepBallistic(Simulator::Impl& s, double until) {
    Timer timer;
    s.last.msNeighbours = s.last.msDensity = s.last.msPressure = 0.0;
    s.a.assign(s.n(), s.p.gravity);
    s.dt = s.cflStep(until, 0.0f);
    const float dt = float(s.dt);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.n(), 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            s.v[i] += dt * s.p.gravity;
            s.density[i] = s.p.restDensity;
        }
    });
    s.last.msForces = timer.lap();
    s.last.densityIterations = s.last.divergenceIterations = 0;
    s.last.densityError = 0.0;
}

}  // namespace meniscus::sim
