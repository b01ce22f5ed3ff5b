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



namespace meniscus {

namespace {

// The neighbour loop runs over four candidates at a time (core/lanes.h).
using F4 = lanes::FloatV;
using I4 = lanes::IntV;
constexpr std::size_t kLanes = lanes::kLanes;
constexpr float kFar = 1e18f;  // padding: |d|^2 ~ 3e36 stays finite, outside any R
inline double hsum(F4 v) { return (double(v[0]) + double(v[1])) + (double(v[2]) + double(v[3])); }

// A matrix from its unit axes (columns of r) and values along them: r diag(v) r^T.
glm::mat3 fromAxes(const glm::dmat3& r, const glm::dvec3& v) {
    glm::dmat3 out(0.0);
    for (int k = 0; k < 3; ++k) out += v[k] * glm::outerProduct(r[k], r[k]);
    return glm::mat3(out);
}

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

namespace {

// A unit vector orthogonal to the unit vector v.
glm::dvec3 orthogonal(const glm::dvec3& v) {
    const glm::dvec3 other = std::abs(v.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    return glm::normalize(glm::cross(v, other));
}

// A unit eigenvector of a for the eigenvalue lambda: the longest cross
// product of two rows of a - lambda I (they span the orthogonal complement
// when lambda is simple). False when all are ~0 (lambda is not simple).
bool eigenvector(const glm::dmat3& a, double lambda, double scale, glm::dvec3& v) {
    const glm::dmat3 b = a - lambda * glm::dmat3(1.0);
    const glm::dvec3 r0(b[0][0], b[1][0], b[2][0]), r1(b[0][1], b[1][1], b[2][1]), r2(b[0][2], b[1][2], b[2][2]);
    const glm::dvec3 c[3] = {glm::cross(r0, r1), glm::cross(r0, r2), glm::cross(r1, r2)};
    int best = 0;
    for (int k = 1; k < 3; ++k)
        if (glm::dot(c[k], c[k]) > glm::dot(c[best], c[best])) best = k;
    const double len2 = glm::dot(c[best], c[best]);
    if (!(len2 > 1e-20 * scale * scale * scale * scale)) return false;
    v = c[best] / std::sqrt(len2);
    return true;
}

}  // namespace

void symmetricEigen(const glm::dmat3& a, glm::dvec3& values, glm::dmat3& vectors) {
    // Eigenvalues in closed form (O. K. Smith, "Eigenvalues of a symmetric
    // 3 x 3 matrix", CACM 4(4) 1961): with q = tr(a)/3 and p the scale of
    // a - qI, B = (a - qI)/p has eigenvalues 2 cos(phi + 2 pi k / 3), where
    // cos(3 phi) = det(B) / 2.
    const double p1 = a[1][0] * a[1][0] + a[2][0] * a[2][0] + a[2][1] * a[2][1];
    const double q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    const double p2 = (a[0][0] - q) * (a[0][0] - q) + (a[1][1] - q) * (a[1][1] - q) + (a[2][2] - q) * (a[2][2] - q) +
                      2.0 * p1;
    const double p = std::sqrt(p2 / 6.0);
    const double scale = std::max({std::abs(a[0][0]), std::abs(a[1][1]), std::abs(a[2][2]), std::sqrt(p1), 1e-300});
    if (!(p > 1e-12 * scale)) {  // a multiple of the identity: any frame
        values = glm::dvec3(q);
        vectors = glm::dmat3(1.0);
        return;
    }
    const glm::dmat3 bm = (a - q * glm::dmat3(1.0)) / p;
    const double r = std::clamp(glm::determinant(bm) / 2.0, -1.0, 1.0);
    const double phi = std::acos(r) / 3.0;
    constexpr double kThird = 2.0943951023931954923;  // 2 pi / 3
    const double e1 = q + 2.0 * p * std::cos(phi), e3 = q + 2.0 * p * std::cos(phi + kThird);
    values = glm::dvec3(e1, 3.0 * q - e1 - e3, e3);  // e1 >= e2 >= e3
    // Eigenvectors (after J. Kopp, "Efficient numerical diagonalization of
    // hermitian 3x3 matrices", 2008): the one of the eigenvalue farthest from
    // the middle one by cross products (it is simple), the other two by
    // diagonalising a in the plane orthogonal to it (a 2 x 2 rotation).
    const bool firstApart = values[0] - values[1] >= values[1] - values[2];
    const int k = firstApart ? 0 : 2;
    glm::dvec3 v;
    if (!eigenvector(a, values[k], scale, v)) {
        vectors = glm::dmat3(1.0);
        return;
    }
    const glm::dvec3 u = orthogonal(v), w = glm::cross(v, u);
    const double auu = glm::dot(u, a * u), auw = glm::dot(u, a * w), aww = glm::dot(w, a * w);
    // The rotation by theta with tan(2 theta) = 2 auw / (auu - aww) diagonalises [[auu, auw], [auw, aww]].
    const double theta = 0.5 * std::atan2(2.0 * auw, auu - aww);
    const double c = std::cos(theta), s = std::sin(theta);
    glm::dvec3 x = c * u + s * w, y = -s * u + c * w;  // eigenvalues: the larger along x
    const double ex = glm::dot(x, a * x), ey = glm::dot(y, a * y);
    if (firstApart) {
        values[1] = std::max(ex, ey), values[2] = std::min(ex, ey);
        if (ex < ey) std::swap(x, y);
        vectors = glm::dmat3(v, x, y);
    } else {
        values[0] = std::max(ex, ey), values[1] = std::min(ex, ey);
        if (ex < ey) std::swap(x, y);
        vectors = glm::dmat3(x, y, v);
    }
    if (glm::dot(glm::cross(vectors[0], vectors[1]), vectors[2]) < 0.0) vectors[2] = -vectors[2];
}

namespace {

// The weighted mean offset of a flat half-space's neighbourhood, in units of
// R: with w = 1 - (d/R)^3, E_w[d cos theta] over the half ball =
// (1/2) (R^4/4 - R^4/7) / (R^3/3 - R^3/6) / R = 9/28.
constexpr double kHalfSpaceOffset = 9.0 / 28.0;

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
            const F4 w = lanes::selectV(in, 1.0f - d2 * lanes::sqrtV(d2) * invR3);  // 1 - (|d| / R)^3 (Yu & Turk eq. 11)
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
        const double floor = sigma[0] / double(params.kr);
        const glm::dvec3 s3(sigma[0], std::max(sigma[1], floor), std::max(sigma[2], floor));
        const glm::dvec3 a = s3 * (double(radius) / std::cbrt(s3.x * s3.y * s3.z));
        shape = {fromAxes(axes, 1.0 / a), fromAxes(axes, a * a)};
        if (params.keepSurface && a.z < radius) {
            // At a free surface the neighbours' mean lies inward along the
            // shortest axis; the flattened ellipsoid would end a - a.z short
            // of the sphere's outer side. Move it out by that much, scaled by
            // how one-sided the neighbourhood is (a flat half-space's mean
            // offset is kHalfSpaceOffset R; a sheet's or the bulk's is ~0).
            const double m = glm::dot(mu, axes[2]);
            const double t = std::min(std::abs(m) / (kHalfSpaceOffset * std::sqrt(double(R2))), 1.0);
            centre += glm::vec3((m > 0.0 ? -1.0 : 1.0) * t * (double(radius) - a.z) * axes[2]);
        }
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
