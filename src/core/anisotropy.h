// Anisotropic kernels (Yu & Turk, "Reconstructing surfaces of particle-based
// fluids using anisotropic kernels", SCA 2010 / ACM TOG 32(1) 2013): each
// particle's ellipsoid from a weighted PCA of its neighbourhood, and its
// Laplacian-smoothed centre. The splat (cpu/splat.cpp, gl/splat.cpp) draws
// the ellipsoids with shared/ellipsoid.h; the parameters and why are in
// AnisotropyParams (include/meniscus/params.h).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/params.h"

namespace meniscus {

// One particle's ellipsoid E = {x : |m (x - centre)| <= 1} in world space:
// m symmetric (1/m), q = m^-2 (m^2), as shared/ellipsoid.h takes them.
struct EllipsoidShape {
    glm::mat3 m{1.0f};
    glm::mat3 q{1.0f};
};

// The ellipsoid of a sphere of radius r.
EllipsoidShape sphereShape(float radius);
// The same ellipsoid (same centre and axes) with every half-axis times `scale`.
EllipsoidShape scaledShape(const EllipsoidShape& shape, float scale);
// The ellipsoid with unit principal axes `axes` (columns, orthonormal) of half-lengths a.
EllipsoidShape ellipsoidShape(const glm::mat3& axes, const glm::vec3& a);

struct Ellipsoids {
    std::vector<glm::vec3> centres;      // smoothed kernel centres, world, metres
    std::vector<EllipsoidShape> shapes;  // one per centre
    std::size_t isolated = 0;            // particles with fewer than minNeighbours neighbours
};

// The ellipsoids of `positions` (radius r > 0, metres) with `params`
// (enabled is not looked at): into `out`, which keeps its memory across
// frames. Threaded; the result does not depend on the thread count. The
// neighbourhood of particle i is every particle j (i included) with
// |x_j - x_i| < R = neighbourRadii r, weighted w = 1 - (|x_j - x_i| / R)^3.
// With `radii` (one per position, metres: the particles' own radii), each
// ellipsoid keeps the volume of its own particle's sphere and a lone
// particle is a sphere of kn times its own radius; R stays neighbourRadii r.
void computeAnisotropy(std::span<const glm::vec3> positions, float radius, const AnisotropyParams& params,
                       Ellipsoids& out, std::span<const float> radii = {});

// The eigen-decomposition of a symmetric 3x3 matrix: eigenvalues in closed
// form (Smith 1961), eigenvectors after Kopp 2008; eigenvalues in descending
// order and the matching unit eigenvectors as the columns of `vectors` (a
// right-handed frame; any frame for a multiple of the identity).
void symmetricEigen(const glm::dmat3& a, glm::dvec3& values, glm::dmat3& vectors);

namespace detail {
// Whether computeAnisotropy and symmetricEigen may take their AVX2 code
// where the CPU has it (the default) or must take the baseline code; returns
// the previous setting. Both give the same bits (tested).
bool allowAnisotropyAvx2(bool allow);
}  // namespace detail

}  // namespace meniscus
