// buildNeighbourLists (declared in neighbour_search.h): count, scan, fill.
#pragma once

#include <algorithm>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sim/parallel.h"

namespace meniscus::sim {

// For each L-bit hit mask: the lanes that hit, in order (then padding). One
// table load, one add and one store append all of a group's hits (SSE2 and
// AVX2 have no compress instruction, and a store per lane cost more).
template <unsigned L>
struct HitLanes {
    alignas(4 * L) std::uint32_t lanes[1u << L][L];
    constexpr HitLanes() : lanes{} {
        for (unsigned mask = 0; mask < (1u << L); ++mask) {
            unsigned c = 0;
            for (unsigned l = 0; l < L; ++l)
                if (mask >> l & 1u) lanes[mask][c++] = l;
        }
    }
};
#if defined(__SSE2__)
inline constexpr HitLanes<4> kHitLanes{};
#endif

// Appends to hits[m...] the k in [b, e) with |xi - (X, Y, Z)[k]|^2 < h2 (the grid's sorted coordinates),
// in order; returns the new m. The same float arithmetic as glm::dot(d, d)
// (((dx dx + dy dy) + dz dz), no fused multiply-add on the baseline path), so
// the same lists as a scalar test. With SSE2 (every x86-64) four candidates are tested at once and the
// hits taken from the comparison's bit mask without a branch: about one
// candidate in seven is a neighbour, so a branch per candidate (or per hit)
// would mispredict often. hits must have room for m + (e - b) + 4 entries.
inline std::size_t distanceTest(const CellGrid& grid, const glm::vec3& xi, float h2, std::uint32_t b, std::uint32_t e,
                                std::uint32_t* hits, std::size_t m) {
    const float* X = grid.sortedCoordinates(0);
    const float* Y = grid.sortedCoordinates(1);
    const float* Z = grid.sortedCoordinates(2);
#if defined(__SSE2__)
    const __m128 px = _mm_set1_ps(xi.x), py = _mm_set1_ps(xi.y), pz = _mm_set1_ps(xi.z), r2 = _mm_set1_ps(h2);
    for (std::uint32_t k = b; k < e; k += 4) {
        const __m128 dx = _mm_sub_ps(px, _mm_loadu_ps(X + k));
        const __m128 dy = _mm_sub_ps(py, _mm_loadu_ps(Y + k));
        const __m128 dz = _mm_sub_ps(pz, _mm_loadu_ps(Z + k));
        const __m128 d2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
        unsigned mask = unsigned(_mm_movemask_ps(_mm_cmplt_ps(d2, r2)));
        if (e - k < 4) mask &= (1u << (e - k)) - 1u;  // past the row: another row's points (or the padding)
        // Branch-free: four entries are written, the count advances by the hits.
        const __m128i lanes = _mm_load_si128(reinterpret_cast<const __m128i*>(kHitLanes.lanes[mask]));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(hits + m), _mm_add_epi32(_mm_set1_epi32(int(k)), lanes));
        // The count from a constant, nibble per mask (a table load would put
        // its latency on the m chain every group).
        m += std::size_t(0x4332322132212110ULL >> (4u * mask) & 0xFu);
    }
#else
    for (std::uint32_t k = b; k < e; ++k) {
        const float dx = xi.x - X[k], dy = xi.y - Y[k], dz = xi.z - Z[k];
        hits[m] = k;
        m += std::size_t(dx * dx + dy * dy + dz * dz < h2);
    }
#endif
    return m;
}

#if MENISCUS_SIM_AVX2_LOOPS
inline constexpr bool kHasEightWide = true;
inline constexpr HitLanes<8> kHitLanes8{};  // 8 KiB

// distanceTest eight candidates at a time, for the AVX2 path (parallel.h).
// There the compiler fuses a product and a sum of |d|^2 (as in the kernel's
// distances below), so a pair within rounding of the support can be in or
// out on one path and not the other; the lists stay symmetric (d and -d give
// the same squares). Besides the hits' positions k it keeps their squared
// distances (d2s), for the kernel, and leaves out the candidate at selfK
// (oneself, by its place in the grid; none when past the end). hits and d2s
// must have room for m + (e - b) + 8 entries.
__attribute__((target("avx2,fma,popcnt"))) inline std::size_t distanceTest8(const CellGrid& grid, const glm::vec3& xi,
                                                                        float h2, std::uint32_t b, std::uint32_t e,
                                                                        std::uint32_t selfK, std::uint32_t* hits,
                                                                        float* d2s, std::size_t m) {
    const float* X = grid.sortedCoordinates(0);
    const float* Y = grid.sortedCoordinates(1);
    const float* Z = grid.sortedCoordinates(2);
    const __m256 px = _mm256_set1_ps(xi.x), py = _mm256_set1_ps(xi.y), pz = _mm256_set1_ps(xi.z), r2 = _mm256_set1_ps(h2);
    for (std::uint32_t k = b; k < e; k += 8) {
        const __m256 dx = _mm256_sub_ps(px, _mm256_loadu_ps(X + k));
        const __m256 dy = _mm256_sub_ps(py, _mm256_loadu_ps(Y + k));
        const __m256 dz = _mm256_sub_ps(pz, _mm256_loadu_ps(Z + k));
        // Written as separate multiplies and adds; GCC contracts intrinsics
        // too, so from -O2 on this is two FMAs (see above).
        const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz));
        unsigned mask = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(d2, r2, _CMP_LT_OQ)));
        if (e - k < 8) mask &= (1u << (e - k)) - 1u;
        const std::uint32_t off = selfK - k;  // wraps past the group when selfK < k
        mask &= ~(off < 8u ? 1u << off : 0u);
        const __m256i lanes = _mm256_load_si256(reinterpret_cast<const __m256i*>(kHitLanes8.lanes[mask]));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(hits + m), _mm256_add_epi32(_mm256_set1_epi32(int(k)), lanes));
        _mm256_storeu_ps(d2s + m, _mm256_permutevar8x32_ps(d2, lanes));
        m += std::size_t(_mm_popcnt_u32(mask));
    }
    return m;
}
#else
inline constexpr bool kHasEightWide = false;
#endif

