// The particles sorted into the cells of a uniform grid, for the queries
// of a vertex or a particle against every particle within a support
// (attributes.cpp, smoothing.cpp): keys in one sorted array, the same order
// for any thread count.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace meniscus::surface {

// Cell keys of a grid of cell h: 21 bits per axis, z major, so the three
// cells of a row (x - 1 .. x + 1) are one run of keys. Coordinates are
// clamped to the grid's 2^21 cells a side: a far outlier shares an edge
// cell, and the distance test keeps it out of every sum it does not reach.
inline constexpr std::int64_t kAxisCells = std::int64_t(1) << 21;

struct CellGrid {
    glm::dvec3 origin{0.0};
    double invCell = 0.0;
    std::vector<std::uint64_t> keys;       // sorted
    std::vector<std::uint32_t> particles;  // the particle of each key
    std::vector<glm::vec3> positions;      // and its position, in the same order

    std::int64_t axis(double v, int a) const {
        const double c = std::floor((v - origin[a]) * invCell) + double(kAxisCells / 2);
        return std::int64_t(std::clamp(c, 0.0, double(kAxisCells - 1)));
    }
    static std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z) {
        return (std::uint64_t(z) << 42) | (std::uint64_t(y) << 21) | std::uint64_t(x);
    }
    // Calls f(s) for every slot s of the sorted arrays whose cell is within
    // `reach` cells of cell `cellKey` along each axis, in the arrays' order
    // (row by row, z then y; each row's cells one run of keys).
    template <class F>
    void forNear(std::uint64_t cellKey, std::int64_t reach, F&& f) const {
        const auto cx = std::int64_t(cellKey & (kAxisCells - 1)), cy = std::int64_t((cellKey >> 21) & (kAxisCells - 1)),
                   cz = std::int64_t(cellKey >> 42);
        for (std::int64_t z = std::max<std::int64_t>(cz - reach, 0); z <= std::min(cz + reach, kAxisCells - 1); ++z)
            for (std::int64_t y = std::max<std::int64_t>(cy - reach, 0); y <= std::min(cy + reach, kAxisCells - 1); ++y) {
                const std::uint64_t lo = key(std::max<std::int64_t>(cx - reach, 0), y, z);
                const std::uint64_t hi = key(std::min(cx + reach, kAxisCells - 1), y, z);
                for (auto i = std::lower_bound(keys.begin(), keys.end(), lo); i != keys.end() && *i <= hi; ++i)
                    f(std::size_t(i - keys.begin()));
            }
    }
};

inline CellGrid makeGrid(const std::vector<glm::vec3>& positions, double cell) {
    CellGrid g;
    glm::dvec3 lo(INFINITY);
    for (const glm::vec3& p : positions) lo = glm::min(lo, glm::dvec3(p));
    g.origin = lo;
    g.invCell = 1.0 / cell;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(positions.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, positions.size()), [&](const auto& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            const glm::vec3& p = positions[i];
            keyed[i] = {CellGrid::key(g.axis(p.x, 0), g.axis(p.y, 1), g.axis(p.z, 2)), std::uint32_t(i)};
        }
    });
    tbb::parallel_sort(keyed.begin(), keyed.end());  // unique pairs: one order for any split
    g.keys.resize(keyed.size());
    g.particles.resize(keyed.size());
    g.positions.resize(keyed.size());
    for (std::size_t i = 0; i < keyed.size(); ++i) {
        g.keys[i] = keyed[i].first;
        g.particles[i] = keyed[i].second;
        g.positions[i] = positions[keyed[i].second];
    }
    return g;
}

}  // namespace meniscus::surface
