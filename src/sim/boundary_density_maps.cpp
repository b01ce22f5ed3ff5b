// Density maps of the boundaries (Koschier & Bender 2017; see boundary_density_maps.h).
#include "sim/boundary_density_maps.h"

#include <algorithm>
#include <cmath>

namespace meniscus::sim {

namespace {
constexpr int kTableSize = 2048;  // samples over [-h, h]: linear interpolation error << 1e-4
}

WallTable::WallTable(float h, const std::function<double(double)>& W) : h_(h) {
    // A(z) = 2 pi int_|z|^h W(s) s ds, then Phi(d) = int_d^h A, by the
    // trapezoid rule on a fine grid, sampled into the table.
    constexpr int fine = 16 * kTableSize;
    const double hd = h, dz = 2.0 * hd / fine;
    std::vector<double> A(fine + 1), Phi(fine + 1);
    // Radial integral from s to h, accumulated from h down to 0.
    std::vector<double> radial(fine / 2 + 1, 0.0);  // radial[k] = int_{s_k}^h W(s) s ds, s_k = k * dz
    for (int k = fine / 2 - 1; k >= 0; --k) {
        const double s0 = k * dz, s1 = (k + 1) * dz;
        radial[std::size_t(k)] = radial[std::size_t(k) + 1] + 0.5 * dz * (W(s0) * s0 + W(s1) * s1);
    }
    for (int k = 0; k <= fine; ++k) {
        const double z = -hd + k * dz;
        const int idx = std::min(fine / 2, int(std::lround(std::abs(z) / dz)));
        A[std::size_t(k)] = 2.0 * 3.14159265358979323846 * radial[std::size_t(idx)];
    }
    Phi[fine] = 0.0;
    for (int k = fine - 1; k >= 0; --k) Phi[std::size_t(k)] = Phi[std::size_t(k) + 1] + 0.5 * dz * (A[std::size_t(k)] + A[std::size_t(k) + 1]);
    phi_.resize(kTableSize + 1), slab_.resize(kTableSize + 1);
    for (int k = 0; k <= kTableSize; ++k) {
        phi_[std::size_t(k)] = float(Phi[std::size_t(k) * (fine / kTableSize)]);
        slab_[std::size_t(k)] = float(A[std::size_t(k) * (fine / kTableSize)]);
    }
}

float WallTable::lookup(const std::vector<float>& t, float d) const {
    const float u = (d + h_) / (2.0f * h_) * float(kTableSize);
    if (!(u > 0.0f)) return t.front();
    if (u >= float(kTableSize)) return t.back();
    const int k = int(u);
    const float f = u - float(k);
    return t[std::size_t(k)] + f * (t[std::size_t(k) + 1] - t[std::size_t(k)]);
}

void forEachBoundaryNear(const Scene& scene, const std::vector<ColliderMesh>& meshes, float support,
                         const glm::vec3& x, const std::function<void(float, const glm::vec3&)>& f) {
    // The tank: six walls, the solid outside the domain box.
    for (int a = 0; a < 3; ++a) {
        glm::vec3 n(0.0f);
        const float lo = x[a] - scene.domain.min[a], hi = scene.domain.max[a] - x[a];
        if (lo < support) n[a] = 1.0f, f(lo, n);
        if (hi < support) n[a] = -1.0f, f(hi, n);
    }
    std::size_t mesh = 0;
    for (const Collider& c : scene.colliders) {
        const ColliderMesh* cm = c.kind == Collider::Kind::Mesh ? &meshes[mesh++] : nullptr;
        if (cm && (glm::any(glm::lessThan(x, cm->lo - glm::vec3(support))) ||
                   glm::any(glm::greaterThan(x, cm->hi + glm::vec3(support)))))
            continue;
        const SurfacePoint s = colliderDistance(c, cm ? &cm->mesh : nullptr, x);
        if (s.distance < support) f(s.distance, s.normal);
    }
}

WallTerm wallTerm(const Scene& scene, const std::vector<ColliderMesh>& meshes, float support, const glm::vec3& x,
                  const WallTable& density, const WallTable* pressure) {
    WallTerm w;
    forEachBoundaryNear(scene, meshes, support, x, [&](float d, const glm::vec3& n) {
        w.density += density.phi(d);
        w.gradient -= density.slab(d) * n;
        if (pressure) w.pressureGradient -= pressure->slab(d) * n;
    });
    if (!pressure) w.pressureGradient = w.gradient;
    return w;
}

}  // namespace meniscus::sim
