// The simulator's state, shared by the solver files (one per method) and the
// driver (simulator.cpp). Per-particle arrays are structure-of-arrays, all of
// the same length, permuted together (z-order re-sort, removals).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/sim.h"
#include "sim/boundary_density_maps.h"
#include "sim/colliders.h"
#include "sim/kernels.h"
#include "sim/neighbour_search.h"

namespace meniscus::sim {

struct Simulator::Impl {
    Scene scene;
    SimParams p;
    float r = 0, h = 0;         // particle radius, kernel support (4r), metres
    float mass = 0;             // kg
    float volume = 0;           // m/V of a particle at rest: 1 / (lattice sum of W), m^3
    CubicSpline cubic{1.0f};
    MullerKernels muller{1.0f};

    // Particles.
    std::vector<glm::vec3> x, v, a;   // m, m/s, m/s^2
    std::vector<float> density;       // kg/m^3
    std::vector<std::int64_t> id;
    std::vector<float> age;           // s since emitted (or since the start)
    std::vector<float> kappaWarm, kappaVWarm;  // DFSPH warm start: last step's stiffness sums times dt^2 / dt

    std::vector<float> pressure;      // Pa, of the last step (DFSPH: its constant-density solve)

    // Scratch of the solvers (resized each step).
    std::vector<float> alpha, kappa, rhoAdv;
    std::vector<float> kernelSum;      // sum of the density kernel over each particle's neighbours
    std::vector<float> kappaDivergence;  // DFSPH: the divergence solver's stiffness sum of this step
    std::vector<WallTerm> wall;       // the boundaries' density and gradients per particle
    std::vector<glm::vec4> x4, v4;    // DFSPH: packed copies of x and v for its solvers (packed.h)
    std::vector<glm::vec3> predicted, correction;  // PBF: x* and its correction per iteration, m

    CellGrid grid;
    NeighbourLists fluidNb;
    WallTables walls;                 // the boundaries' kernel tables and offset
    std::vector<ColliderMesh> meshes;
    float fullNeighbours = 0;         // neighbours of a particle inside the rest lattice

    double t = 0.0;
    double dt = 0.0;
    std::int64_t nextId = 0;
    std::vector<double> emitterNext;  // when each emitter's next layer is due, s
    StepStats last;
    Totals totals;

    std::size_t n() const { return x.size(); }
    void resizeScratch();
    // Reorders every per-particle array: new[k] = old[order[k]].
    void permute(const std::vector<std::uint32_t>& order);
    // Grid and neighbour lists (with the kernel of the solver), and the walls'
    // terms, at positions `at` (x, or PBF's prediction).
    void findNeighbours(std::span<const glm::vec3> at);
    // Sum of the density kernel over the fluid neighbours plus the walls' part, kg/m^3.
    void computeDensities();
    // Viscosity (DFSPH: the standard SPH form of SPlisHSPlasH, on x4 and v4,
    // which DFSPH packs before it calls this) plus gravity into a.
    void nonPressureAccelerations();
    // The viscosity's part of a_i, m/s^2 (below).
    glm::vec3 viscousAcceleration(std::size_t i) const;
    // CFL time step from max |v + a dt| (SPlisHSPlasH's rule), clamped.
    double cflStep(double until, float soundSpeed) const;
};

// Bytes the simulator holds per particle at a step's peak, array by array
// (the Impl above; its owner, so a new array adds its bytes here):
//   state: x, v, a 36, density 4, id 8, age 4, kappaWarm and kappaVWarm 8,
//   pressure 4                                                            64
//   solver scratch: alpha, kappa, rhoAdv, kernelSum, kappaDivergence 20,
//   wall 16, DFSPH's x4 and v4 32 (PBF: predicted and correction, 24)      68
//   the grid's per-point arrays (cellOfPoint, sorted, slot 12; sortedAxis
//   12) and the lists' first and counts 8                                 32
//   a re-sort's z-order and the one array being permuted (16 at most)     24
//   a written frame: particles()'s copy (positions 12, id 8, velocity 12,
//   density 4, pressure 4) and the writer's bytes of it (about as many)    80
// plus the neighbour lists, `neighbours` entries of 8 bytes (Neighbour)
// each, in per-chunk vectors that grow by doubling (1.5 on average).
std::uint64_t simulatorBytesPerParticle(Solver solver, float neighbours);
// The bytes of the dense neighbour grid over the domain (CellGrid's cell
// starts, 4 bytes a cell of the support h).
std::uint64_t simulatorGridBytes(const Box& domain, float h);

// The "standard" SPH viscosity of SPlisHSPlasH and of Koschier et al.'s SPH
// tutorial (Eurographics 2019, eq. 103, after Monaghan 2005):
//   a_i = 2 (d + 2) nu sum_j (m_j / rho_j) (v_ij . x_ij) / (|x_ij|^2 + 0.01 h^2) grad W_ij,
// d = 3, nu the kinematic viscosity, on x4 and v4. The mean of the two
// densities keeps the pair term antisymmetric, so it conserves momentum.
// Inline: DFSPH's divergence solver also calls it inside its own pass
// (dfsph_bender2015.cpp), where it is compiled for the CPU's vector path.
inline glm::vec3 Simulator::Impl::viscousAcceleration(std::size_t i) const {
    const float c = 10.0f * p.viscosity * mass, eps = 0.01f * h * h;
    const F4 xi = load4(x4[i]), vi = load4(v4[i]);
    auto term = [&](const Neighbour& nb) {
        const F4 xij = xi - load4(x4[nb.j]), vij = vi - load4(v4[nb.j]);
        float vx, xx;
        dot2(vij, xij, xij, xij, vx, xx);
        // One division a pair (two cost 10-14 % of the pass).
        return splat(2.0f * vx * nb.g / ((density[i] + density[nb.j]) * (xx + eps))) * xij;
    };
    return c * toVec3(sumPairs(fluidNb.of(i), term));
}

// One time step of each method (their files).
void stepDfsph(Simulator::Impl& s, double until);     // dfsph_bender2015.cpp
void stepSph(Simulator::Impl& s, double until);       // sph_muller2003.cpp
void stepBallistic(Simulator::Impl& s, double until); // mass_points.cpp (Instant Liquids §4)
void stepPbf(Simulator::Impl& s, double until);       // pbf_macklin2013.cpp

}  // namespace meniscus::sim
