// buildNeighbourLists (declared in neighbour_search.h): count, scan, fill.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace meniscus::sim {

template <class Kernel>
void buildNeighbourLists(std::span<const glm::vec3> points, const CellGrid& grid, std::span<const glm::vec3> others,
                         float support, bool self, const Kernel& kernel, NeighbourLists& out) {
    const std::size_t n = points.size();
    const float h2 = support * support;
    out.offsets.assign(n + 1, 0);
    // Pass 1: counts.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            const glm::vec3 xi = points[i];
            std::uint32_t count = 0;
            grid.forEachNear(xi, [&](std::uint32_t j) {
                const glm::vec3 d = xi - others[j];
                if (glm::dot(d, d) < h2 && !(self && j == i)) ++count;
            });
            out.offsets[i + 1] = count;
        }
    });
    for (std::size_t i = 0; i < n; ++i) out.offsets[i + 1] += out.offsets[i];
    out.entries.resize(out.offsets[n]);
    // Pass 2: the entries, in the order pass 1 counted them.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            const glm::vec3 xi = points[i];
            Neighbour* e = out.entries.data() + out.offsets[i];
            grid.forEachNear(xi, [&](std::uint32_t j) {
                const glm::vec3 d = xi - others[j];
                const float r2 = glm::dot(d, d);
                if (r2 < h2 && !(self && j == i)) {
                    const auto [w, g] = kernel(d, std::sqrt(r2), r2);
                    *e++ = Neighbour{j, w, g};
                }
            });
        }
    });
}

}  // namespace meniscus::sim
