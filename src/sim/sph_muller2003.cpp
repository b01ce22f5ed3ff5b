// SPH after Muller, Charypar & Gross, "Particle-Based Fluid Simulation for
// Interactive Applications", SCA 2003, with two changes that make it stable
// (below):
//  - pressure p = k (rho - rho0) (eq. 12), clamped at 0: a free surface must
//    not pull particles into clumps (the tensile instability of plain SPH);
//  - density and pressure force with the same kernel, Muller's spiky (eq. 21):
//    rho_i = sum_j m W_spiky + the walls (density maps);
//  - pressure acceleration -sum_j m (p_i / rho_i^2 + p_j / rho_j^2) grad W_spiky,
//    the walls' part -(rho0 p_i / rho_i^2) grad(rho_wall / rho0) (the walls
//    mirror p_i, as Akinci et al. 2012 do with particles);
//  - viscosity mu sum_j m_j (v_j - v_i) / rho_j lap W_visc (eq. 14);
//  - surface tension from the colour field (eqs. 15-19, poly6): f = -sigma
//    lap(c) n/|n| where |n| exceeds a threshold (0.2 / h here: the paper
//    leaves l open);
//  - gravity; symplectic Euler; time step by CFL on the speed of sound sqrt(k)
//    plus the largest velocity, and the viscous limit 0.125 h^2 rho0 / mu.
//
// Why not the paper's pressure force (poly6 density, eq. 3/20, and the
// symmetrised -sum_j m_j (p_i + p_j) / (2 rho_j) grad W_spiky, eq. 10): that
// force is not the gradient of the fluid's internal energy, so it does net
// work wherever neighbouring densities differ (the free surface, where rho
// falls to 0.7 rho0, and the walls) and wherever the density kernel is not
// the force's kernel. A column at rest in a box (r = 0.01 m, 0.2 x 0.29 x
// 0.2 m, k = 1000 m^2/s^2, mu = 0.5 Pa s) gained energy from 15.3 J to 37 J
// in 0.3 s and boiled at 6 m/s, for any CFL, k or mu (mu = 5 too). Each
// mismatch alone blows it up: the paper's symmetrisation with a consistent
// kernel (12.6 -> 23.8 J in 0.6 s), this symmetrisation with poly6 density and
// spiky force (15.3 -> 31.8 J in 0.45 s). The poly6 gradient for both would conserve
// energy but clumps (it vanishes at r = 0, why the paper has the spiky), and
// poly6 has a third fault with density-map walls: a particle moving from the
// rest lattice (r from a wall) toward the wall loses density (1000 -> 988
// kg/m^3 at r/2, rho0 again only 0.05 r inside the wall), so p_i, hence the
// wall's push, drops to 0 while its neighbours press it on: the walls leaked
// (3 10^5 guard corrections in 1 s). With the spiky the density there is flat
// (999.4 at 0.9 r) and rises toward the wall. The form used here is the
// Lagrangian one (Monaghan 1992; Price 2012, eq. 35): momentum and energy are
// conserved up to the time integration, and the same column settles at rest.
#include <algorithm>
#include <cmath>

#include "sim/parallel.h"
#include "sim/state.h"
#include "sim/timer.h"

namespace meniscus::sim {

void stepSph(Simulator::Impl& s, double until) {
    StepStats& st = s.last;
    Timer timer;
    s.findNeighbours(s.x);
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
        const float rhoi = s.density[i], pi = s.pressure[i], piOverRho2 = pi / (rhoi * rhoi);
        glm::vec3 fp(0.0f), fv(0.0f), normal(0.0f);
        float lapC = m / rhoi * K.poly6Lap(0.0f);
        for (const Neighbour& nb : s.fluidNb.of(i)) {
            const float rhoj = s.density[nb.j];
            const glm::vec3 d = xi - s.x[nb.j];
            fp -= (m * (piOverRho2 + s.pressure[nb.j] / (rhoj * rhoj)) * nb.g) * d;
            const float r2 = glm::dot(d, d), r = std::sqrt(r2);
            fv += (m * K.viscosityLap(r) / rhoj) * (s.v[nb.j] - vi);
            if (sigma > 0.0f) {
                normal += (m / rhoj) * K.poly6Grad(d, r2);
                lapC += (m / rhoj) * K.poly6Lap(r2);
            }
        }
        glm::vec3 acc = fp + (mu / rhoi) * fv - (rho0 * piOverRho2) * s.wall[i].gradient;
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
