// Weighted Laplacian smoothing of the mesh (docs/meshes.md#smoothing), after
// Löschner, Böttcher, Jeske and Bender, "Weighted Laplacian Smoothing for
// Surface Reconstruction of Particle-based Fluids" (VMV 2023), as splashsurf
// implements it:
//  1. each particle's distance-weighted neighbour count
//       n_i = sum over j != i with |x_i - x_j| < h of (1 - |x_i - x_j|^2 / h^2)
//     (about 12.5 in the bulk of a 2r lattice at h = 4 r, a few or none for a
//     drop);
//  2. n interpolated onto the vertices (interpolateAttributes: the SPH kernel
//     normalised by its sum), divided by a normalisation (13 by default) and
//     clamped to [0, 1], then eased by the smoother step 6x^5 - 15x^4 + 10x^3:
//     the vertex's weight w, 1 on the bulk's surface, near 0 on a lone drop;
//  3. `iterations` Jacobi steps of Laplacian smoothing, each vertex moved to
//     (1 - w) x + w * (the mean of its edge neighbours), all from the last
//     step's positions.
// So the bulk's particle-scale bumps (the "orange peel") flatten, while
// splashes and drops, whose few neighbours give small weights, keep their
// shape and volume. Weights off: w = 1 everywhere (plain Laplacian smoothing,
// which shrinks drops). Normals are then made again from the smoothed
// triangles, angle-weighted as the mesher makes them. Deterministic: every
// sum in a fixed order, the same mesh for any thread count.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "meniscus/surface.h"
#include "surface/cell_grid.h"
#include "surface/marching_slices.h"
#include "surface/weld.h"

namespace meniscus {

namespace {

using surface::CellGrid;

// Step 1: each particle's distance-weighted neighbour count, in the input's order.
std::vector<float> weightedNeighbourCounts(const std::vector<glm::vec3>& positions, float h) {
    constexpr int kSplit = 2;  // cells of h / 2: the (2.5 h)^3 around a particle's cell
    const CellGrid grid = surface::makeGrid(positions, double(h) / kSplit);
    const float h2 = h * h, invH2 = 1.0f / h2;
    std::vector<float> counts(positions.size(), 0.0f);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid.keys.size(), 256), [&](const auto& r) {
        for (std::size_t s = r.begin(); s < r.end(); ++s) {
            const glm::vec3 x = grid.positions[s];
            double n = 0.0;
            grid.forNear(grid.keys[s], kSplit, [&](std::size_t t) {
                if (t == s) return;
                const glm::vec3 d = grid.positions[t] - x;
                const float d2 = glm::dot(d, d);
                if (d2 < h2) n += double(1.0f - d2 * invH2);
            });
            counts[grid.particles[s]] = float(n);
        }
    });
    return counts;
}

// Each vertex's edge neighbours, once each, ascending (CSR: first[v] .. first[v + 1]).
void vertexNeighbours(const TriangleMesh& m, std::vector<std::uint32_t>& first, std::vector<std::uint32_t>& list) {
    const std::size_t V = m.vertexCount();
    first.assign(V + 1, 0);
    for (std::size_t k = 0; k < m.indices.size(); ++k) first[m.indices[k] + 1] += 2;
    for (std::size_t v = 0; v < V; ++v) first[v + 1] += first[v];
    list.resize(first[V]);
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t a = m.indices[t + std::size_t(c)];
            list[fill[a]++] = m.indices[t + std::size_t((c + 1) % 3)];
            list[fill[a]++] = m.indices[t + std::size_t((c + 2) % 3)];
        }
    // Sorted and unique per vertex, compacted in place.
    std::uint32_t out = 0;
    for (std::size_t v = 0; v < V; ++v) {
        const auto b = list.begin() + first[v], e = list.begin() + first[v + 1];
        std::sort(b, e);
        const auto u = std::unique(b, e);
        const std::uint32_t start = out;
        for (auto i = b; i != u; ++i) list[out++] = *i;
        first[v] = start;
    }
    first[V] = out;
    list.resize(out);
}

}  // namespace

Status smoothMesh(const ParticleSet& particles, const MeshSmoothing& params, float supportM, TriangleMesh& mesh,
                  int threads, std::vector<float>* weightsOut) {
    if (params.iterations < 0 || params.iterations > 10000)
        return makeError("", "smoothing iterations must be 0 to 10000, not " + std::to_string(params.iterations));
    if (!(params.normalization > 0.0f) || !std::isfinite(params.normalization))
        return makeError("", "the smoothing weights' normalisation must be positive");
    if (auto st = mesh.validate(); !st) return st;
    const std::size_t V = mesh.vertexCount();
    if (params.iterations == 0 || V == 0) return okStatus();
    std::vector<float> weights(V, 1.0f);
    auto work = [&]() -> Status {
        if (params.weights) {
            // Steps 1 and 2: the counts, interpolated onto a copy of the vertices.
            ParticleSet counted;
            counted.positions = particles.positions;
            counted.attributes.push_back(
                {"wnn", AttributeType::Float, 1, weightedNeighbourCounts(particles.positions, supportM), {}});
            TriangleMesh at;
            at.positions = mesh.positions;
            if (auto st = interpolateAttributes(counted, {"wnn"}, supportM, at, threads); !st) return st;
            const std::vector<float>& n = at.attributes[0].floats;
            for (std::size_t v = 0; v < V; ++v) {
                const float x = std::min(std::max(n[v], 0.0f) / params.normalization, 1.0f);
                weights[v] = x * x * x * (x * (x * 6.0f - 15.0f) + 10.0f);
            }
        }
        // Step 3: Jacobi steps over the edge neighbours.
        std::vector<std::uint32_t> first, list;
        vertexNeighbours(mesh, first, list);
        std::vector<glm::vec3> next(V);
        for (int it = 0; it < params.iterations; ++it) {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, V, 4096), [&](const auto& r) {
                for (std::size_t v = r.begin(); v < r.end(); ++v) {
                    const std::uint32_t b = first[v], e = first[v + 1];
                    if (b == e) {
                        next[v] = mesh.positions[v];
                        continue;
                    }
                    glm::vec3 mean(0.0f);
                    for (std::uint32_t k = b; k < e; ++k) mean += mesh.positions[list[k]];
                    mean /= float(e - b);
                    next[v] = (1.0f - weights[v]) * mesh.positions[v] + weights[v] * mean;
                }
            });
            mesh.positions.swap(next);
        }
        return okStatus();
    };
    Status st = okStatus();
    if (threads > 0) tbb::task_arena(threads).execute([&] { st = work(); });
    else st = work();
    if (!st) return st;
    // Normals of the smoothed triangles, angle-weighted as the mesher's.
    if (!mesh.normals.empty()) {
        surface::BlockOutput whole;
        whole.vertices = mesh.positions;
        whole.triangles = mesh.indices;
        surface::blockNormalSums(whole, 0);
        for (std::size_t v = 0; v < V; ++v) {
            const float len = glm::length(whole.normalSums[v]);
            mesh.normals[v] = len > 0.0f ? whole.normalSums[v] / len : mesh.normals[v];
        }
    }
    if (weightsOut) *weightsOut = std::move(weights);
    return okStatus();
}

}  // namespace meniscus
