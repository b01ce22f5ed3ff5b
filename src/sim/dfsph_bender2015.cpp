// Divergence-free SPH: Bender & Koschier, "Divergence-Free Smoothed Particle
// Hydrodynamics", SCA 2015 (and the TVCG 2017 extension, [BK17]). Two
// pressure solvers per step, both Jacobi iterations on a stiffness kappa_i:
//  - the divergence-free solver makes d(rho)/dt = 0 (Algorithm 2 of [BK17]),
//  - the constant-density solver makes the predicted density rho0 (Algorithm 3),
// with the factor alpha_i (eq. 11 of [BK17]) shared by both, warm-started with
// half the last step's stiffness, as SPlisHSPlasH does. Densities here are
// relative (rho / rho0), volumes V = m / rho0; the boundary (density maps,
// boundary_density_maps.h) enters through its density and gradient per particle. Stopping rules and tolerances as SPlisHSPlasH:
// mean density error <= densityTolerance (at least 2 iterations), mean
// d(rho)/dt * dt <= divergenceTolerance (at least 1), both at most
// maxIterations; a particle with fewer than 20 neighbours (a deficient
// surface particle) gets no divergence correction.
#include <algorithm>
#include <cmath>

#include "sim/packed.h"
#include "sim/parallel.h"
#include "sim/state.h"
#include "sim/timer.h"

