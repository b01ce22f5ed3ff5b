// Uniform-grid neighbour search (cell size = the kernel support h): a counting
// sort of the particles by cell every step, and neighbour lists in CSR form.
// The particles themselves are permuted into z-curve (Morton) order of their
// cells every few steps (zOrder), so neighbours sit close in memory.
// Deterministic: every list is in cell order, then particle order, whatever
// the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/sim.h"
#include "sim/packed.h"

namespace meniscus::sim {

class CellGrid {
public:
    // The grid covers `box` grown by one cell; positions outside are clamped
    // to the border cells (they still find their true neighbours there).
    void configure(const Box& box, float cellSize);
    // Rebuilds the cell lists of `points`.
    void build(std::span<const glm::vec3> points);

    glm::ivec3 cellOf(const glm::vec3& p) const {
        const glm::vec3 c = glm::floor((p - origin_) * invCell_);
        // Clamp in float first: a far point must not overflow the int
        // conversion. max(0, c) is (0 < c ? c : 0), so a NaN (a diverged run,
        // stopped by the step's check after this) lands in cell 0 instead of
        // being converted, which is undefined; for numbers it is clamp().
        const glm::vec3 hi = glm::vec3(dims_ - 1);
        return glm::ivec3(glm::min(hi, glm::max(glm::vec3(0.0f), c)));
    }
    std::size_t linear(const glm::ivec3& c) const {
        return (std::size_t(c.z) * std::size_t(dims_.y) + std::size_t(c.y)) * std::size_t(dims_.x) + std::size_t(c.x);
    }
    glm::ivec3 dims() const { return dims_; }
    std::size_t cellCount() const { return cellStart_.empty() ? 0 : cellStart_.size() - 1; }

    // Calls f(b, e) for each of the 9 rows of cells around p that can hold a
    // point within `reach` of it (reach <= the cell size): the points
    // sortedIndex(k), at sortedCoordinates(0..2)[k], for k in [b, e) (not
    // distance-tested). A row's end cells are left out where p's chord
    // through the row does not reach them, and rows wholly out of reach are
    // skipped: a quarter fewer candidates, and the same lists (the cells left
    // out hold no point within reach). The coordinates are a copy in cell
    // order, so each row's cells stream from one contiguous run of memory.
    template <class F>
    void forEachRowNear(const glm::vec3& p, float reach, F&& f) const {
        const glm::ivec3 c = cellOf(p);
        const glm::ivec3 lo = glm::max(c - 1, glm::ivec3(0)), hi = glm::min(c + 1, dims_ - 1);
        // p within its cell, in cells; a point clamped into a border cell
        // (outside the grid) gets no trimming.
        const glm::vec3 u = (p - origin_) * invCell_ - glm::vec3(c);
        const bool inCell = glm::all(glm::greaterThanEqual(u, glm::vec3(0.0f))) && glm::all(glm::lessThanEqual(u, glm::vec3(1.0f)));
        // In cells, with a margin for the rounding of u against the distance test's.
        const float reach2 = inCell ? reach * reach * (invCell_ * invCell_) * (1.0f + 1e-4f) + 1e-4f : 1e30f;
        auto gap = [](int cell, int own, float at) { return cell < own ? at : cell > own ? 1.0f - at : 0.0f; };
        for (int z = lo.z; z <= hi.z; ++z) {
            const float gz = gap(z, c.z, u.z);
            for (int y = lo.y; y <= hi.y; ++y) {
                const float gy = gap(y, c.y, u.y), chord2 = reach2 - (gy * gy + gz * gz);
                if (chord2 <= 0.0f) continue;
                const int x0 = lo.x < c.x && u.x * u.x < chord2 ? lo.x : c.x;
                const int x1 = hi.x > c.x && (1.0f - u.x) * (1.0f - u.x) < chord2 ? hi.x : c.x;
                const std::size_t row = linear({0, y, z});
                f(cellStart_[row + std::size_t(x0)], cellStart_[row + std::size_t(x1) + 1]);
            }
        }
    }
    std::uint32_t sortedIndex(std::uint32_t k) const { return sorted_[k]; }
    // Where point i sits in that order: sortedIndex(slotOf(i)) == i.
    std::uint32_t slotOf(std::uint32_t i) const { return slot_[i]; }
    // The positions in cell order by coordinate (x, y, z arrays), each padded with
    // kPad far-away values so that an 8-wide load from any k < size is safe.
    static constexpr std::size_t kPad = 8;
    const float* sortedCoordinates(int axis) const { return sortedAxis_[std::size_t(axis)].data(); }

    // Morton (z-curve) key of a point's cell: the order zOrder sorts by.
    std::uint64_t mortonKey(const glm::vec3& p) const;

private:
    glm::vec3 origin_{0.0f};
    float invCell_ = 1.0f;
    glm::ivec3 dims_{1};
    std::vector<std::uint32_t> cellStart_;  // cellCount + 1
    std::vector<std::uint32_t> sorted_;     // point indices by cell
    std::vector<std::uint32_t> slot_;       // its inverse
    std::vector<float> sortedAxis_[3];      // their coordinates in the same order, padded
    std::vector<std::uint32_t> cellOfPoint_;
};

// The permutation that puts points in z-curve order of their cells (stable).
std::vector<std::uint32_t> zOrder(const CellGrid& grid, std::span<const glm::vec3> points);

// One neighbour of a particle: its index and the kernel gradient's factor g,
// grad W(x_i - x_j) = g (x_i - x_j) (both kernels' gradients point along the
// offset). 8 bytes: the pressure solvers stream these lists several times a
// step, and memory, not arithmetic, bounds them; the offset is recomputed
// from positions, which stay in cache (z-order).
struct Neighbour {
    // Left uninitialised: the lists are resized, then written in place.
    Neighbour() {}  // NOLINT: not = default, so resize() does not zero each entry
    std::uint32_t j;
    float g;
};

// Neighbour lists: the neighbours of particle i are of(i), count(i) of them.
// Each chunk of kChunk particles keeps its own array (filled by one task), so
// the build never joins them into one.
struct NeighbourLists {
    static constexpr std::size_t kChunk = 1024;
    std::vector<std::vector<Neighbour>> chunkEntries;
    std::vector<std::uint32_t> first;  // per particle: its first entry in its chunk's array
    std::vector<std::uint32_t> counts;
    std::uint32_t count(std::size_t i) const { return counts[i]; }
    std::span<const Neighbour> of(std::size_t i) const {
        return {chunkEntries[i / kChunk].data() + first[i], counts[i]};
    }
};

// Lists of every point of `grid` within `support` of each of `points` (with
// `self`, `points` must be the points the grid was built from, and each one's
// own entry is left out), with kernel values from
// `kernel(F4 r, F4& W, F4& g)` (packed.h: four distances at once; g the
// gradient's factor); the
// sum of W over each list goes to `wSum` (when not empty). One pass, in
// fixed chunks: the same lists for any thread count. Parallel (oneTBB).
template <class Kernel>
void buildNeighbourLists(std::span<const glm::vec3> points, const CellGrid& grid, float support, bool self,
                         const Kernel& kernel, NeighbourLists& out, std::span<float> wSum);

}  // namespace meniscus::sim

#include "sim/neighbour_search_impl.h"
