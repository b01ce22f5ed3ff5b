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
        for (int a = 0; a < 3; ++a)
            if (extent[a] > float(maxCells)) return false;
        const glm::ivec3 dims = glm::ivec3(extent) + 1;
        if (double(dims.x) * dims.y * dims.z > double(maxCells)) return false;
        sort(pts, lo, cell, dims);
        return true;
    }

    // Like build, but never refuses finite points: when the whole box would
    // take more than maxCells cells of side minCell, the grid spans only the
    // box of the central 99.8 % of the points on each axis (grown by minCell)
    // with cells as much larger as needed, and the points beyond it are kept
    // in its boundary cells. Queries stay exact (a point within one cell of a
    // query is in the 3x3x3 cells around it after the same clamping: clamping
    // cell coordinates never moves two of them further apart); only the
    // boundary cells' outliers cost a distance test each.
    bool buildBounded(std::span<const glm::vec3> pts, float minCell, std::size_t maxCells) {
        if (build(pts, minCell, maxCells)) return true;
        if (pts.empty() || !(minCell > 0.0f) || maxCells < 1) return false;
        glm::vec3 lo(0.0f), hi(0.0f);
        std::vector<float> c(pts.size());
        for (int a = 0; a < 3; ++a) {
            for (std::size_t i = 0; i < pts.size(); ++i) c[i] = pts[i][a];
            const std::size_t k0 = pts.size() / 1000, k1 = pts.size() - 1 - k0;
            std::nth_element(c.begin(), c.begin() + std::ptrdiff_t(k0), c.end());
            lo[a] = c[k0] - minCell;
            std::nth_element(c.begin(), c.begin() + std::ptrdiff_t(k1), c.end());
            hi[a] = c[k1] + minCell;
            if (!std::isfinite(lo[a]) || !std::isfinite(hi[a])) return false;
        }
        const glm::dvec3 size = glm::dvec3(hi - lo);
        double cell = std::max(double(minCell), std::cbrt(size.x * size.y * size.z / double(maxCells)));
        for (int n = 0;; ++n) {  // grow until the cells fit (a flat box needs more than the cube root)
            const glm::dvec3 dims = glm::floor(size / cell) + 1.0;
            if (dims.x * dims.y * dims.z <= double(maxCells)) break;
            if (n == 64) return false;
            cell *= 1.25;
        }
        const glm::ivec3 dims = glm::ivec3(glm::floor(size / cell)) + 1;
        sort(pts, lo, float(cell), dims);
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

    // The grid's frame, for copies of it (the GL raycast uploads these):
    // cell (x, y, z) spans lo + cell * [x, x + 1) etc.
    glm::vec3 lo() const { return lo_; }
    float invCell() const { return inv_; }
    glm::ivec3 dims() const { return dims_; }
    const std::vector<std::uint32_t>& starts() const { return start_; }  // cellCount() + 1 entries

    // The (clamped) cell of a point; clamped as floats, so that a far point
    // never overflows the integer conversion.
    glm::ivec3 cellOf(const glm::vec3& p) const {
        const glm::vec3 u = glm::clamp((p - lo_) * inv_, glm::vec3(0.0f), glm::vec3(dims_ - 1));
        return glm::ivec3(u);
    }


private:
    // Counting sort of `pts` into the cells of side `cell` from `lo`, `dims`
    // of them (coordinates clamped into the grid).
    void sort(std::span<const glm::vec3> pts, const glm::vec3& lo, float cell, const glm::ivec3& dims) {
        lo_ = lo, inv_ = 1.0f / cell, dims_ = dims;
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
