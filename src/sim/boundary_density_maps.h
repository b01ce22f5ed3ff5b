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
// A(z) being the kernel integrated over a plane at distance z. Exact for
// planes (the domain, plane colliders, box faces); for curved or edged
// solids it is the tangent-plane approximation, and where two walls meet
// (a corner) their overlap behind both is counted twice (a few per cent of
// rho0 within 2r of the corner's edge). Nothing is sampled, so walls cost
// nothing in the neighbour search and a column of fluid rests on a wall
// exactly as on more fluid.
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

// The boundary's part of one particle: relative density (sum of Phi) and its
// gradient with respect to the particle's position (sum of -A n, pointing
// into the solids), for the density kernel; and the gradient for the
// pressure kernel when it differs (Muller's spiky).
struct WallTerm {
    float density = 0.0f;
    glm::vec3 gradient{0.0f};
    glm::vec3 pressureGradient{0.0f};
};

// Calls f(distance, outward normal) for every boundary within `support` of x:
// the six walls of the domain and every collider.
void forEachBoundaryNear(const Scene& scene, const std::vector<ColliderMesh>& meshes, float support,
                         const glm::vec3& x, const std::function<void(float, const glm::vec3&)>& f);

WallTerm wallTerm(const Scene& scene, const std::vector<ColliderMesh>& meshes, float support, const glm::vec3& x,
                  const WallTable& density, const WallTable* pressure);

}  // namespace meniscus::sim
