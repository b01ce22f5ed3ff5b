#include "surface/lookup_cache.h"

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace meniscus::surface {

namespace {
std::int16_t clamp16(long v, long lo, long hi) { return std::int16_t(std::clamp(v, lo, hi)); }
constexpr int kBuckets = 256;
}  // namespace

void LookupCache::build(const Grid& grid, const Field& field, glm::ivec3 corner0, std::span<const glm::vec3> positions,
                        std::span<const std::uint32_t> particles) {
    field_ = field;
    grid_ = &grid;
    const int n = grid.n;
    side_ = n + 1;
    reach_ = int(std::ceil(field.support / grid.cube)) + 1;
    kLo_ = -reach_ - 2;  // clamping keeps midK's order
    kHi_ = n + reach_ + kLanes + 2;
    zOrigin_ = long(grid.origin.z) + corner0.z;
    xOrigin_ = long(grid.origin.x) + corner0.x;
    const long yOrigin = long(grid.origin.y) + corner0.y;
    colX_.resize(std::size_t(side_));
    colY_.resize(std::size_t(side_));
    for (int i = 0; i < side_; ++i) {
        colX_[std::size_t(i)] = grid.corner(corner0.x + i, 0, 0).x;
        colY_[std::size_t(i)] = grid.corner(0, corner0.y + i, 0).y;
    }
    // A contiguous copy in z order: the row builds read it sequentially.
    const std::size_t np = particles.size();
    const float invC = 1.0f / grid.cube;  // ranges are widened by one, so rounding here is harmless
    px_.resize(np);
    py_.resize(np);
    pz_.resize(np);
    mid_.resize(np);
    for (std::size_t q = 0; q < np; ++q) {
        const glm::vec3 p = positions[particles[q]];
        px_[q] = p.x;
        py_[q] = p.y;
        pz_[q] = p.z;
        mid_[q] = clamp16(floorToLong(p.z * invC) - zOrigin_, kLo_, kHi_);
    }
    // Row buckets (counting sort, so each row keeps the z order): particle q
    // is in row j when its horizontal distance to the row's line is within
    // the support, the test buildRow repeats per column.
    auto rowsOf = [&](std::size_t q, auto&& visit) {
        const int j0 = std::max(0, int(ceilToLong((py_[q] - field_.support) * invC) - yOrigin) - 1);
        const int j1 = std::min(n, int(floorToLong((py_[q] + field_.support) * invC) - yOrigin) + 1);
        for (int j = j0; j <= j1; ++j) {
            const float dy = py_[q] - colY_[std::size_t(j)];
            if (dy * dy < field_.support2) visit(std::size_t(j));
        }
    };
    rowStart_.assign(std::size_t(side_) + 1, 0);
    for (std::size_t q = 0; q < np; ++q) rowsOf(q, [&](std::size_t j) { ++rowStart_[j + 1]; });
    for (int j = 0; j < side_; ++j) rowStart_[std::size_t(j) + 1] += rowStart_[std::size_t(j)];
    rowList_.resize(rowStart_.back());
    count_.assign(rowStart_.begin(), rowStart_.end() - 1);
    for (std::size_t q = 0; q < np; ++q) rowsOf(q, [&](std::size_t j) { rowList_[count_[j]++] = std::uint32_t(q); });

    // Slices a particle in slab mid can reach from a column at squared
    // horizontal distance in bucket b: the half chord at the bucket's lower
    // end, rounded up, plus one for the centre's place in its slab and one
    // of slack for rounding (the kernel decides on the exact distance).
    reachOf_.resize(kBuckets);
    for (int b = 0; b < kBuckets; ++b) {
        const double d2 = double(b) * double(field.support2) / kBuckets;
        const double half = std::sqrt(std::max(0.0, double(field.support2) - d2));
        reachOf_[std::size_t(b)] = std::int16_t(std::ceil(half / double(grid.cube)) + 2);
    }
    built_.assign(std::size_t(side_), 0);
    start_.assign(std::size_t(side_) * std::size_t(side_), 0);
    ends_.assign(start_.size(), 0);
    entries_.clear();
    entryBytes_ = 0;
    rowsBuilt_ = 0;
}

// The thesis's construction, for the columns of row j: the row's particles in
// z order, each appended to every column of the row within the support of it,
// so each column comes out sorted by z. Two passes: count, then fill.
void LookupCache::buildRow(int j) {
    built_[std::size_t(j)] = 1;
    ++rowsBuilt_;
    const float invC = 1.0f / grid_->cube;
    const int n = side_ - 1;
    const float y = colY_[std::size_t(j)];
    const std::span<const std::uint32_t> row(rowList_.data() + rowStart_[std::size_t(j)],
                                             rowStart_[std::size_t(j) + 1] - rowStart_[std::size_t(j)]);
    // Each particle's columns: those with dx^2 + dy^2 < support^2, a
    // contiguous run (the test is convex in i). The run from the half chord,
    // then its ends moved by the exact test, so it is the same set as testing
    // every column, for a few tests.
    auto dxy2Of = [&](std::uint32_t q, int i, float dy2) {
        const float dx = px_[q] - colX_[std::size_t(i)];
        return dx * dx + dy2;
    };
    spans_.resize(row.size());
    count_.assign(std::size_t(side_) + 2, 0);  // slot i + 1: column i; one spare at the end
    for (std::size_t r = 0; r < row.size(); ++r) {
        const std::uint32_t q = row[r];
        const float dy = py_[q] - y;
        const float dy2 = dy * dy;
        const float w = std::sqrt(std::max(0.0f, field_.support2 - dy2));
        int i0 = std::clamp(int(ceilToLong((px_[q] - w) * invC) - xOrigin_), 0, n);
        int i1 = std::clamp(int(floorToLong((px_[q] + w) * invC) - xOrigin_), 0, n);
        while (i0 > 0 && dxy2Of(q, i0 - 1, dy2) < field_.support2) --i0;
        while (i0 <= i1 && !(dxy2Of(q, i0, dy2) < field_.support2)) ++i0;
        while (i1 < n && dxy2Of(q, i1 + 1, dy2) < field_.support2) ++i1;
        while (i1 >= i0 && !(dxy2Of(q, i1, dy2) < field_.support2)) --i1;
        spans_[r] = {std::int16_t(i0), std::int16_t(i1)};
        if (i0 <= i1) {
            ++count_[std::size_t(i0) + 1];
            --count_[std::size_t(i1) + 2];
        }
    }
    // count_[i + 1] holds the change in run count at column i; two prefix
    // sums give the per-column counts, then their starts.
    for (int i = 0; i < side_; ++i) count_[std::size_t(i) + 1] += count_[std::size_t(i)];
    for (int i = 0; i < side_; ++i) count_[std::size_t(i) + 1] += count_[std::size_t(i)];
    // Rows are appended in the order they are built; start_/ends_ hold each
    // column's range wherever it landed.
    const std::size_t base = entries_.size(), column0 = std::size_t(j) * std::size_t(side_);
    entries_.resize(base + count_[std::size_t(side_)]);
    entryBytes_ += count_[std::size_t(side_)] * sizeof(Entry);
    for (int i = 0; i < side_; ++i) {
        start_[column0 + std::size_t(i)] = std::uint32_t(base + count_[std::size_t(i)]);
        ends_[column0 + std::size_t(i)] = std::uint32_t(base + count_[std::size_t(i) + 1]);
    }
    Entry* fill = entries_.data() + base;
    const float bucketScale = float(kBuckets) / field_.support2;
    for (std::size_t r = 0; r < row.size(); ++r) {
        const std::uint32_t q = row[r];
        const float z = pz_[q];
        const std::int16_t mid = mid_[q];
        const float dy = py_[q] - y;
        const float dy2 = dy * dy;
        for (int i = spans_[r].first; i <= spans_[r].second; ++i) {
            const float dxy2 = dxy2Of(q, i, dy2);
            const int h = reachOf_[std::size_t(std::min(int(dxy2 * bucketScale), kBuckets - 1))];
            Entry& e = fill[count_[std::size_t(i)]++];
            e.z = z;
            e.dxy2 = dxy2;
            e.minK = std::int16_t(mid - h);
            e.maxK = std::int16_t(mid + h);
            e.midK = mid;
            e.pad = 0;
        }
    }
}

std::span<const LookupCache::Entry> LookupCache::window(int i, int j, int k) {
    if (!built_[std::size_t(j)]) buildRow(j);
    const std::size_t c = std::size_t(j) * std::size_t(side_) + std::size_t(i);
    const Entry* first = entries_.data() + start_[c];
    const Entry* last = entries_.data() + ends_[c];
    // The entries whose centre slab can reach one of the slices (midK is
    // non-decreasing, so binary searches): midK in [k - reach, k + kLanes - 1 + reach].
    const Entry* from = std::partition_point(first, last, [&](const Entry& e) { return e.midK < k - reach_; });
    const Entry* to = std::partition_point(from, last, [&](const Entry& e) { return e.midK < k + kLanes + reach_; });
    return {from, std::size_t(to - from)};
}

void LookupCache::valuesScalar(int i, int j, int k, const float* zs, float* out) {
    const bool sph = field_.kind == SurfaceField::Sph;
    float sum[kLanes] = {};
    for (const Entry& e : window(i, j, k))
        for (int q = 0; q < kLanes; ++q) {
            const float dz = e.z - zs[q];
            const float d2 = e.dxy2 + dz * dz;
            const float v = sph ? field_.sphKernel(d2) : field_.thesisKernel(d2);
            sum[q] += (e.minK <= k + q && k + q <= e.maxK) ? v : 0.0f;
        }
    for (int q = 0; q < kLanes; ++q) out[q] = sum[q];
}

void LookupCache::values(int i, int j, int k, const float* zs, float* out) {
#if defined(__SSE2__)
    const std::span<const Entry> entries = window(i, j, k);
    const Entry* from = entries.data();
    const Entry* to = from + entries.size();
    const bool sph = field_.kind == SurfaceField::Sph;
    // The kernels of field.h, lane q = corner k + q, the same operations in
    // the same order (SSE arithmetic is IEEE single like the scalar code).
    const __m128 z4 = _mm_loadu_ps(zs);
    const __m128i k4 = _mm_add_epi32(_mm_set1_epi32(k), _mm_set_epi32(3, 2, 1, 0));
    const __m128 support2 = _mm_set1_ps(field_.support2), invS = _mm_set1_ps(field_.invSupport),
                 invS2 = _mm_set1_ps(field_.invSupport2);
    const __m128 one = _mm_set1_ps(1.0f), half = _mm_set1_ps(0.5f), two = _mm_set1_ps(2.0f), six = _mm_set1_ps(6.0f);
    __m128 sum = _mm_setzero_ps();
    for (const Entry* e = from; e != to; ++e) {
        const __m128 dz = _mm_sub_ps(_mm_set1_ps(e->z), z4);
        const __m128 d2 = _mm_add_ps(_mm_set1_ps(e->dxy2), _mm_mul_ps(dz, dz));
        __m128 w;
        if (sph) {
            const __m128 q = _mm_mul_ps(_mm_sqrt_ps(d2), invS);
            const __m128 a = _mm_sub_ps(one, q);
            const __m128 inner = _mm_add_ps(_mm_mul_ps(_mm_mul_ps(_mm_mul_ps(six, q), q), _mm_sub_ps(q, one)), one);
            const __m128 outer = _mm_mul_ps(_mm_mul_ps(_mm_mul_ps(two, a), a), a);
            const __m128 near = _mm_cmple_ps(q, half);
            w = _mm_or_ps(_mm_and_ps(near, inner), _mm_andnot_ps(near, outer));
        } else {
            const __m128 v = _mm_sub_ps(_mm_mul_ps(_mm_mul_ps(half, d2), invS2), half);
            w = _mm_mul_ps(v, v);
        }
        // minK <= k + q <= maxK, and inside the support.
        const __m128i outside = _mm_or_si128(_mm_cmpgt_epi32(_mm_set1_epi32(e->minK), k4),
                                             _mm_cmpgt_epi32(k4, _mm_set1_epi32(e->maxK)));
        const __m128 keep = _mm_andnot_ps(_mm_castsi128_ps(outside), _mm_cmplt_ps(d2, support2));
        sum = _mm_add_ps(sum, _mm_and_ps(keep, w));
    }
    _mm_storeu_ps(out, sum);
#else
    valuesScalar(i, j, k, zs, out);
#endif
}

}  // namespace meniscus::surface
