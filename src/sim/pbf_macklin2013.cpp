// Position-based fluids: Macklin & Muller, "Position Based Fluids", SIGGRAPH
// 2013 (Algorithm 1). Each step predicts the positions under gravity, finds
// the neighbours once at the prediction, then projects the density
// constraints C_i = rho_i / rho0 - 1 by Jacobi iterations:
//   lambda_i = -C_i / (sum_k |grad_k C_i|^2 + eps)                  (eq. 11)
//   dx_i = sum_j V (lambda_i + lambda_j + s_corr) grad W_ij         (eq. 14)
// with the artificial pressure s_corr = -k (W_ij / W(dq))^n against the
// tensile instability (eq. 13: k = 0.1, n = 4, dq = 0.2 h), then sets
// v = (x* - x) / dt and smooths it with XSPH (eq. 17, c = 0.01).
// Departures, as SPlisHSPlasH's PBF does: one kernel (the cubic spline, the
// one of the walls' density maps) for density and gradient, where the paper
// has poly6 and spiky; densities relative (V = m / rho0), so lambda is in m^2
// and eps and s_corr are stated relative to the rest lattice's
// sum_k |grad_k C|^2 (kRelaxation, and s_corr in units of its inverse); the
// constraint clamped at C >= 0 (a free surface may be below rho0 without
// pulling together, as the paper's unilateral variant); the walls (density
// maps) enter C_i and its gradient as DFSPH's do, and the collision response
// of Algorithm 1 (line 12) projects x* to at least r from every wall and
// collider after each update (the rest lattice's first layer sits at r).
// Without it the bulk's lambda_j pushed the floor layer, under-dense at the
// wall (C < 0, so lambda = 0: no push back), through the floor: the 1,500-
// particle column took 9 10^4 guard corrections in 1.5 s, none with it.
// Iterations until the mean density error is below density_tolerance (at
// least 2, at most max_iterations) rather than a fixed count. Vorticity
// confinement (§5) is not applied: it adds energy, and the dam break's tests
// check that none is gained. The driver's advection then moves x by dt v, which is x* plus
// XSPH's (small) change.
#include <algorithm>
#include <cmath>

#include "sim/colliders.h"
#include "sim/parallel.h"
#include "sim/state.h"
#include "sim/timer.h"

