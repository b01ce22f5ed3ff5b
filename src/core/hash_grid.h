// The core's neighbour search and SPH kernel (shared by the radius estimate
// in particles.cpp and the spray classification in spray.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <tbb/parallel_sort.h>

#include "shared/sph_kernels.h"

namespace meniscus::detail {

// Hashed uniform grid: points sorted by cell, and an open-addressing table
// from cell coordinates to each occupied cell's range. Only occupied cells
// exist, so a far outlier costs one cell, not a grid spanning the bounds.
class HashGrid {
public:
    using Key = std::array<std::int64_t, 3>;

    HashGrid(std::span<const glm::vec3> pts, double cell, const glm::dvec3& origin) : cell_(cell), origin_(origin) {
        std::vector<std::pair<Key, std::uint32_t>> keyed(pts.size());
        for (std::size_t i = 0; i < pts.size(); ++i) keyed[i] = {cellOf(pts[i]), std::uint32_t(i)};
        // By cell, then index: unique keys, so the order is the same however
        // the parallel sort splits the work.
        tbb::parallel_sort(keyed.begin(), keyed.end());
        sorted_.resize(pts.size());
        order_.resize(pts.size());
        for (std::size_t i = 0; i < keyed.size(); ++i) {
            sorted_[i] = pts[keyed[i].second];
            order_[i] = keyed[i].second;
            if (i == 0 || keyed[i].first != keyed[i - 1].first)
                cells_.push_back({keyed[i].first, std::uint32_t(i), std::uint32_t(i)});
            ++cells_.back().end;
        }
        std::size_t size = 16;
        while (size < 2 * cells_.size()) size *= 2;
        table_.assign(size, -1);
        for (std::size_t c = 0; c < cells_.size(); ++c) {
            std::size_t h = hash(cells_[c].key) & (size - 1);
            while (table_[h] >= 0) h = (h + 1) & (size - 1);
            table_[h] = std::int32_t(c);
        }
    }

    double cell() const { return cell_; }
    // The points in cell order (queries in this order touch memory locally).
    const std::vector<glm::vec3>& points() const { return sorted_; }
    // The input index of each point of points().
    const std::vector<std::uint32_t>& order() const { return order_; }

    // The occupied cells, in key order: cell c holds points()[begin .. end).
    std::size_t cellCount() const { return cells_.size(); }
    const Key& cellKey(std::size_t c) const { return cells_[c].key; }
    std::uint32_t cellBegin(std::size_t c) const { return cells_[c].begin; }
    std::uint32_t cellEnd(std::size_t c) const { return cells_[c].end; }

    // Calls f(begin, end) with the range in points() of the cell `key`, if it is occupied.
    template <class F>
    void forCellRange(const Key& key, F&& f) const {
        const std::size_t mask = table_.size() - 1;
        for (std::size_t h = hash(key) & mask; table_[h] >= 0; h = (h + 1) & mask) {
            const CellRange& c = cells_[std::size_t(table_[h])];
            if (c.key[0] != key[0] || c.key[1] != key[1] || c.key[2] != key[2]) continue;
            f(c.begin, c.end);
            return;
        }
    }

    // Cell coordinates, clamped far beyond any real grid (2^40 cells a side)
    // so that a huge coordinate over a tiny cell cannot overflow.
    Key cellOf(const glm::vec3& p) const {
        constexpr double kLimit = double(std::int64_t(1) << 40);
        Key k;
        for (int a = 0; a < 3; ++a)
            k[a] = std::int64_t(std::clamp(std::floor((double(p[a]) - origin_[a]) / cell_), -kLimit, kLimit));
        return k;
    }

    // Calls f(point) for every point in the cell `key` (none if it is empty).
    template <class F>
    void forCell(const Key& key, F&& f) const {
        forCellRange(key, [&](std::uint32_t b, std::uint32_t e) {
            for (std::uint32_t i = b; i < e; ++i) f(sorted_[i]);
        });
    }

    // Calls f(d2) with the squared distance of every point (p itself too)
    // closer to p than sqrt(reach2), which must not exceed the cell size: the
    // 27 cells around p's.
    template <class F>
    void forNear(const glm::vec3& p, float reach2, F&& f) const {
        const Key c = cellOf(p);
        for (int z = -1; z <= 1; ++z)
            for (int y = -1; y <= 1; ++y)
                for (int x = -1; x <= 1; ++x)
                    forCell({c[0] + x, c[1] + y, c[2] + z}, [&](const glm::vec3& o) {
                        const glm::vec3 d = o - p;
                        const float d2 = glm::dot(d, d);
                        if (d2 < reach2) f(d2);
                    });
    }

    // Nearest distance to a point other than p itself (distance > minDist),
    // searching shells of cells up to maxRing; +inf when it cannot be certain.
    float nearest(const glm::vec3& p, float minDist, int maxRing) const {
        const Key c = cellOf(p);
        float best2 = std::numeric_limits<float>::infinity();
        const float min2 = minDist * minDist;
        for (int ring = 0; ring <= maxRing; ++ring) {
            // Shells 0..ring-1 are searched; any point in shell `ring` or beyond
            // is at least (ring-1)*cell away, so a nearer hit is final.
            const float reach = float(double(ring - 1) * cell_);
            if (ring > 0 && best2 <= reach * reach) break;
            for (int z = -ring; z <= ring; ++z)
                for (int y = -ring; y <= ring; ++y)
                    for (int x = -ring; x <= ring; ++x) {
                        if (std::max({std::abs(x), std::abs(y), std::abs(z)}) != ring) continue;  // shell only
                        forCell({c[0] + x, c[1] + y, c[2] + z}, [&](const glm::vec3& q) {
                            const glm::vec3 d = q - p;
                            const float d2 = glm::dot(d, d);
                            if (d2 > min2 && d2 < best2) best2 = d2;
                        });
                    }
        }
        // Unsearched shells start maxRing*cell away: beyond that, not certain.
        const float certain = float(double(maxRing) * cell_);
        return best2 <= certain * certain ? std::sqrt(best2) : std::numeric_limits<float>::infinity();
    }

private:
    struct CellRange {
        Key key;
        std::uint32_t begin, end;
    };
    static std::size_t hash(const Key& k) {
        std::uint64_t h = std::uint64_t(k[0]) * 0x9E3779B97F4A7C15ull ^ std::uint64_t(k[1]) * 0xC2B2AE3D27D4EB4Full ^
                          std::uint64_t(k[2]) * 0x165667B19E3779F9ull;
        h ^= h >> 31;
        h *= 0xBF58476D1CE4E5B9ull;
        return std::size_t(h ^ (h >> 29));
    }

    double cell_;
    glm::dvec3 origin_;
    std::vector<glm::vec3> sorted_;
    std::vector<std::uint32_t> order_;
    std::vector<CellRange> cells_;
    std::vector<std::int32_t> table_;
};

// The normalised cubic spline with support radius H (shared/sph_kernels.h),
// in double: integrates to 1 over the ball of radius H.
inline double cubicKernel(double dist, double H) {
    const double q = dist / H;
    return q < 1.0 ? shared::sphKernelSigma(H) * shared::sphKernel(q) : 0.0;
}

}  // namespace meniscus::detail
