// buildNeighbourLists (declared in neighbour_search.h): count, scan, fill.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace meniscus::sim {

template <class Kernel>
void buildNeighbourLists(std::span<const glm::vec3> points, const CellGrid& grid, std::span<const glm::vec3> others,
                         float support, bool self, const Kernel& kernel, NeighbourLists& out, std::span<float> wSum) {
    const std::size_t n = points.size();
    const float h2 = support * support;
    constexpr std::size_t kChunk = 1024;
    const std::size_t chunks = (n + kChunk - 1) / kChunk;
    out.offsets.assign(n + 1, 0);
    out.chunkEntries.resize(chunks);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t c = r.begin(); c < r.end(); ++c) {
            std::vector<Neighbour>& list = out.chunkEntries[c];
            list.clear();
            const std::size_t end = std::min(n, (c + 1) * kChunk);
            for (std::size_t i = c * kChunk; i < end; ++i) {
                const glm::vec3 xi = points[i];
                const std::size_t before = list.size();
                float sum = 0.0f;
                grid.forEachNear(xi, [&](std::uint32_t j) {
                    const glm::vec3 d = xi - others[j];
                    const float r2 = glm::dot(d, d);
                    if (r2 < h2 && !(self && j == i)) {
                        const auto [w, g] = kernel(d, std::sqrt(r2), r2);
                        sum += w;
                        list.push_back(Neighbour{j, g});
                    }
                });
                out.offsets[i + 1] = std::uint32_t(list.size() - before);
                if (!wSum.empty()) wSum[i] = sum;
            }
        }
    });
    for (std::size_t i = 0; i < n; ++i) out.offsets[i + 1] += out.offsets[i];
    out.entries.resize(out.offsets[n]);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t c = r.begin(); c < r.end(); ++c) {
            const auto at = std::ptrdiff_t(out.offsets[c * kChunk]);
            std::copy(out.chunkEntries[c].begin(), out.chunkEntries[c].end(), out.entries.begin() + at);
        }
    });
}

}  // namespace meniscus::sim
