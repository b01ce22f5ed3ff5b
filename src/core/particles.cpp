// Particle-set queries: bounds, the default radius (half the median
// nearest-neighbour distance, SPEC §3.3), attribute statistics, NaN removal.
#include "meniscus/particles.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

namespace meniscus {

Bounds computeBounds(std::span<const glm::vec3> positions) {
    Bounds b;
    for (const auto& p : positions) b.extend(p);
    return b;
}

namespace {

// Uniform grid over the particles: points sorted by cell (counting sort), so a
// cell's points are contiguous. Cells are cubes of side `cell` metres.
struct PointGrid {
    glm::vec3 origin{0.0f};
    float cell = 1.0f;
    glm::ivec3 dims{1};
    std::vector<std::uint32_t> cellStart;  // size cells+1
    std::vector<glm::vec3> sorted;

    glm::ivec3 cellOf(const glm::vec3& p) const {
        const glm::ivec3 c = glm::ivec3(glm::floor((p - origin) / cell));
        return glm::clamp(c, glm::ivec3(0), dims - 1);
    }
    std::size_t index(const glm::ivec3& c) const {
        return (std::size_t(c.z) * std::size_t(dims.y) + std::size_t(c.y)) * std::size_t(dims.x) + std::size_t(c.x);
    }

    PointGrid(std::span<const glm::vec3> pts, const Bounds& b, float cellSize) : origin(b.min), cell(cellSize) {
        dims = glm::max(glm::ivec3(glm::floor(b.extent() / cell)) + 1, glm::ivec3(1));
        const std::size_t n = std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z);
        cellStart.assign(n + 1, 0);
        for (const auto& p : pts) ++cellStart[index(cellOf(p)) + 1];
        for (std::size_t i = 0; i < n; ++i) cellStart[i + 1] += cellStart[i];
        std::vector<std::uint32_t> fill(cellStart.begin(), cellStart.end() - 1);
        sorted.resize(pts.size());
        for (const auto& p : pts) sorted[fill[index(cellOf(p))]++] = p;
    }

    // Nearest distance to a point other than p itself (distance > minDist),
    // searching shells of cells up to maxRing; +inf when it cannot be certain.
    float nearest(const glm::vec3& p, float minDist, int maxRing) const {
        const glm::ivec3 c = cellOf(p);
        float best2 = std::numeric_limits<float>::infinity();
        const float min2 = minDist * minDist;
        for (int ring = 0; ring <= maxRing; ++ring) {
            // Shells 0..ring-1 are searched; any point in shell `ring` or beyond
            // is at least (ring-1)*cell away, so a nearer hit is final.
            const float reach = float(ring - 1) * cell;
            if (ring > 0 && best2 <= reach * reach) break;
            const glm::ivec3 lo = c - ring, hi = c + ring;
            for (int z = std::max(lo.z, 0); z <= std::min(hi.z, dims.z - 1); ++z)
                for (int y = std::max(lo.y, 0); y <= std::min(hi.y, dims.y - 1); ++y)
                    for (int x = std::max(lo.x, 0); x <= std::min(hi.x, dims.x - 1); ++x) {
                        const bool onShell = x == lo.x || x == hi.x || y == lo.y || y == hi.y || z == lo.z || z == hi.z;
                        if (!onShell) continue;
                        const std::size_t k = index({x, y, z});
                        for (std::uint32_t i = cellStart[k]; i < cellStart[k + 1]; ++i) {
                            const glm::vec3 d = sorted[i] - p;
                            const float d2 = glm::dot(d, d);
                            if (d2 > min2 && d2 < best2) best2 = d2;
                        }
                    }
        }
        // Unsearched shells start maxRing*cell away: beyond that, not certain.
        const float certain = float(maxRing) * cell;
        return best2 <= certain * certain ? std::sqrt(best2) : std::numeric_limits<float>::infinity();
    }
};

}  // namespace

