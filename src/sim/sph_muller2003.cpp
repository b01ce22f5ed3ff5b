// SPH after Muller, Charypar & Gross, "Particle-Based Fluid Simulation for
// Interactive Applications", SCA 2003:
//  - density with the poly6 kernel (eq. 3, 20), fluid and walls (density maps);
//  - pressure p = k (rho - rho0) (eq. 12), clamped at 0: a free surface must
//    not pull particles into clumps (the tensile instability of plain SPH);
//  - symmetrised pressure force -sum_j m_j (p_i + p_j) / (2 rho_j) grad W_spiky
//    (eq. 10), the walls mirroring p_i (as Akinci et al. 2012 do with particles);
//  - viscosity mu sum_j m_j (v_j - v_i) / rho_j lap W_visc (eq. 14);
//  - surface tension from the colour field (eqs. 15-19): f = -sigma lap(c) n/|n|
//    where |n| exceeds a threshold (0.2 / h here: the paper leaves l open);
//  - gravity; symplectic Euler; time step by CFL on the speed of sound sqrt(k)
//    plus the largest velocity, and the viscous limit 0.125 h^2 rho0 / mu.
#include <algorithm>
#include <cmath>

#include "sim/parallel.h"
#include "sim/state.h"
#include "sim/timer.h"

namespace meniscus::sim {

void stepSph(Simulator::Impl& s, double until) {
    StepStats& st = s.last;
    Timer timer;
    s.findNeighbours();
    st.msNeighbours = timer.lap();
    s.computeDensities();
    const std::size_t n = s.n();
    const float k = s.p.stiffness, rho0 = s.p.restDensity, m = s.mass;
    forAll(n, [&](std::size_t i) { s.pressure[i] = k * std::max(s.density[i] - rho0, 0.0f); });
    st.msDensity = timer.lap();

    s.nonPressureAccelerations();  // gravity (this solver's viscosity, mu, is below)
    const MullerKernels& K = s.muller;
    const float mu = s.p.viscosity, sigma = s.p.surfaceTension;
    const float threshold = 0.2f / s.h;
    forAll(n, [&](std::size_t i) {
        const glm::vec3 xi = s.x[i], vi = s.v[i];
        const float rhoi = s.density[i], pi = s.pressure[i];
        glm::vec3 fp(0.0f), fv(0.0f), normal(0.0f);
        float lapC = m / rhoi * K.poly6Lap(0.0f);
        for (const Neighbour& nb : s.fluidNb.of(i)) {
            const float rhoj = s.density[nb.j];
            fp -= (m * (pi + s.pressure[nb.j]) / (2.0f * rhoj)) * nb.gradW;
            const glm::vec3 d = xi - s.x[nb.j];
            const float r2 = glm::dot(d, d), r = std::sqrt(r2);
            fv += (m * K.viscosityLap(r) / rhoj) * (s.v[nb.j] - vi);
            if (sigma > 0.0f) {
                normal += (m / rhoj) * K.poly6Grad(d, r2);
                lapC += (m / rhoj) * K.poly6Lap(r2);
            }
        }
        glm::vec3 acc = (fp + mu * fv) / rhoi;
        acc -= (rho0 * pi / (rhoi * rhoi)) * s.wall[i].pressureGradient;
        const float len = glm::length(normal);
        if (sigma > 0.0f && len > threshold) acc -= (sigma * lapC / (len * rhoi)) * normal;
        s.a[i] += acc;
    });
    st.msPressure = timer.lap();

    float soundSpeed = std::sqrt(k);
    s.dt = s.cflStep(until, soundSpeed);
    if (mu > 0.0f) s.dt = std::min(s.dt, double(0.125f * s.h * s.h * rho0 / mu));
    const float dt = float(s.dt);
    forAll(n, [&](std::size_t i) { s.v[i] += dt * s.a[i]; });
    st.msForces = timer.lap();
    st.densityIterations = st.divergenceIterations = 0;
    st.densityError = 0.0;
}

}  // namespace meniscus::sim
