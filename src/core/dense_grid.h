// A dense uniform grid over the points' bounding box, for neighbour queries
// that touch every point (the anisotropy's PCA): the points sorted by cell
// with a counting sort (O(N), in input order within a cell, so deterministic),
// cells in x-fastest order, so the cells of one row of a neighbourhood are
// one contiguous range of points and no hashing is needed. It refuses (build
// returns false) when the box would need too many cells (far outliers, a
// cell far smaller than the spread); HashGrid (hash_grid.h) handles those.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace meniscus::detail {

class DenseGrid {
public:
    // Grids `pts` with cubic cells of side `cell`; false (and nothing built)
    // when that takes more than maxCells cells or a coordinate is not finite.
    bool build(std::span<const glm::vec3> pts, float cell, std::size_t maxCells) {
        if (pts.empty() || !(cell > 0.0f)) return false;
        glm::vec3 lo(pts[0]), hi(pts[0]);
        for (const glm::vec3& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
        const glm::vec3 extent = (hi - lo) / cell;
        if (!std::isfinite(extent.x) || !std::isfinite(extent.y) || !std::isfinite(extent.z)) return false;
        for (int a = 0; a < 3; ++a) {
            if (extent[a] > float(maxCells)) return false;
            dims_[a] = int(extent[a]) + 1;
        }
        if (double(dims_[0]) * dims_[1] * dims_[2] > double(maxCells)) return false;
        lo_ = lo, inv_ = 1.0f / cell;
        const std::size_t cells = std::size_t(dims_[0]) * dims_[1] * dims_[2];
        std::vector<std::uint32_t> cellOfPoint(pts.size());
        start_.assign(cells + 1, 0);
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const glm::ivec3 c = cellOf(pts[i]);
            cellOfPoint[i] = std::uint32_t(index(c.x, c.y, c.z));
            ++start_[cellOfPoint[i] + 1];
        }
        for (std::size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
        std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
        sorted_.resize(pts.size());
        order_.resize(pts.size());
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const std::uint32_t at = next[cellOfPoint[i]]++;
            sorted_[at] = pts[i];
            order_[at] = std::uint32_t(i);
        }
        return true;
    }

    std::size_t cellCount() const { return start_.empty() ? 0 : start_.size() - 1; }
    // The points in cell order, and the input index of each.
    const std::vector<glm::vec3>& points() const { return sorted_; }
    const std::vector<std::uint32_t>& order() const { return order_; }
    // Cell c (x-fastest linear index) holds points()[begin(c) .. begin(c + 1)).
    std::uint32_t begin(std::size_t c) const { return start_[c]; }
    glm::ivec3 coords(std::size_t c) const {
        const int x = int(c % std::size_t(dims_.x)), y = int(c / std::size_t(dims_.x) % std::size_t(dims_.y));
        return {x, y, int(c / (std::size_t(dims_.x) * std::size_t(dims_.y)))};
    }

    // Calls f(begin, end) for each row of cells (x from c.x - reach to
    // c.x + reach) of the (2 reach + 1)^2 rows around cell c that lie in
    // the grid: the points of the cube of cells around c, a range per row.
    template <class F>
    void forRowsNear(const glm::ivec3& c, int reach, F&& f) const {
        const int x0 = std::max(c.x - reach, 0), x1 = std::min(c.x + reach, dims_.x - 1);
        for (int z = std::max(c.z - reach, 0); z <= std::min(c.z + reach, dims_.z - 1); ++z)
            for (int y = std::max(c.y - reach, 0); y <= std::min(c.y + reach, dims_.y - 1); ++y)
                f(start_[index(x0, y, z)], start_[index(x1, y, z) + 1]);
    }

private:
    glm::ivec3 cellOf(const glm::vec3& p) const {
        const glm::vec3 u = (p - lo_) * inv_;
        return glm::clamp(glm::ivec3(u), glm::ivec3(0), dims_ - 1);
    }
    std::size_t index(int x, int y, int z) const {
        return (std::size_t(z) * std::size_t(dims_.y) + std::size_t(y)) * std::size_t(dims_.x) + std::size_t(x);
    }

    glm::vec3 lo_{0.0f};
    float inv_ = 1.0f;
    glm::ivec3 dims_{0};
    std::vector<std::uint32_t> start_;
    std::vector<glm::vec3> sorted_;
    std::vector<std::uint32_t> order_;
};

}  // namespace meniscus::detail
