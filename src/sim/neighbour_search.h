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

namespace meniscus::sim {

class CellGrid {
public:
    // The grid covers `box` grown by one cell; positions outside are clamped
    // to the border cells (they still find their true neighbours there).
    void configure(const Box& box, float cellSize);
    // Rebuilds the cell lists of `points`.
    void build(std::span<const glm::vec3> points);

    glm::ivec3 cellOf(const glm::vec3& p) const;
    std::size_t linear(const glm::ivec3& c) const {
        return (std::size_t(c.z) * std::size_t(dims_.y) + std::size_t(c.y)) * std::size_t(dims_.x) + std::size_t(c.x);
    }
    glm::ivec3 dims() const { return dims_; }
    std::size_t cellCount() const { return cellStart_.empty() ? 0 : cellStart_.size() - 1; }

    // Calls f(j) for every point j in the 27 cells around p (not distance-tested).
    template <class F>
    void forEachNear(const glm::vec3& p, F&& f) const {
        const glm::ivec3 c = cellOf(p);
        const glm::ivec3 lo = glm::max(c - 1, glm::ivec3(0)), hi = glm::min(c + 1, dims_ - 1);
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y) {
                const std::size_t row = linear({0, y, z});
                const std::uint32_t b = cellStart_[row + std::size_t(lo.x)], e = cellStart_[row + std::size_t(hi.x) + 1];
                for (std::uint32_t k = b; k < e; ++k) f(sorted_[k]);
            }
    }

    // Morton (z-curve) key of a point's cell: the order zOrder sorts by.
    std::uint64_t mortonKey(const glm::vec3& p) const;

private:
    glm::vec3 origin_{0.0f};
    float invCell_ = 1.0f;
    glm::ivec3 dims_{1};
    std::vector<std::uint32_t> cellStart_;  // cellCount + 1
    std::vector<std::uint32_t> sorted_;     // point indices by cell
    std::vector<std::uint32_t> cellOfPoint_;
};

// The permutation that puts points in z-curve order of their cells (stable).
std::vector<std::uint32_t> zOrder(const CellGrid& grid, std::span<const glm::vec3> points);

// One neighbour of a particle: its index and the kernel gradient at
// x_i - x_j (in the solver's own kernel). 16 bytes: the pressure solvers
// stream these lists several times a step.
struct Neighbour {
    std::uint32_t j;
    glm::vec3 gradW;
};

// Neighbour lists in CSR form: the neighbours of particle i are
// entries[offsets[i] .. offsets[i+1]).
struct NeighbourLists {
    std::vector<std::uint32_t> offsets;
    std::vector<Neighbour> entries;
    std::vector<std::vector<Neighbour>> chunkEntries;  // the build's per-chunk lists, kept to reuse their memory
    std::span<const Neighbour> of(std::size_t i) const {
        return {entries.data() + offsets[i], entries.data() + offsets[i + 1]};
    }
};

// Lists of every point of `grid` (holding `others`) within `support` of each
// of `points` (the point itself excluded when `self`), with kernel values
// from `kernel(d, r, r^2) -> std::pair<float, glm::vec3>` (W, grad W); the
// sum of W over each list goes to `wSum` (when not empty). One pass, in
// fixed chunks whose lists are then joined in order: the same lists for any
// thread count. Parallel (oneTBB).
template <class Kernel>
void buildNeighbourLists(std::span<const glm::vec3> points, const CellGrid& grid, std::span<const glm::vec3> others,
                         float support, bool self, const Kernel& kernel, NeighbourLists& out, std::span<float> wSum);

}  // namespace meniscus::sim

#include "sim/neighbour_search_impl.h"
