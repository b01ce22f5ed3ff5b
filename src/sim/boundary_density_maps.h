// Boundaries as density maps: Koschier & Bender, "Density Maps for Improved
// SPH Boundary Handling", SCA 2017. A solid contributes to a fluid particle's
// density the integral of the kernel over the part of the solid inside the
// support, rho_b(x) = rho0 * int_solid W(x - y) dy, and to the pressure
// force its gradient (the boundary mirrors the particle's own pressure, as
// Akinci et al. 2012 do with particles). Koschier & Bender tabulate that
// integral on a 3-D grid around each body; here every boundary is a signed
// distance function (the domain's six walls, the colliders: colliders.h) and
// the integral is taken over the half-space behind the closest surface
// point, a function of the distance d alone, tabulated once:
//     Phi(d) = int_d^h A(z) dz,   A(z) = 2 pi int_|z|^h W(s) s ds,
// A(z) being the kernel integrated over a plane at distance z: exact for
// planes and box faces; for curved or edged colliders the tangent-plane
// approximation. The domain (the tank) is exact everywhere, edges and
// corners included: its walls' part is 1 minus the kernel's mass inside the
// box, from a table of the kernel's mass in an octant (DomainTable).
// Both are evaluated at the distance plus an offset (wallOffset) chosen so
// that the rest lattice of spacing 2r, its first layer r from a flat wall
// (the block filling rule), has exactly rho0 there: the continuous wall and
// the discrete fluid then agree and a column at rest has no spurious push.
// Nothing is sampled, so walls cost nothing in the neighbour search.
#pragma once

#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/sim.h"
#include "sim/colliders.h"

namespace meniscus::sim {

// Phi(d) and A(d) of one kernel, tabulated on [-h, h] (relative density and
// its derivative: d Phi / d d = -A).
class WallTable {
public:
    WallTable() = default;
    WallTable(float h, const std::function<double(double)>& W);
    float phi(float d) const { return lookup(phi_, d); }
    float slab(float d) const { return lookup(slab_, d); }

private:
    float lookup(const std::vector<float>& t, float d) const;
    float h_ = 1.0f;
    std::vector<float> phi_, slab_;
};

// The kernel's mass in the region {u : u_k >= -d_k} (the fluid side of up to
// three axis-aligned walls at distances d_k) and its gradient, from a 3-D
// table of suffix sums over [-h, h]^3 (trilinear).
class DomainTable {
public:
    DomainTable() = default;
    DomainTable(float h, const std::function<double(double)>& W);
    // Mass inside for distances d (each clipped to [-h, h]; h = no wall on that axis).
    float inside(const glm::vec3& d) const;
    // d inside / d d_k.
    glm::vec3 gradient(const glm::vec3& d) const;

private:
    float at(float a, float b, float c) const;
    float h_ = 1.0f, cell_ = 1.0f;
    int n_ = 0;
    std::vector<float> suffix_;
};

// The offset added to every wall distance (see above): solves
// lattice(first layer) + Phi(r + offset) = 1 for the half-space lattice.
float wallOffset(float r, float h, const WallTable& table, const std::function<float(float)>& W);

// The boundary's part of one particle: relative density (sum of Phi) and its
// gradient with respect to the particle's position (sum of -A n, pointing
// into the solids), in the solver's kernel (both solvers' pressure forces use
// the kernel their density does).
struct WallTerm {
    float density = 0.0f;
    glm::vec3 gradient{0.0f};
};

// The kernel tables of one solver.
struct WallTables {
    WallTable density;                // half-space Phi/A
    DomainTable domainDensity;
    float offset = 0.0f;              // metres, added to every distance
    // metres: the least distance (offset included) a wall is evaluated at.
    // Closer, a wall counts as if this far (Bender et al. 2019 likewise hold
    // their boundary point at least a particle diameter away "to avoid strong
    // pressure forces"): a centre at a wall's surface, or at an edge where two
    // walls' half-spaces make 3/4 of its support solid, would otherwise read
    // up to 1.75 rho0 with no fluid around it, and the pressure solve fired
    // it off along the wall at 2-3x the speed of the flow that put it there.
    float nearest = 0.0f;
};

WallTerm wallTerm(const Scene& scene, const std::vector<ColliderMesh>& meshes, float support, const glm::vec3& x,
                  const WallTables& tables);

}  // namespace meniscus::sim