namespace meniscus::sim {

namespace {

constexpr float kWarmStart = 0.5f;  // fraction of last step's stiffness reused (SPlisHSPlasH's)
// SPlisHSPlasH's deficiency rule, 20 neighbours of the ~33 of a full
// neighbourhood, with a wall counted as the fluid it stands for.
constexpr float kMinNeighboursForDivergence = 20.0f;

// Rate of change of the relative density, sum_j V_j (v_i - v_j) . grad W_ij,
// on the packed positions x4 and velocities v4 (packed.h).
float densityRate(const Simulator::Impl& s, std::size_t i) {
    const F4 xi = load4(s.x4[i]), vi = load4(s.v4[i]);
    auto term = [&](const Neighbour& nb) { return splat(nb.g) * ((vi - load4(s.v4[nb.j])) * (xi - load4(s.x4[nb.j]))); };
    const F4 fluid = sumPairs(s.fluidNb.of(i), term);
    return s.volume * sum4(fluid) + glm::dot(glm::vec3(s.v4[i]), s.wall[i].gradient);
}

// v_i -= dt * (sum_j V (k_i + k_j) grad W_ij + k_i grad rho_wall), on v4.
void applyStiffness(Simulator::Impl& s, const std::vector<float>& k, float dt) {
    forAll(s.n(), [&](std::size_t i) {
        const F4 xi = load4(s.x4[i]);
        const float ki = k[i];
        auto term = [&](const Neighbour& nb) { return splat((ki + k[nb.j]) * nb.g) * (xi - load4(s.x4[nb.j])); };
        const F4 fluid = sumPairs(s.fluidNb.of(i), term);
        const F4 dv = splat(dt) * (splat(s.volume) * fluid + splat(ki) * load4(s.wall[i].gradient));
        store4(s.v4[i], load4(s.v4[i]) - dv);
    });
}

// The factor alpha_i (eq. 11 of [BK17]) and, in the same pass over the lists
// (which positions both read), the divergence solver's first rate(i): the
// same sums in the same order as densityRate, so the same bits.
template <class Rate>
void computeFactorsAndRates(Simulator::Impl& s, const Rate& rate) {
    forAll(s.n(), [&](std::size_t i) {
        const F4 xi = load4(s.x4[i]), vi = load4(s.v4[i]);
        F4 g = zero4(), squares = zero4(), even = zero4(), odd = zero4();
        auto visit = [&](const Neighbour& nb, F4& sum) {
            const F4 xij = xi - load4(s.x4[nb.j]);
            const F4 gj = splat(s.volume * nb.g) * xij;
            g = g + gj;
            squares = squares + gj * gj;
            sum = sum + splat(nb.g) * ((vi - load4(s.v4[nb.j])) * xij);
        };
        const std::span<const Neighbour> list = s.fluidNb.of(i);
        std::size_t q = 0;
        for (; q + 1 < list.size(); q += 2) visit(list[q], even), visit(list[q + 1], odd);
        if (q < list.size()) visit(list[q], even);
        const glm::vec3 gs = toVec3(g) + s.wall[i].gradient;
        const float denom = glm::dot(gs, gs) + sum4(squares);
        s.alpha[i] = denom > 1e-5f ? 1.0f / denom : 0.0f;
        s.rhoAdv[i] = rate(i, s.volume * sum4(even + odd) + glm::dot(glm::vec3(s.v4[i]), s.wall[i].gradient));
    });
}

// The divergence-free solver: returns its iterations. Each iteration's last
// pass also computes the non-pressure accelerations a (viscosity and gravity,
// nonPressureAccelerations) from the velocities it reads: those of the last
// iteration are the step's (one traversal of the lists fewer; an iteration
// that turns out not to be the last computed them for nothing).
int divergenceSolve(Simulator::Impl& s, float dt) {
    const std::size_t n = s.n();
    // The rate of particle i, whose sum over the neighbours is d.
    auto rule = [&](std::size_t i, float d) {
        const float neighbours = float(s.fluidNb.count(i)) + s.wall[i].density * s.fullNeighbours;
        return neighbours < kMinNeighboursForDivergence ? 0.0f : std::max(d, 0.0f);
    };
    auto rate = [&](std::size_t i) { return rule(i, densityRate(s, i)); };
    const bool viscous = s.p.viscosity > 0.0f;
    s.a.resize(n);
    computeFactorsAndRates(s, rule);
    // Warm start: half of last step's stiffness where the fluid still compresses.
    forAll(n, [&](std::size_t i) { s.kappa[i] = s.rhoAdv[i] > 0.0f ? kWarmStart * s.kappaVWarm[i] / dt : 0.0f; });
    std::vector<float>& total = s.pressure;  // reused as the stiffness sum
    total = s.kappa;
    applyStiffness(s, s.kappa, dt);
    forAll(n, [&](std::size_t i) { s.rhoAdv[i] = rate(i); });
    const double eta = double(s.p.divergenceTolerance) / dt;
    int iterations = 0;
    double err = sumAll(n, [&](std::size_t i) { return s.rhoAdv[i]; }) / double(std::max<std::size_t>(n, 1));
    while ((iterations < 1 || err > eta) && iterations < s.p.maxIterations) {
        forAll(n, [&](std::size_t i) {
            s.kappa[i] = s.rhoAdv[i] * s.alpha[i] / dt;
            total[i] += s.kappa[i];
        });
        applyStiffness(s, s.kappa, dt);
        forAll(n, [&](std::size_t i) {
            s.rhoAdv[i] = rate(i);
            s.a[i] = viscous ? s.p.gravity + s.viscousAcceleration(i) : s.p.gravity;
        });
        err = sumAll(n, [&](std::size_t i) { return s.rhoAdv[i]; }) / double(std::max<std::size_t>(n, 1));
        ++iterations;
    }
    forAll(n, [&](std::size_t i) { s.kappaVWarm[i] = total[i] * dt; });
    s.kappaDivergence = total;
    return iterations;
}

// The constant-density solver: returns its iterations and the final mean error.
int densitySolve(Simulator::Impl& s, float dt, double* errOut) {
    const std::size_t n = s.n();
    // Predicted relative density after the step, compressions only (a free
    // surface may have rho < rho0 without pulling particles together).
    auto predicted = [&](std::size_t i) { return std::max(s.density[i] / s.p.restDensity + dt * densityRate(s, i), 1.0f); };
    forAll(n, [&](std::size_t i) { s.rhoAdv[i] = predicted(i); });
    const float invDt2 = 1.0f / (dt * dt);
    forAll(n, [&](std::size_t i) { s.kappa[i] = s.rhoAdv[i] > 1.0f ? kWarmStart * s.kappaWarm[i] * invDt2 : 0.0f; });
    std::vector<float>& total = s.pressure;
    total = s.kappa;
    applyStiffness(s, s.kappa, dt);
    forAll(n, [&](std::size_t i) { s.rhoAdv[i] = predicted(i); });
    auto meanError = [&] { return sumAll(n, [&](std::size_t i) { return s.rhoAdv[i] - 1.0f; }) / double(std::max<std::size_t>(n, 1)); };
    double err = meanError();
    int iterations = 0;
    while ((iterations < 2 || err > s.p.densityTolerance) && iterations < s.p.maxIterations) {
        forAll(n, [&](std::size_t i) {
            s.kappa[i] = (s.rhoAdv[i] - 1.0f) * s.alpha[i] * invDt2;
            total[i] += s.kappa[i];
        });
        applyStiffness(s, s.kappa, dt);
        forAll(n, [&](std::size_t i) { s.rhoAdv[i] = predicted(i); });
        err = meanError();
        ++iterations;
    }
    // kappa is p / rho^2 times rho0 (compare the pressure acceleration
    // -sum_j m_j (p_i / rho_i^2 + p_j / rho_j^2) grad W_ij with applyStiffness);
    // both solvers' stiffnesses act over the step, so the pressure is their sum.
    forAll(n, [&](std::size_t i) {
        s.kappaWarm[i] = total[i] * dt * dt;
        const float divergence = i < s.kappaDivergence.size() ? s.kappaDivergence[i] : 0.0f;
        total[i] = (total[i] + divergence) * s.density[i] * s.density[i] / s.p.restDensity;
    });
    *errOut = err;
    return iterations;
}

}  // namespace

void stepDfsph(Simulator::Impl& s, double until) {
    StepStats& st = s.last;
    Timer timer;
    s.findNeighbours(s.x);
    pack(s.x, s.x4);  // fixed for the step
    st.msNeighbours = timer.lap();
    s.computeDensities();
    st.msDensity = timer.lap();
    // Divergence-free solve on the velocities of the last step (its dt);
    // it computes the factors alpha too (in its first pass).
    pack(s.v, s.v4);
    st.divergenceIterations = s.n() ? divergenceSolve(s, float(s.dt)) : 0;
    unpack(s.v4, s.v);
    st.msPressure = timer.lap();
    if (st.divergenceIterations == 0) s.nonPressureAccelerations();  // else the solver did
    s.dt = s.cflStep(until, 0.0f);
    // The explicit viscosity's own limit, 0.125 h^2 / nu (as for SPH below).
    if (s.p.viscosity > 0.0f) s.dt = std::min(s.dt, double(0.125f * s.h * s.h / s.p.viscosity));
    const float dt = float(s.dt);
    forAll(s.n(), [&](std::size_t i) { s.v[i] += dt * s.a[i]; });
    st.msForces = timer.lap();
    double err = 0.0;
    pack(s.v, s.v4);
    st.densityIterations = s.n() ? densitySolve(s, dt, &err) : 0;
    unpack(s.v4, s.v);
    st.densityError = err;
    st.msPressure += timer.lap();
}

}  // namespace meniscus::sim
