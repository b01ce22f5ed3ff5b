// Anisotropic kernels, Yu & Turk 2013 (anisotropy.h). Per particle, in one
// pass over its neighbourhood: the weighted mean offset mu (their eq. 10,
// relative to the particle so nothing large cancels), the weighted
// covariance C = E_w[d d^T] - mu mu^T (eq. 9), its eigen-decomposition
// C = R diag(s1, s2, s3) R^T, the axes (eq. 13, volume-preserving, see
// AnisotropyParams) and the smoothed centre x + lambda mu (eq. 6).
//
// The neighbour search: a dense grid over the bounds (core/dense_grid.h; the
// hashed grid of core/hash_grid.h when far outliers would make it too
// large) with cells of R, walked cell by cell: the candidates of the 3^3
// cells around a cell, as ranges of the sorted points, serve all of that
// cell's particles. The sums run in the grid's fixed order, so the result
// does not depend on the thread count.
#include "core/anisotropy.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/dense_grid.h"
#include "core/hash_grid.h"
#include "core/lanes.h"
#include "shared/anisotropy.h"



namespace meniscus {

namespace {

// The neighbour loop runs over four candidates at a time (core/lanes.h).
using F4 = lanes::FloatV;
using I4 = lanes::IntV;
constexpr std::size_t kLanes = lanes::kLanes;
constexpr float kFar = 1e18f;  // padding: |d|^2 ~ 3e36 stays finite, outside any R
inline double hsum(F4 v) { return (double(v[0]) + double(v[1])) + (double(v[2]) + double(v[3])); }

// A matrix from its unit axes (columns of r) and values along them: r diag(v) r^T.
glm::mat3 fromAxes(const glm::dmat3& r, const glm::dvec3& v) { return glm::mat3(shared::anisotropyFromAxes(r, v)); }

}  // namespace

EllipsoidShape sphereShape(float radius) {
    return {glm::mat3(1.0f / radius), glm::mat3(radius * radius)};
}

EllipsoidShape scaledShape(const EllipsoidShape& shape, float scale) {
    return {shape.m * (1.0f / scale), shape.q * (scale * scale)};
}

EllipsoidShape ellipsoidShape(const glm::mat3& axes, const glm::vec3& a) {
    const glm::dmat3 r(axes);
    const glm::dvec3 ad(a);
    return {fromAxes(r, 1.0 / ad), fromAxes(r, ad * ad)};
}

// The formulas (Smith 1961, Kopp 2008) are src/shared/anisotropy.h's, shared
// with the GPU's shaders/anisotropy.comp.
void symmetricEigen(const glm::dmat3& a, glm::dvec3& values, glm::dmat3& vectors) {
    shared::anisotropyEigen(a, values, vectors);
}

namespace {

// One particle's ellipsoid from its candidate neighbours (ranges of the
// sorted points): returns whether it is isolated.
struct Pca {
    float R2, invR3;
    const AnisotropyParams& params;

