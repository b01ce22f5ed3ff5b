#include "surface/weld.h"

#include <unordered_map>

#include <tbb/parallel_for.h>

namespace meniscus::surface {

void weldBlocks(const std::vector<BlockOutput>& blocks, TriangleMesh& mesh) {
    // Global indices, in block order (one pass; only seam vertices need the map).
    std::vector<std::vector<std::uint32_t>> remap(blocks.size());
    std::vector<std::size_t> triangleStart(blocks.size() + 1, 0);
    std::unordered_map<std::uint64_t, std::uint32_t> seam;
    struct Copy {
        std::uint32_t block, vertex;
    };
    std::vector<Copy> copies;  // seam vertices already kept by an earlier block, in block order
    std::uint32_t next = 0;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
        const BlockOutput& o = blocks[b];
        auto& map = remap[b];
        map.resize(o.vertices.size());
        for (std::size_t v = 0; v < o.vertices.size(); ++v) {
            if (o.onSeam[v]) {
                auto [it, fresh] = seam.try_emplace(o.edgeKeys[v], next);
                map[v] = it->second;
                if (fresh) {
                    ++next;
                } else {
                    map[v] |= 0x80000000u;  // a copy: its block does not write the position
                    copies.push_back({std::uint32_t(b), std::uint32_t(v)});
                }
            } else {
                map[v] = next++;
            }
        }
        triangleStart[b + 1] = triangleStart[b] + o.triangles.size();
    }
    mesh.positions.assign(next, glm::vec3(0.0f));
    mesh.normals.assign(next, glm::vec3(0.0f));
    mesh.indices.resize(triangleStart.back());
    tbb::parallel_for(std::size_t(0), blocks.size(), [&](std::size_t b) {
        const BlockOutput& o = blocks[b];
        const auto& map = remap[b];
        for (std::size_t v = 0; v < o.vertices.size(); ++v)
            if (!(map[v] & 0x80000000u)) {
                mesh.positions[map[v]] = o.vertices[v];
                mesh.normals[map[v]] = o.normalSums[v];
            }
        std::uint32_t* out = mesh.indices.data() + triangleStart[b];
        for (std::size_t t = 0; t < o.triangles.size(); ++t) out[t] = map[o.triangles[t]] & 0x7fffffffu;
    });
    // A seam vertex's other blocks add their sums after its first block's.
    for (const Copy& c : copies)
        mesh.normals[remap[c.block][c.vertex] & 0x7fffffffu] += blocks[c.block].normalSums[c.vertex];
    tbb::parallel_for(std::size_t(0), mesh.normals.size(), [&](std::size_t v) {
        const float len = glm::length(mesh.normals[v]);
        mesh.normals[v] = len > 0.0f ? mesh.normals[v] / len : glm::vec3(0.0f, 1.0f, 0.0f);
    });
}

}  // namespace meniscus::surface
