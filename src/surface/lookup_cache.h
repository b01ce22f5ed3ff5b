// The per-block particle lookup cache (thesis §4.2.4 after Rosenberg &
// Birdwell 2008): one projection slice of (n+1)^2 columns; column (i, j) lists
// the particles that influence any corner on it, sorted by z, each with the
// integer slice range [minK, maxK] it can reach and the slab midK of its
// centre. Finding the particles of a corner is then integer comparisons only:
// a binary search on midK and minK <= k <= maxK; the kernel itself is
// evaluated on the exact squared distance.
//
// The block's particles are copied once (z order) and bucketed by row, and a
// row's columns are filled lazily when a corner on it is first asked for, so
// a block's cache costs only what its surface touches.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "surface/field.h"
#include "surface/grid.h"

namespace meniscus::surface {

class LookupCache {
public:
    // Corners per column pass: the marcher asks for a corner and gets the
    // next kLanes up the column with it (the walk goes up, and a surface
    // column needs two or three consecutive corners).
    static constexpr int kLanes = 4;

    // Fills the row buckets of the block whose corner (0,0,0) is global corner
    // `corner0`, from `particles` (indices into `positions`, sorted by z then index).
    void build(const Grid& grid, const Field& field, glm::ivec3 corner0, std::span<const glm::vec3> positions,
               std::span<const std::uint32_t> particles);

    // Raw field at local corners (i, j, k + q), q < kLanes, in one pass over
    // the column; zs[q] is the world z of slice k + q (Grid::corner). Each
    // sum adds the column's entries in z order, an entry outside [minK, maxK]
    // or past the support adding exactly 0, so a corner's float depends only
    // on the particles that reach it -- the same in every block, whatever
    // window the pass started from.
    void values(int i, int j, int k, const float* zs, float* out);
    // The same sums without SIMD: the reference the SSE path is tested
    // against bit for bit, and the path where SSE2 is missing.
    void valuesScalar(int i, int j, int k, const float* zs, float* out);

    std::size_t bytes() const { return entryBytes_; }
    std::size_t entries() const { return entryBytes_ / sizeof(Entry); }
    std::size_t rowsBuilt() const { return rowsBuilt_; }

private:
    struct Entry {
        float z;      // particle centre z, metres
        float dxy2;   // squared horizontal distance to the column, m^2
        std::int16_t minK, maxK, midK, pad;
    };
    void buildRow(int j);
    std::span<const Entry> window(int i, int j, int k);  // column (i, j)'s entries for slices k .. k + kLanes - 1

    Field field_;
    const Grid* grid_ = nullptr;
    int side_ = 0;   // n + 1
    int reach_ = 0;  // slabs a particle centre can be from a slice it influences, plus slack
    long kLo_ = 0, kHi_ = 0, zOrigin_ = 0, xOrigin_ = 0;
    std::vector<float> colX_, colY_;
    // The block's particles in z order: positions and centre slab.
    std::vector<float> px_, py_, pz_;
    std::vector<std::int16_t> mid_;
    std::vector<std::int16_t> reachOf_;  // slices reached, by squared horizontal distance bucket
    // Row j's particles (local indices, ascending = z order):
    // rowList_[rowStart_[j] .. rowStart_[j + 1]).
    std::vector<std::uint32_t> rowStart_, rowList_;
    std::vector<std::uint8_t> built_;  // per row
    // Column c's entries are entries_[start_[c], ends_[c]).
    std::vector<std::uint32_t> start_, ends_;
    std::vector<Entry> entries_;
    std::vector<std::uint32_t> count_;
    std::vector<std::pair<std::int16_t, std::int16_t>> spans_;  // a row's particles' column runs
    std::size_t entryBytes_ = 0;
    std::size_t rowsBuilt_ = 0;
};

}  // namespace meniscus::surface