    // The candidates: points [b, e) of each range of the SoA arrays xs, ys,
    // zs (padded past the last point, so a whole vector may be loaded at the
    // end of a range; the lanes past it are masked).
    // `radius`: the particle's own radius (its volume, and its size alone).
    bool operator()(const glm::vec3& p, float radius, const float* xs, const float* ys, const float* zs,
                    std::span<const std::pair<std::uint32_t, std::uint32_t>> ranges, glm::vec3& centre,
                    EllipsoidShape& shape) const {
        // Weighted sums of the offsets d = x_j - x_i: W, sum w d, sum w d d^T,
        // lane by lane in float, then added up in a fixed order.
        F4 W{}, sx{}, sy{}, sz{}, sxx{}, sxy{}, sxz{}, syy{}, syz{}, szz{};
        I4 inside{};
        const I4 lane = {0, 1, 2, 3};
        for (const auto& [b, e] : ranges)
        for (std::uint32_t k = b; k < e; k += kLanes) {
            F4 dx, dy, dz;
            std::memcpy(&dx, xs + k, sizeof dx);
            std::memcpy(&dy, ys + k, sizeof dy);
            std::memcpy(&dz, zs + k, sizeof dz);
            dx -= p.x, dy -= p.y, dz -= p.z;
            const F4 d2 = dx * dx + dy * dy + dz * dz;
            const I4 in = (d2 < R2) & (lane < std::int32_t(e - k));
            const F4 w = lanes::selectV(in, shared::anisotropyWeight(d2, lanes::sqrtV(d2), invR3));  // 1 - (|d| / R)^3 (Yu & Turk eq. 11)
            inside -= in;  // `in` is -1 where true
            const F4 wx = w * dx, wy = w * dy, wz = w * dz;
            W += w, sx += wx, sy += wy, sz += wz;
            sxx += wx * dx, sxy += wx * dy, sxz += wx * dz;
            syy += wy * dy, syz += wy * dz, szz += wz * dz;
        }
        const int count = (inside[0] + inside[1]) + (inside[2] + inside[3]);
        const double Wd = hsum(W);  // >= 1: the particle itself
        const glm::dvec3 mu = glm::dvec3(hsum(sx), hsum(sy), hsum(sz)) / Wd;
        centre = glm::vec3(glm::dvec3(p) + double(params.smoothing) * mu);  // Yu & Turk eq. 6
        if (count - 1 < params.minNeighbours) {
            shape = sphereShape(params.kn * radius);
            return true;
        }
        const double cxx = hsum(sxx), cxy = hsum(sxy), cxz = hsum(sxz);
        const double cyy = hsum(syy), cyz = hsum(syz), czz = hsum(szz);
        glm::dmat3 cov;  // Yu & Turk eq. 9, about the weighted mean
        cov[0] = glm::dvec3(cxx, cxy, cxz) / Wd - mu.x * mu;
        cov[1] = glm::dvec3(cxy, cyy, cyz) / Wd - mu.y * mu;
        cov[2] = glm::dvec3(cxz, cyz, czz) / Wd - mu.z * mu;
        glm::dvec3 sigma;
        glm::dmat3 axes;
        symmetricEigen(cov, sigma, axes);
        if (!(sigma[0] > 0.0)) {  // all neighbours on the particle itself
            shape = sphereShape(params.kn * radius);
            return true;
        }
        // Yu & Turk eq. 13: the smaller axes at least 1/kr of the largest;
        // then the volume of the sphere of radius r.
        const glm::dvec3 a = shared::anisotropyAxes(sigma, double(params.kr), double(radius));
        shape = {fromAxes(axes, 1.0 / a), fromAxes(axes, a * a)};
        if (params.keepSurface && a.z < radius)  // the free surface kept (shared/anisotropy.h)
            centre += glm::vec3(shared::anisotropySurfaceShift(mu, axes[2], a.z, double(radius), std::sqrt(double(R2))));
        return false;
    }
};

}  // namespace

void computeAnisotropy(std::span<const glm::vec3> positions, float radius, const AnisotropyParams& params,
                       Ellipsoids& out, std::span<const float> radii) {
    const std::size_t n = positions.size();
    out.centres.resize(n);
    out.shapes.resize(n);
    out.isolated = 0;
    if (n == 0) return;
    const float R = params.neighbourRadii * radius;
    const Pca pca{R * R, 1.0f / (R * R * R), params};
    const bool own = radii.size() == n;
    std::vector<std::uint8_t> isolated(n, 0);
    // Cells of R: the 3^3 cells around a particle's hold its neighbourhood.
    // The points in cell order as plain arrays (padded for whole-vector
    // loads), and per cell the ranges of its candidates, once for all its
    // particles. (Cells of R/2 scan fewer candidates, 5^3/8 of the volume
    // instead of 27, but in 25 short ranges per cell: measured slower, 56 ms
    // against 48 ms at R = 5 r on frame 21 with 2 threads.)
    std::vector<float> xs, ys, zs;
    auto run = [&](std::size_t cells, const std::vector<glm::vec3>& pts, const std::vector<std::uint32_t>& order,
                   auto&& ranges, auto&& range) {
        xs.assign(pts.size() + kLanes, kFar), ys.assign(pts.size() + kLanes, kFar), zs.assign(pts.size() + kLanes, kFar);
        for (std::size_t k = 0; k < pts.size(); ++k) xs[k] = pts[k].x, ys[k] = pts[k].y, zs[k] = pts[k].z;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 64), [&](const auto& block) {
            std::vector<std::pair<std::uint32_t, std::uint32_t>> near;
            for (std::size_t c = block.begin(); c != block.end(); ++c) {
                const auto [b, e] = range(c);
                if (b == e) continue;
                near.clear();
                ranges(c, near);
                for (std::uint32_t s = b; s < e; ++s) {
                    const std::uint32_t i = order[s];
                    isolated[i] = pca(pts[s], own ? radii[i] : radius, xs.data(), ys.data(), zs.data(), near,
                                      out.centres[i], out.shapes[i]);
                }
            }
        });
    };
    using Ranges = std::vector<std::pair<std::uint32_t, std::uint32_t>>;
    detail::DenseGrid dense;
    if (dense.build(positions, R, 8 * n + (std::size_t(1) << 20))) {
        // Dense: a row of three cells is one range of points.
        run(
            dense.cellCount(), dense.points(), dense.order(),
            [&](std::size_t c, Ranges& near) {
                dense.forRowsNear(dense.coords(c), 1, [&](std::uint32_t b, std::uint32_t e) {
                    if (b < e) near.emplace_back(b, e);
                });
            },
            [&](std::size_t c) { return std::pair(dense.begin(c), dense.begin(c + 1)); });
    } else {
        // Far outliers: the hashed grid (only occupied cells exist).
        const detail::HashGrid grid(positions, double(R), glm::dvec3(positions[0]));
        run(
            grid.cellCount(), grid.points(), grid.order(),
            [&](std::size_t c, Ranges& near) {
                const detail::HashGrid::Key key = grid.cellKey(c);
                for (int z = -1; z <= 1; ++z)
                    for (int y = -1; y <= 1; ++y)
                        for (int x = -1; x <= 1; ++x)
                            grid.forCellRange({key[0] + x, key[1] + y, key[2] + z},
                                              [&](std::uint32_t b, std::uint32_t e) { near.emplace_back(b, e); });
            },
            [&](std::size_t c) { return std::pair(grid.cellBegin(c), grid.cellEnd(c)); });
    }
    for (std::uint8_t v : isolated) out.isolated += v;
}

std::string checkAnisotropyParams(const AnisotropyParams& p) {
    if (!(p.neighbourRadii >= 2.0f && p.neighbourRadii <= 16.0f)) return "neighbourRadii: 2 to 16 particle radii";
    if (!(p.kr >= 1.0f && p.kr <= 16.0f)) return "kr: 1 to 16";
    if (!(p.kn > 0.0f && p.kn <= 1.0f)) return "kn: above 0, at most 1";
    if (p.minNeighbours < 0 || p.minNeighbours > 1000) return "minNeighbours: 0 to 1000";
    if (!(p.smoothing >= 0.0f && p.smoothing <= 1.0f)) return "smoothing: 0 to 1";
    return {};
}

}  // namespace meniscus
