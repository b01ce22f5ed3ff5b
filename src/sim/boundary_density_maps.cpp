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

DomainTable::DomainTable(float h, const std::function<double(double)>& W) : h_(h) {
    // Cells of h/32 over [-h, h]^3; suffix_[i][j][k] = sum of W * cell^3 over
    // the cells at or above (i, j, k) on every axis, so the mass in
    // {u_k >= -h + index * cell} is one lookup.
    constexpr int cellsPerH = 32;
    const int cells = 2 * cellsPerH;
    n_ = cells + 1;
    cell_ = h / float(cellsPerH);
    std::vector<double> sum(std::size_t(n_) * std::size_t(n_) * std::size_t(n_), 0.0);
    auto idx = [&](int i, int j, int k) { return (std::size_t(i) * std::size_t(n_) + std::size_t(j)) * std::size_t(n_) + std::size_t(k); };
    const double c = cell_, vol = c * c * c;
    for (int i = 0; i < cells; ++i)
        for (int j = 0; j < cells; ++j)
            for (int k = 0; k < cells; ++k) {
                const double x = -h + (i + 0.5) * c, y = -h + (j + 0.5) * c, z = -h + (k + 0.5) * c;
                sum[idx(i, j, k)] = W(std::sqrt(x * x + y * y + z * z)) * vol;
            }
    for (int i = cells - 1; i >= 0; --i)
        for (int j = cells - 1; j >= 0; --j)
            for (int k = cells - 1; k >= 0; --k)
                sum[idx(i, j, k)] += sum[idx(i + 1, j, k)] + sum[idx(i, j + 1, k)] + sum[idx(i, j, k + 1)] -
                                     sum[idx(i + 1, j + 1, k)] - sum[idx(i + 1, j, k + 1)] - sum[idx(i, j + 1, k + 1)] +
                                     sum[idx(i + 1, j + 1, k + 1)];
    // The cell-centre rule's total is not exactly 1: normalise so that no wall = 0.
    const double total = sum[idx(0, 0, 0)];
    suffix_.resize(sum.size());
    for (std::size_t q = 0; q < sum.size(); ++q) suffix_[q] = float(sum[q] / total);
}

float DomainTable::at(float a, float b, float c) const {
    // Trilinear in the suffix table at offsets (a, b, c) in [-h, h].
    auto coord = [&](float v, int& i, float& f) {
        const float u = std::clamp((v + h_) / cell_, 0.0f, float(n_ - 1) - 1e-4f);
        i = int(u), f = u - float(i);
    };
    int i, j, k;
    float fi, fj, fk;
    coord(a, i, fi), coord(b, j, fj), coord(c, k, fk);
    auto T = [&](int di, int dj, int dk) {
        return suffix_[(std::size_t(i + di) * std::size_t(n_) + std::size_t(j + dj)) * std::size_t(n_) + std::size_t(k + dk)];
    };
    const float c00 = T(0, 0, 0) + fk * (T(0, 0, 1) - T(0, 0, 0)), c01 = T(0, 1, 0) + fk * (T(0, 1, 1) - T(0, 1, 0));
    const float c10 = T(1, 0, 0) + fk * (T(1, 0, 1) - T(1, 0, 0)), c11 = T(1, 1, 0) + fk * (T(1, 1, 1) - T(1, 1, 0));
    const float c0 = c00 + fj * (c01 - c00), c1 = c10 + fj * (c11 - c10);
    return c0 + fi * (c1 - c0);
}

float DomainTable::inside(const glm::vec3& d) const { return at(-d.x, -d.y, -d.z); }

glm::vec3 DomainTable::gradient(const glm::vec3& d) const {
    glm::vec3 g;
    for (int a = 0; a < 3; ++a) {
        glm::vec3 p = d, m = d;
        p[a] += cell_, m[a] -= cell_;
        g[a] = (inside(p) - inside(m)) / (2.0f * cell_);
    }
    return g;
}

float wallOffset(float r, float h, const WallTable& table, const std::function<float(float)>& W) {
    double half = 0.0, full = 0.0;
    const int reach = int(std::ceil(h / (2.0f * r)));
    for (int z = -reach; z <= reach; ++z)
        for (int y = -reach; y <= reach; ++y)
            for (int x = -reach; x <= reach; ++x) {
                const float d = 2.0f * r * std::sqrt(float(x * x + y * y + z * z));
                if (d >= h) continue;
                full += W(d);
                if (y >= 0) half += W(d);
            }
    const float target = float(1.0 - half / full);
    // Phi decreases with the distance: bisection on [-r, 2r] for Phi(r + o) = target.
    float lo = -r, hi = 2.0f * r;
    for (int it = 0; it < 60; ++it) {
        const float mid = 0.5f * (lo + hi);
        if (table.phi(r + mid) > target) lo = mid;
        else hi = mid;
    }
    return 0.5f * (lo + hi);
}

WallTerm wallTerm(const Scene& scene, const std::vector<ColliderMesh>& meshes, float support, const glm::vec3& x,
                  const WallTables& t) {
    WallTerm w;
    // The domain: distance to the nearer face on each axis (signed, + inside),
    // grown by the offset, and which side it is on.
    glm::vec3 d, side;
    bool near = false;
    for (int a = 0; a < 3; ++a) {
        const float lo = x[a] - scene.domain.min[a], hi = scene.domain.max[a] - x[a];
        d[a] = std::max(std::min(lo, hi) + t.offset, t.nearest);
        side[a] = lo <= hi ? 1.0f : -1.0f;  // +1: the wall is below on this axis
        near = near || d[a] < support;
    }
    if (near) {
        const glm::vec3 dc = glm::min(d, glm::vec3(support));
        w.density = 1.0f - t.domainDensity.inside(dc);
        // d rho / dx_a = -d inside / d d_a * d d_a / dx_a, with d d_a / dx_a = side_a.
        w.gradient = -t.domainDensity.gradient(dc) * side;
    }
    forEachCollider(scene, meshes, x, support, [&](const Collider&, const SurfacePoint& s) {
        const float dist = std::max(s.distance + t.offset, t.nearest);
        if (dist >= support) return;
        w.density += t.density.phi(dist);
        w.gradient -= t.density.slab(dist) * s.normal;
    });
    return w;
}

}  // namespace meniscus::sim