RadiusEstimate estimateRadius(std::span<const glm::vec3> positions) {
    RadiusEstimate est;
    const Bounds b = computeBounds(positions);
    const float diag = b.empty() ? 0.0f : glm::length(b.extent());
    const auto fallback = [&] {
        est.fallback = true;
        est.radius = diag > 0.0f ? 0.01f * diag : 0.01f;
        return est;
    };
    if (positions.size() < 2 || !(diag > 0.0f) || !std::isfinite(diag)) return fallback();

    const std::size_t n = positions.size();
    const float minDist = 1e-7f * diag;  // closer than this counts as the same point
    // Cell size: the mean spacing if the points filled their box, then grown
    // until the grid has at most ~2 cells per point (sheets, sparse sprays).
    const glm::vec3 ext = glm::max(b.extent(), glm::vec3(1e-3f * diag));
    float cell = std::cbrt(ext.x * ext.y * ext.z / float(n));
    auto cellCount = [&](float c) {
        const glm::vec3 d = glm::floor(ext / c) + 1.0f;
        return double(d.x) * double(d.y) * double(d.z);
    };
    while (cellCount(cell) > 2.0 * double(n) + 8.0) cell *= 1.25f;

    // Queries: every particle, or an even stride of them for very large sets.
    const std::size_t maxQueries = 200000;
    const std::size_t stride = std::max<std::size_t>(1, (n + maxQueries - 1) / maxQueries);
    const std::size_t queries = (n + stride - 1) / stride;
    std::vector<float> nn(queries);
    for (int attempt = 0; attempt < 8; ++attempt) {
        const PointGrid grid(positions, b, cell);
        tbb::parallel_for(std::size_t(0), queries, [&](std::size_t q) {
            nn[q] = grid.nearest(positions[q * stride], minDist, 2);
        });
        std::vector<float> found;
        found.reserve(queries);
        for (float d : nn)
            if (std::isfinite(d)) found.push_back(d);
        // Isolated particles (nothing within two rings of cells) are farther than
        // nearly every found distance, so they count toward the median's rank
        // as long ones without being measured.
        const std::size_t mid = (queries - 1) / 2;
        if (mid < found.size()) {
            std::nth_element(found.begin(), found.begin() + std::ptrdiff_t(mid), found.end());
            est.medianNeighbourDistance = found[mid];
            est.radius = 0.5f * est.medianNeighbourDistance;
            return est;
        }
        cell *= 2.0f;  // too sparse for this grid: coarser cells and try again
    }
    return fallback();
}

std::optional<MinMedianMax> attributeStats(const ParticleSet& set, std::string_view name, int component) {
    const Attribute* a = set.find(name);
    if (!a || component < 0 || component >= a->components || a->count() == 0) return std::nullopt;
    std::vector<double> v(a->count());
    for (std::size_t i = 0; i < v.size(); ++i) {
        const std::size_t k = i * std::size_t(a->components) + std::size_t(component);
        v[i] = a->type == AttributeType::Float ? double(a->floats[k]) : double(a->ints[k]);
    }
    MinMedianMax s;
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    s.min = *lo;
    s.max = *hi;
    // numpy's median: the middle value, or the mean of the two middle values.
    const std::size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(mid), v.end());
    s.median = v[mid];
    if (v.size() % 2 == 0) s.median = 0.5 * (s.median + *std::max_element(v.begin(), v.begin() + std::ptrdiff_t(mid)));
    return s;
}

std::size_t dropNonFinite(ParticleSet& set) {
    const std::size_t n = set.size();
    std::vector<std::size_t> keep;
    keep.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3& p = set.positions[i];
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) keep.push_back(i);
    }
    if (keep.size() == n) return 0;
    auto compact = [&](auto& values, std::size_t comps) {
        for (std::size_t j = 0; j < keep.size(); ++j)
            for (std::size_t c = 0; c < comps; ++c) values[j * comps + c] = values[keep[j] * comps + c];
        values.resize(keep.size() * comps);
    };
    compact(set.positions, 1);
    for (Attribute& a : set.attributes) {
        if (a.type == AttributeType::Float)
            compact(a.floats, std::size_t(a.components));
        else
            compact(a.ints, std::size_t(a.components));
    }
    return n - keep.size();
}

}  // namespace meniscus
