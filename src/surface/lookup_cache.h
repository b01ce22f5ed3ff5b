// The per-block particle lookup cache (thesis §4.2.4 after Rosenberg &
// Birdwell 2008): one projection slice of (n+1)^2 columns; column (i, j) lists
// the particles that influence any corner on it, sorted by z, each with the
// integer slice range [minK, maxK] it can reach and the slab midK of its
// centre. Finding the particles of a corner is then integer comparisons only:
// a binary search on midK, a scan, and minK <= k <= maxK; the kernel itself
// is evaluated on the exact squared distance.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "surface/field.h"
#include "surface/grid.h"

namespace meniscus::surface {

class LookupCache {
public:
    // Fills the columns of the block whose corner (0,0,0) is global corner
    // `corner0`, from `particles` (indices into `positions`, sorted by z then index).
    void build(const Grid& grid, const Field& field, glm::ivec3 corner0, std::span<const glm::vec3> positions,
               std::span<const std::uint32_t> particles);

    // Raw field at local corner (i, j, k), i, j, k in [0, n]; zk is the
    // corner's world z (Grid::corner).
    float value(int i, int j, int k, float zk) const {
        const std::size_t c = std::size_t(j) * std::size_t(side_) + std::size_t(i);
        const Entry* first = entries_.data() + start_[c];
        const Entry* last = entries_.data() + start_[c + 1];
        // First entry whose centre slab can reach slice k (midK is non-decreasing).
        const int lo = k - reach_;
        std::size_t count = std::size_t(last - first);
        while (count > 0) {
            const std::size_t half = count / 2;
            if (first[half].midK < lo) {
                first += half + 1;
                count -= half + 1;
            } else {
                count = half;
            }
        }
        const int hi = k + reach_;
        float sum = 0.0f;
        for (const Entry* e = first; e != last && e->midK <= hi; ++e) {
            if (e->minK > k || e->maxK < k) continue;
            const float dz = e->z - zk;
            sum += field_.kernel(e->dxy2 + dz * dz);
        }
        return sum;
    }

    std::size_t bytes() const { return entries_.capacity() * sizeof(Entry) + start_.capacity() * sizeof(std::uint32_t); }
    std::size_t entryCount() const { return entries_.size(); }

private:
    struct Entry {
        float z;      // particle centre z, metres
        float dxy2;   // squared horizontal distance to the column, m^2
        std::int16_t minK, maxK, midK, pad;
    };
    Field field_;
    int side_ = 0;   // n + 1
    int reach_ = 0;  // slabs a particle centre can be from a slice it influences, plus slack
    std::vector<std::uint32_t> start_;  // CSR: column c's entries are [start_[c], start_[c+1])
    std::vector<Entry> entries_;
    std::vector<std::uint32_t> fill_;
};

}  // namespace meniscus::surface