template <class Kernel>
void buildNeighbourLists(std::span<const glm::vec3> points, const CellGrid& grid, float support, bool self,
                         const Kernel& kernel, NeighbourLists& out, std::span<float> wSum) {
    const std::size_t n = points.size();
    const float h2 = support * support;
    constexpr std::size_t kChunk = NeighbourLists::kChunk;
    const std::size_t chunks = (n + kChunk - 1) / kChunk;
    out.first.resize(n);
    out.counts.resize(n);
    out.chunkEntries.resize(chunks);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<std::uint32_t> hits;  // candidates within the support, of the current particle
        std::vector<float> d2s;           // their squared distances (AVX2 path)
        // On the AVX2 path, eight candidates a test (distanceTest8).
        auto chunkOf = [&](std::size_t c, auto path) {
            std::vector<Neighbour>& list = out.chunkEntries[c];
            list.clear();
            const std::size_t end = std::min(n, (c + 1) * kChunk);
            for (std::size_t i = c * kChunk; i < end; ++i) {
                const glm::vec3 xi = points[i];
                constexpr bool eight = decltype(path)::value == SimdPath::Avx2Fma;
                std::size_t m = 0;
                const std::uint32_t selfK = self ? grid.slotOf(std::uint32_t(i)) : ~0u;
                grid.forEachRowNear(xi, support, [&](std::uint32_t b, std::uint32_t e) {
                    if (hits.size() < m + (e - b) + 8) hits.resize(2 * (m + (e - b) + 8));
#if MENISCUS_SIM_AVX2_LOOPS
                    if constexpr (eight) {
                        if (d2s.size() < hits.size()) d2s.resize(hits.size());
                        m = distanceTest8(grid, xi, h2, b, e, selfK, hits.data(), d2s.data(), m);
                    } else
#endif
                        m = distanceTest(grid, xi, h2, b, e, hits.data(), m);
                });
                // Oneself (when self) is among the hits: out, keeping the order
                // (the eight-wide test left it out already).
                if (self && !(eight && kHasEightWide)) m = std::size_t(std::remove_if(hits.begin(), hits.begin() + std::ptrdiff_t(m),
                                                         [&](std::uint32_t k) { return grid.sortedIndex(k) == i; }) -
                                          hits.begin());
                const std::size_t at = list.size();
                out.first[i] = std::uint32_t(at);
                out.counts[i] = std::uint32_t(m);
                // Written field by field where they belong: a whole entry built
                // on the stack and copied stalled on its 16-byte reload.
                if (list.capacity() < at + m) list.reserve(2 * (at + m));
                list.resize(at + m);
                Neighbour* dst = list.data() + at;
                float sum = 0.0f;
                const float* X = grid.sortedCoordinates(0);
                const float* Y = grid.sortedCoordinates(1);
                const float* Z = grid.sortedCoordinates(2);
                // The kernel four hits at a time (the spare lanes repeat the
                // last hit and are set at the support: zero). The distances
                // in the same float arithmetic as the test above.
                alignas(16) float w[4], g[4];
                const F4 px = splat(xi.x), py = splat(xi.y), pz = splat(xi.z), support2 = splat(h2);
                const F4 lane = set4(0.0f, 1.0f, 2.0f, 3.0f);
                for (std::size_t q = 0; q < m; q += 4) {
                    const std::size_t lanes = std::min<std::size_t>(4, m - q);
                    F4 d2;
                    if constexpr (eight && kHasEightWide) {
                        d2 = load4(d2s.data() + q);  // kept by the test (past m: cut below)
                    } else {
                        const std::uint32_t k0 = hits[q], k1 = hits[q + std::min<std::size_t>(1, lanes - 1)],
                                            k2 = hits[q + std::min<std::size_t>(2, lanes - 1)],
                                            k3 = hits[q + std::min<std::size_t>(3, lanes - 1)];
                        const F4 dx = px - set4(X[k0], X[k1], X[k2], X[k3]);
                        const F4 dy = py - set4(Y[k0], Y[k1], Y[k2], Y[k3]);
                        const F4 dz = pz - set4(Z[k0], Z[k1], Z[k2], Z[k3]);
                        d2 = (dx * dx + dy * dy) + dz * dz;
                    }
                    const F4 r2 = select(less(lane, splat(float(lanes))), d2, support2);
                    F4 w4, g4;
                    kernel(sqrt4(r2), w4, g4);
                    store4(w, w4), store4(g, g4);
                    for (std::size_t l = 0; l < lanes; ++l) {
                        sum += w[l];
                        dst[q + l].j = grid.sortedIndex(hits[q + l]);
                        dst[q + l].g = g[l];
                    }
                }
                if (!wSum.empty()) wSum[i] = sum;
            }
        };
        runRangeOnPath(chunkOf, r.begin(), r.end());  // parallel.h
    });
}

}  // namespace meniscus::sim
