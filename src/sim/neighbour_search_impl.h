// buildNeighbourLists (declared in neighbour_search.h): count, scan, fill.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace meniscus::sim {

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
        for (std::size_t c = r.begin(); c < r.end(); ++c) {
            std::vector<Neighbour>& list = out.chunkEntries[c];
            list.clear();
            const std::size_t end = std::min(n, (c + 1) * kChunk);
            for (std::size_t i = c * kChunk; i < end; ++i) {
                const glm::vec3 xi = points[i];
                const auto self_ = self ? std::uint32_t(i) : ~std::uint32_t(0);
                // Distance tests without a branch per candidate (about one in
                // seven is a neighbour, so a branch would mispredict often):
                // write every candidate, advance past the hits only.
                std::size_t m = 0;
                grid.forEachRowNear(xi, [&](std::uint32_t b, std::uint32_t e) {
                    if (hits.size() < m + (e - b)) hits.resize(2 * (m + (e - b)));
                    for (std::uint32_t k = b; k < e; ++k) {
                        const glm::vec3 d = xi - grid.sortedPosition(k);
                        hits[m] = k;
                        m += std::size_t((glm::dot(d, d) < h2) & (grid.sortedIndex(k) != self_));
                    }
                });
                out.first[i] = std::uint32_t(list.size());
                out.counts[i] = std::uint32_t(m);
                float sum = 0.0f;
                for (std::size_t q = 0; q < m; ++q) {
                    const std::uint32_t k = hits[q];
                    const glm::vec3 d = xi - grid.sortedPosition(k);
                    const float r2 = glm::dot(d, d);
                    const auto [w, g] = kernel(d, std::sqrt(r2), r2);
                    sum += w;
                    list.push_back(Neighbour{grid.sortedIndex(k), g});
                }
                if (!wSum.empty()) wSum[i] = sum;
            }
        }
    });
}

}  // namespace meniscus::sim
