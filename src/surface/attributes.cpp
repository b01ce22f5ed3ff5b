// Particle attributes on the mesh's vertices (docs/meshes.md#attributes):
// each named attribute interpolated at every vertex x by the SPH cubic spline
// W of support h (shared/sph_kernels.h, the mesher's own SPH kernel),
// normalised by the kernel sum (Shepard's interpolation, the "normalised" SPH
// interpolant of Koschier et al.'s SPH tutorial, Eurographics 2019, §3.1):
//
//   A(x) = sum_j A_j W(|x - x_j|, h) / sum_j W(|x - x_j|, h)
//
// The plain SPH sum, sum_j (m_j / rho_j) A_j W, sees only half a
// neighbourhood at a free surface, which is where every vertex lies, and
// would give a vertex about half its particles' velocity; the normalised one
// reproduces a constant field exactly (a linear one up to its gradient times
// the offset of the kernel-weighted centre, about 1.4 r inward at a flat
// face). Sums in double, over the particles in one fixed order (sorted by
// grid cell, then index), so the values are the same for any thread count.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include "meniscus/surface.h"
#include "shared/sph_kernels.h"
#include "surface/cell_grid.h"

namespace meniscus {

namespace {

using surface::CellGrid;
using surface::makeGrid;

}  // namespace

Status interpolateAttributes(const ParticleSet& particles, const std::vector<std::string>& names, float supportM,
                             TriangleMesh& mesh, int threads) {
    if (names.empty()) return okStatus();
    if (!(supportM > 0.0f) || !std::isfinite(supportM))
        return makeError("", "the interpolation's support must be a positive length, not " + std::to_string(supportM));
    if (particles.positions.size() >= std::size_t(UINT32_MAX))
        return makeError("", "at most 2^32 - 1 particles can be interpolated from");
    for (const glm::vec3& p : particles.positions)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            return makeError("", "a particle position is not finite");
    // The attributes asked for, each once, checked whole before any work.
    std::vector<const Attribute*> sources;
    for (const std::string& name : names) {
        const Attribute* a = particles.find(name);
        if (!a) {
            std::string have;
            for (const Attribute& b : particles.attributes) have += (have.empty() ? "" : ", ") + b.name;
            return makeError("", "--interpolate " + name + ": the particles have no such attribute (they have: " +
                                     (have.empty() ? std::string("none") : have) + ")");
        }
        if (a->components < 1 || a->count() != particles.size())
            return makeError("", "--interpolate " + name + ": the attribute does not have one value per particle");
        for (const Attribute& m : mesh.attributes)
            if (m.name == name) return makeError("", "--interpolate " + name + ": named twice");
        if (std::find(sources.begin(), sources.end(), a) != sources.end())
            return makeError("", "--interpolate " + name + ": named twice");
        sources.push_back(a);
    }
    const std::size_t V = mesh.positions.size();
    const std::size_t first = mesh.attributes.size();
    for (const Attribute* a : sources) {
        Attribute out;
        out.name = a->name;
        out.type = AttributeType::Float;
        out.components = a->components;
        out.floats.assign(V * std::size_t(a->components), 0.0f);
        mesh.attributes.push_back(std::move(out));
    }
    if (V == 0) return okStatus();
    if (particles.size() == 0) {
        mesh.attributes.resize(first);
        return makeError("", "no particles to interpolate the attributes from");
    }

    // The particles in cells of h / kSplit, so a vertex's candidates are the
    // (2 kSplit + 1)^3 cells around its own: (2.5 h)^3 of space at kSplit = 2
    // instead of the (3 h)^3 of cells of h. The vertices grouped by cell (one
    // candidate list per group) and the groups spread over the threads.
    constexpr int kSplit = 2;
    const CellGrid grid = makeGrid(particles.positions, double(supportM) / kSplit);
    const float h2 = supportM * supportM, invH = 1.0f / supportM;
    std::size_t components = 0;
    for (const Attribute* a : sources) components += std::size_t(a->components);
    // Every value asked for, as doubles, in the grid's order: components
    // values per particle, read without indirection in the sums below.
    std::vector<double> values(grid.particles.size() * components);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid.particles.size()), [&](const auto& r) {
        for (std::size_t s = r.begin(); s < r.end(); ++s) {
            const std::size_t p = grid.particles[s];
            double* out = &values[s * components];
            for (const Attribute* a : sources)
                for (int c = 0; c < a->components; ++c) {
                    const std::size_t k = p * std::size_t(a->components) + std::size_t(c);
                    *out++ = a->type == AttributeType::Int ? double(a->ints[k]) : double(a->floats[k]);
                }
        }
    });
    std::vector<std::pair<std::uint64_t, std::uint32_t>> byCell(V);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, V), [&](const auto& r) {
        for (std::size_t v = r.begin(); v < r.end(); ++v) {
            const glm::vec3 x = mesh.positions[v];
            byCell[v] = {CellGrid::key(grid.axis(x.x, 0), grid.axis(x.y, 1), grid.axis(x.z, 2)), std::uint32_t(v)};
        }
    });
    tbb::parallel_sort(byCell.begin(), byCell.end());
    std::vector<std::size_t> groups;  // the first vertex of each cell's run in byCell, and V
    for (std::size_t i = 0; i < V; ++i)
        if (i == 0 || byCell[i].first != byCell[i - 1].first) groups.push_back(i);
    groups.push_back(V);
    std::vector<std::uint8_t> unreached(V, 0);
    auto work = [&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, groups.size() - 1, 16), [&](const auto& r) {
            std::vector<double> sums(components);
            std::vector<std::uint32_t> candidates;  // indices into the grid's sorted arrays, in their order
            for (std::size_t g = r.begin(); g < r.end(); ++g) {
                candidates.clear();
                grid.forNear(byCell[groups[g]].first, kSplit,
                             [&](std::size_t s) { candidates.push_back(std::uint32_t(s)); });
                for (std::size_t k = groups[g]; k < groups[g + 1]; ++k) {
                    const std::size_t v = byCell[k].second;
                    const glm::vec3 x = mesh.positions[v];
                    std::fill(sums.begin(), sums.end(), 0.0);
                    double weight = 0.0;
                    for (const std::uint32_t s : candidates) {
                        const glm::vec3 d = grid.positions[s] - x;
                        const float d2 = glm::dot(d, d);
                        if (!(d2 < h2)) continue;
                        const double w = double(shared::sphKernel(std::sqrt(d2) * invH));
                        weight += w;
                        const double* of = &values[std::size_t(s) * components];
                        for (std::size_t c = 0; c < components; ++c) sums[c] += w * of[c];
                    }
                    if (!(weight > 0.0)) {
                        unreached[v] = 1;
                        continue;
                    }
                    std::size_t c = 0;
                    for (std::size_t m = 0; m < sources.size(); ++m) {
                        Attribute& out = mesh.attributes[first + m];
                        for (int j = 0; j < out.components; ++j)
                            out.floats[v * std::size_t(out.components) + std::size_t(j)] = float(sums[c++] / weight);
                    }
                }
            }
        });
    };
    if (threads > 0) tbb::task_arena(threads).execute(work);
    else work();
    const auto miss = std::find(unreached.begin(), unreached.end(), std::uint8_t(1));
    if (miss != unreached.end()) {
        mesh.attributes.resize(first);
        return makeError("", "vertex " + std::to_string(miss - unreached.begin()) +
                                 " is beyond the support of every particle: the mesh was not made from these "
                                 "particles (or with a larger support)");
    }
    return okStatus();
}

}  // namespace meniscus
