// Uniform grid and z-curve order (see neighbour_search.h).
#include "sim/neighbour_search.h"

#include <algorithm>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace meniscus::sim {

void CellGrid::configure(const Box& box, float cellSize) {
    invCell_ = 1.0f / cellSize;
    origin_ = box.min - glm::vec3(cellSize);
    const glm::vec3 ext = box.max - box.min + glm::vec3(2.0f * cellSize);
    dims_ = glm::max(glm::ivec3(glm::ceil(ext * invCell_)), glm::ivec3(1));
    cellStart_.assign(std::size_t(dims_.x) * std::size_t(dims_.y) * std::size_t(dims_.z) + 1, 0);
}

void CellGrid::build(std::span<const glm::vec3> points) {
    const std::size_t n = points.size();
    std::fill(cellStart_.begin(), cellStart_.end(), 0u);
    cellOfPoint_.resize(n);
    // The cells in parallel (half of this build's time, serial); the counts
    // and the scatter stay serial, which keeps each cell in point order.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) cellOfPoint_[i] = std::uint32_t(linear(cellOf(points[i])));
    });
    for (std::size_t i = 0; i < n; ++i) ++cellStart_[cellOfPoint_[i] + 1];
    for (std::size_t c = 1; c < cellStart_.size(); ++c) cellStart_[c] += cellStart_[c - 1];
    sorted_.resize(n);
    slot_.resize(n);
    std::vector<std::uint32_t> fill(cellStart_.begin(), cellStart_.end() - 1);
    for (auto& a : sortedAxis_) a.assign(n + kPad, 1e30f);  // the padding is never within reach
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t k = fill[cellOfPoint_[i]]++;
        sorted_[k] = std::uint32_t(i);
        slot_[i] = k;
        for (int a = 0; a < 3; ++a) sortedAxis_[a][k] = points[i][a];
    }
}

namespace {
// Spreads the low 21 bits of v to every third bit.
std::uint64_t spread3(std::uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}
}  // namespace

std::uint64_t CellGrid::mortonKey(const glm::vec3& p) const {
    const glm::ivec3 c = cellOf(p);
    return spread3(std::uint64_t(c.x)) | spread3(std::uint64_t(c.y)) << 1 | spread3(std::uint64_t(c.z)) << 2;
}

std::vector<std::uint32_t> zOrder(const CellGrid& grid, std::span<const glm::vec3> points) {
    std::vector<std::uint64_t> keys(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) keys[i] = grid.mortonKey(points[i]);
    std::vector<std::uint32_t> order(points.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
    return order;
}

}  // namespace meniscus::sim