namespace meniscus::sim {

namespace {

constexpr float kRelaxation = 0.5f;          // eps, fraction of the rest lattice's sum |grad C|^2
constexpr float kCorrK = 0.1f, kCorrDq = 0.2f;  // s_corr's k and dq / h (n = 4)
constexpr float kXsph = 0.01f;               // XSPH's c

// sum_k |grad_k C_i|^2 of a particle inside the rest lattice (spacing 2r):
// the scale of eps and s_corr.
float restGradientSquares(const Simulator::Impl& s) {
    const float spacing = 2.0f * s.r;
    const int reach = int(std::ceil(s.h / spacing));
    double sum = 0.0;
    for (int z = -reach; z <= reach; ++z)
        for (int y = -reach; y <= reach; ++y)
            for (int x = -reach; x <= reach; ++x) {
                const glm::vec3 d = spacing * glm::vec3(float(x), float(y), float(z));
                const glm::vec3 g = s.volume * s.cubic.gradW(d, glm::length(d));
                sum += double(glm::dot(g, g));  // sum_j |grad_j C_i|^2; grad_i C_i = 0 by symmetry
            }
    return float(sum);
}

}  // namespace

void stepPbf(Simulator::Impl& s, double until) {
    StepStats& st = s.last;
    Timer timer;
    const std::size_t n = s.n();
    const CubicSpline& K = s.cubic;
    s.a.assign(n, s.p.gravity);
    s.dt = s.cflStep(until, 0.0f);
    const float dt = float(s.dt);
    // Predict.
    std::vector<glm::vec3>& xp = s.predicted;
    xp.resize(n);
    forAll(n, [&](std::size_t i) {
        s.v[i] += dt * s.a[i];
        xp[i] = s.x[i] + dt * s.v[i];
    });
    st.msForces = timer.lap();
    s.findNeighbours(xp);  // once, at the prediction (the paper's step 5-7)
    st.msNeighbours = timer.lap();

    const float squares0 = restGradientSquares(s);
    const float eps = kRelaxation * squares0;
    const float wDq = K.W(kCorrDq * s.h), corrScale = kCorrK / squares0;
    std::vector<float>& lambda = s.kappa;
    std::vector<glm::vec3>& dx = s.correction;
    dx.resize(n);
    bool moved = false;  // x* changed since findNeighbours evaluated the walls
    auto constraint = [&](std::size_t i, glm::vec3* gradOut, float* squaresOut) {
        const glm::vec3 xi = xp[i];
        float w = K.W(0.0f);
        glm::vec3 grad(0.0f);
        float squares = 0.0f;
        for (const Neighbour& nb : s.fluidNb.of(i)) {
            const glm::vec3 d = xi - xp[nb.j];
            const float r = glm::length(d);
            w += K.W(r);
            const glm::vec3 g = s.volume * K.gradW(d, r);
            grad += g;
            squares += glm::dot(g, g);
        }
        // The first iteration is at the prediction, whose walls findNeighbours has.
        if (moved) s.wall[i] = wallTerm(s.scene, s.meshes, s.h, xi, s.walls);
        const WallTerm& wall = s.wall[i];
        grad += wall.gradient;
        *gradOut = grad;
        *squaresOut = squares;
        return s.volume * w + wall.density - 1.0f;
    };
    int iterations = 0;
    double err = 0.0;
    while (iterations < s.p.maxIterations) {
        forAll(n, [&](std::size_t i) {
            glm::vec3 grad;
            float squares;
            s.rhoAdv[i] = constraint(i, &grad, &squares);
            lambda[i] = -std::max(s.rhoAdv[i], 0.0f) / (squares + glm::dot(grad, grad) + eps);
        });
        err = sumAll(n, [&](std::size_t i) { return std::max(s.rhoAdv[i], 0.0f); }) / double(std::max<std::size_t>(n, 1));
        if (iterations >= 2 && err <= s.p.densityTolerance) break;
        forAll(n, [&](std::size_t i) {
            const glm::vec3 xi = xp[i];
            glm::vec3 sum(0.0f);
            for (const Neighbour& nb : s.fluidNb.of(i)) {
                const glm::vec3 d = xi - xp[nb.j];
                const float r = glm::length(d);
                const float q = K.W(r) / wDq, q2 = q * q;
                const float corr = -corrScale * q2 * q2;
                sum += (lambda[i] + lambda[nb.j] + corr) * K.gradW(d, r);
            }
            dx[i] = s.volume * sum + lambda[i] * s.wall[i].gradient;
        });
        forAll(n, [&](std::size_t i) {
            xp[i] += dx[i];
            projectOutside(s.scene, s.meshes, s.r, xp[i]);
        });
        moved = true;
        ++iterations;
    }
    st.densityIterations = iterations;
    st.divergenceIterations = 0;
    st.densityError = err;
    st.msPressure = timer.lap();

    // Velocities from the projected positions, then XSPH: v_i += c sum_j V (v_j - v_i) W_ij.
    forAll(n, [&](std::size_t i) { s.v[i] = (xp[i] - s.x[i]) / dt; });
    std::vector<glm::vec3>& smoothed = dx;
    forAll(n, [&](std::size_t i) {
        glm::vec3 sum(0.0f);
        for (const Neighbour& nb : s.fluidNb.of(i)) sum += K.W(glm::length(xp[i] - xp[nb.j])) * (s.v[nb.j] - s.v[i]);
        smoothed[i] = s.v[i] + kXsph * s.volume * sum;
    });
    forAll(n, [&](std::size_t i) {
        s.v[i] = smoothed[i];
        s.density[i] = s.p.restDensity * (1.0f + s.rhoAdv[i]);
        s.pressure[i] = 0.0f;
    });
    st.msDensity = timer.lap();
}

}  // namespace meniscus::sim
