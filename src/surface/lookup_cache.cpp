#include "surface/lookup_cache.h"

#include <algorithm>
#include <cmath>

namespace meniscus::surface {

namespace {
std::int16_t clamp16(long v, long lo, long hi) { return std::int16_t(std::clamp(v, lo, hi)); }
}  // namespace

void LookupCache::build(const Grid& grid, const Field& field, glm::ivec3 corner0, std::span<const glm::vec3> positions,
                        std::span<const std::uint32_t> particles) {
    field_ = field;
    const int n = grid.n;
    side_ = n + 1;
    const float c = grid.cube;
    reach_ = int(std::ceil(field.support / c)) + 2;
    const long kLo = -reach_ - 2, kHi = n + reach_ + 2;  // clamping keeps midK's order
    const long zOrigin = long(grid.origin.z) + corner0.z;
    std::vector<float> colX(static_cast<std::size_t>(side_)), colY(static_cast<std::size_t>(side_));
    for (int i = 0; i < side_; ++i) {
        colX[std::size_t(i)] = grid.corner(corner0.x + i, 0, 0).x;
        colY[std::size_t(i)] = grid.corner(0, corner0.y + i, 0).y;
    }
    const long xOrigin = long(grid.origin.x) + corner0.x, yOrigin = long(grid.origin.y) + corner0.y;
    const std::size_t columns = std::size_t(side_) * std::size_t(side_);
    start_.assign(columns + 1, 0);

    // The thesis's construction: particles in z order, each appended to every
    // column within Rc of it (so each column comes out sorted by z). Two passes:
    // count, then fill.
    auto forColumns = [&](const glm::vec3& p, auto&& visit) {
        const int i0 = std::max(0, int(std::ceil((p.x - field.support) / c) - xOrigin) - 1);
        const int i1 = std::min(n, int(std::floor((p.x + field.support) / c) - xOrigin) + 1);
        const int j0 = std::max(0, int(std::ceil((p.y - field.support) / c) - yOrigin) - 1);
        const int j1 = std::min(n, int(std::floor((p.y + field.support) / c) - yOrigin) + 1);
        for (int j = j0; j <= j1; ++j) {
            const float dy = p.y - colY[std::size_t(j)];
            const float dy2 = dy * dy;
            for (int i = i0; i <= i1; ++i) {
                const float dx = p.x - colX[std::size_t(i)];
                const float dxy2 = dx * dx + dy2;
                if (dxy2 < field.support2) visit(std::size_t(j) * std::size_t(side_) + std::size_t(i), dxy2);
            }
        }
    };
    for (std::uint32_t id : particles) forColumns(positions[id], [&](std::size_t col, float) { ++start_[col + 1]; });
    for (std::size_t k = 0; k < columns; ++k) start_[k + 1] += start_[k];
    entries_.resize(start_[columns]);
    fill_.assign(start_.begin(), start_.end() - 1);
    for (std::uint32_t id : particles) {
        const glm::vec3 p = positions[id];
        const long mid = long(std::floor(p.z / c)) - zOrigin;
        forColumns(p, [&](std::size_t col, float dxy2) {
            // The slices the particle reaches, widened by one on each side so
            // rounding never drops a particle that is in range: the kernel
            // itself decides on the exact distance.
            const float half = std::sqrt(std::max(0.0f, field.support2 - dxy2));
            Entry e;
            e.z = p.z;
            e.dxy2 = dxy2;
            e.minK = clamp16(long(std::floor((p.z - half) / c)) - zOrigin - 1, kLo, kHi);
            e.maxK = clamp16(long(std::ceil((p.z + half) / c)) - zOrigin + 1, kLo, kHi);
            e.midK = clamp16(mid, kLo, kHi);
            e.pad = 0;
            entries_[fill_[col]++] = e;
        });
    }
}

}  // namespace meniscus::surface
