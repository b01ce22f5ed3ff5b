// The per-block particle lookup cache (thesis §4.2.4 after Rosenberg &
// Birdwell 2008): one projection slice of (n+1)^2 columns; column (i, j) lists
// the particles that influence any corner on it, sorted by z, each with the
// integer slice range [minK, maxK] it can reach and the slab midK of its
// centre. Finding the particles of a corner is then integer comparisons only:
// a binary search on midK, a scan, and minK <= k <= maxK; the kernel itself
// is evaluated on the exact squared distance. The columns are filled lazily, a
// row (fixed j) and a chunk of kChunk slices at a time, when a corner there is
// first asked for, so a block's cache costs only what its surface touches.
#pragma once

#include <cstddef>
#include <algorithm>
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
    float value(int i, int j, int k, float zk) {
        float v;
        values<1>(i, j, k, &zk, &v);
        return v;
    }
    // Corners (i, j, k) and (i, j, k + 1) in one pass over the column: the
    // same two floats as two calls of value() (each sum adds the same terms in
    // the same order; the wider window only adds exact zeros).
    void value2(int i, int j, int k, float zk, float zk1, float* v0, float* v1) {
        const float zs[2] = {zk, zk1};
        float v[2];
        values<2>(i, j, k, zs, v);
        *v0 = v[0];
        *v1 = v[1];
    }

    std::size_t bytes() const { return entryBytes_; }
    std::size_t entries() const { return entryBytes_ / sizeof(Entry); }
    std::size_t rowsBuilt() const { return rowsBuilt_; }

private:
    struct Entry {
        float z;      // particle centre z, metres
        float dxy2;   // squared horizontal distance to the column, m^2
        std::int16_t minK, maxK, midK, pad;
    };
    // Slabs per chunk. Measured on the dam break (2 cores): 8 duplicated too
    // many entries (the support spans 8 slices at cube 0.5 r) and was slower
    // than one chunk per default block.
    static constexpr int kChunk = 32;
    // First entry in [first, last) with midK >= k (binary search).
    static const Entry* boundOf(const Entry* first, const Entry* last, int k) {
        std::size_t count = std::size_t(last - first);
        while (count > 0) {
            const std::size_t half = count / 2;
            if (first[half].midK < k) {
                first += half + 1;
                count -= half + 1;
            } else {
                count = half;
            }
        }
        return first;
    }
    void buildRowChunk(int j, int w);

    // The sums of corners (i, j, k) .. (i, j, k + N - 1), z of each in zs.
    template <int N>
    void values(int i, int j, int k, const float* zs, float* out) {
        const int w = std::min(k / kChunk, chunks_ - 1);
        const std::size_t rc = std::size_t(j) * std::size_t(chunks_) + std::size_t(w);
        if (!built_[rc]) buildRowChunk(j, w);
        const std::size_t c = (std::size_t(j) * std::size_t(side_) + std::size_t(i)) * std::size_t(chunks_) + std::size_t(w);
        const Entry* first = entries_.data() + start_[c];
        const Entry* last = entries_.data() + ends_[c];
        // The entries whose centre slab can reach one of the slices (midK is
        // non-decreasing): [lower bound of k - reach, upper bound of k + N - 1 + reach).
        const Entry* from = boundOf(first, last, k - reach_);
        const Entry* to = boundOf(from, last, k + N - 1 + reach_ + 1);
        // In order, branch-free: an entry outside [minK, maxK] adds exactly 0,
        // so the sum is the same float in every block whose list holds more or
        // fewer such entries (the kernel is 0 past the support too).
        float sum[N] = {};
        if (field_.kind == SurfaceField::Sph) {
            for (const Entry* e = from; e != to; ++e)
                for (int q = 0; q < N; ++q) {
                    const float dz = e->z - zs[q];
                    const float v = field_.sphKernel(e->dxy2 + dz * dz);
                    sum[q] += (e->minK <= k + q && k + q <= e->maxK) ? v : 0.0f;
                }
        } else {
            for (const Entry* e = from; e != to; ++e)
                for (int q = 0; q < N; ++q) {
                    const float dz = e->z - zs[q];
                    const float v = field_.thesisKernel(e->dxy2 + dz * dz);
                    sum[q] += (e->minK <= k + q && k + q <= e->maxK) ? v : 0.0f;
                }
        }
        for (int q = 0; q < N; ++q) out[q] = sum[q];
    }

    Field field_;
    const Grid* grid_ = nullptr;
    glm::ivec3 corner0_{0};
    std::span<const glm::vec3> positions_;
    std::span<const std::uint32_t> particles_;
    int side_ = 0;   // n + 1
    int reach_ = 0;  // slabs a particle centre can be from a slice it influences, plus slack
    long kLo_ = 0, kHi_ = 0, zOrigin_ = 0, xOrigin_ = 0;
    std::vector<float> colX_, colY_;
    int chunks_ = 1;
    std::vector<std::uint8_t> built_;  // per (row, chunk)
    std::vector<float> sortedZ_;       // the particles' z, in their (z) order
    // Column-chunk (c, w)'s entries are entries_[start_[c * chunks + w], ends_[...]).
    std::vector<std::uint32_t> start_, ends_;
    std::vector<Entry> entries_;
    std::size_t entryBytes_ = 0;
    std::size_t rowsBuilt_ = 0;
};

}  // namespace meniscus::surface
