#include "surface/lookup_cache.h"

#include <algorithm>
#include <cmath>

namespace meniscus::surface {

namespace {
std::int16_t clamp16(long v, long lo, long hi) { return std::int16_t(std::clamp(v, lo, hi)); }
// floor and ceil to an integer by truncation: the same values as std::floor /
// std::ceil for |x| < 2^31, without the slow emulation baseline x86-64 (no
// SSE4.1 roundss) compiles those into.
long floorToLong(float x) {
    const long i = long(x);
    return i - (x < float(i));
}
long ceilToLong(float x) {
    const long i = long(x);
    return i + (x > float(i));
}
}  // namespace

void LookupCache::build(const Grid& grid, const Field& field, glm::ivec3 corner0, std::span<const glm::vec3> positions,
                        std::span<const std::uint32_t> particles) {
    field_ = field;
    grid_ = &grid;
    corner0_ = corner0;
    positions_ = positions;
    particles_ = particles;
    const int n = grid.n;
    side_ = n + 1;
    reach_ = int(std::ceil(field.support / grid.cube)) + 1;
    kLo_ = -reach_ - 2;  // clamping keeps midK's order
    kHi_ = n + reach_ + 2;
    zOrigin_ = long(grid.origin.z) + corner0.z;
    xOrigin_ = long(grid.origin.x) + corner0.x;
    colX_.resize(std::size_t(side_));
    colY_.resize(std::size_t(side_));
    for (int i = 0; i < side_; ++i) {
        colX_[std::size_t(i)] = grid.corner(corner0.x + i, 0, 0).x;
        colY_[std::size_t(i)] = grid.corner(0, corner0.y + i, 0).y;
    }
    chunks_ = (n + kChunk - 1) / kChunk;
    built_.assign(std::size_t(side_) * std::size_t(chunks_), 0);
    sortedZ_.resize(particles.size());
    for (std::size_t k = 0; k < particles.size(); ++k) sortedZ_[k] = positions[particles[k]].z;
    start_.assign(std::size_t(side_) * std::size_t(side_) * std::size_t(chunks_), 0);
    ends_.assign(start_.size(), 0);
    entries_.clear();
    entryBytes_ = 0;
    rowsBuilt_ = 0;
}

// The thesis's construction, for the columns of row j and the slices of
// chunk w: the particles in z order (those within reach of the chunk), each
// appended to every column of the row within Rc of it, so each column comes
// out sorted by z. Two passes: count, then fill.
void LookupCache::buildRowChunk(int j, int w) {
    built_[std::size_t(j) * std::size_t(chunks_) + std::size_t(w)] = 1;
    ++rowsBuilt_;
    const float c = grid_->cube;
    const float invC = 1.0f / c;  // the ranges below are widened by one, so rounding here is harmless
    const int n = side_ - 1;
    const float y = colY_[std::size_t(j)];
    // The particles that can reach a slice of the chunk: z within the
    // support (plus a cube of slack) of the chunk's slices.
    const int k0 = w * kChunk, k1 = std::min(n, (w + 1) * kChunk);
    const float zLo = grid_->corner(0, 0, corner0_.z + k0).z - field_.support - c;
    const float zHi = grid_->corner(0, 0, corner0_.z + k1).z + field_.support + c;
    const std::size_t b0 = std::size_t(std::lower_bound(sortedZ_.begin(), sortedZ_.end(), zLo) - sortedZ_.begin());
    const std::size_t b1 = std::size_t(std::upper_bound(sortedZ_.begin(), sortedZ_.end(), zHi) - sortedZ_.begin());
    const std::span<const std::uint32_t> band = particles_.subspan(b0, b1 - b0);
    auto slot = [&](int i) {
        return (std::size_t(j) * std::size_t(side_) + std::size_t(i)) * std::size_t(chunks_) + std::size_t(w);
    };
    auto forColumns = [&](const glm::vec3& p, auto&& visit) {
        const float dy = p.y - y;
        const float dy2 = dy * dy;
        if (!(dy2 < field_.support2)) return;
        const int i0 = std::max(0, int(ceilToLong((p.x - field_.support) * invC) - xOrigin_) - 1);
        const int i1 = std::min(n, int(floorToLong((p.x + field_.support) * invC) - xOrigin_) + 1);
        for (int i = i0; i <= i1; ++i) {
            const float dx = p.x - colX_[std::size_t(i)];
            const float dxy2 = dx * dx + dy2;
            if (dxy2 < field_.support2) visit(std::size_t(i), dxy2);
        }
    };
    std::vector<std::uint32_t> count(std::size_t(side_) + 1, 0);
    for (std::uint32_t id : band) forColumns(positions_[id], [&](std::size_t i, float) { ++count[i + 1]; });
    for (int i = 0; i < side_; ++i) count[std::size_t(i) + 1] += count[std::size_t(i)];
    // Row-chunks are appended in the order they are built; start_/ends_ hold
    // each column's range wherever it landed.
    const std::size_t base = entries_.size();
    entries_.resize(base + count[std::size_t(side_)]);
    entryBytes_ += count[std::size_t(side_)] * sizeof(Entry);
    for (int i = 0; i < side_; ++i) start_[slot(i)] = std::uint32_t(base + count[std::size_t(i)]);
    for (int i = 0; i < side_; ++i) ends_[slot(i)] = std::uint32_t(base + count[std::size_t(i) + 1]);
    std::vector<std::uint32_t> fill(count.begin(), count.end() - 1);
    for (std::uint32_t id : band) {
        const glm::vec3 p = positions_[id];
        const long mid = floorToLong(p.z * invC) - zOrigin_;
        forColumns(p, [&](std::size_t i, float dxy2) {
            // The slices the particle reaches, widened by one on each side so
            // rounding never drops a particle that is in range: the kernel
            // itself decides on the exact distance.
            const float half = std::sqrt(std::max(0.0f, field_.support2 - dxy2));
            Entry e;
            e.z = p.z;
            e.dxy2 = dxy2;
            e.minK = clamp16(floorToLong((p.z - half) * invC) - zOrigin_ - 1, kLo_, kHi_);
            e.maxK = clamp16(ceilToLong((p.z + half) * invC) - zOrigin_ + 1, kLo_, kHi_);
            e.midK = clamp16(mid, kLo_, kHi_);
            e.pad = 0;
            entries_[base + fill[i]++] = e;
        });
    }
}

}  // namespace meniscus::surface
