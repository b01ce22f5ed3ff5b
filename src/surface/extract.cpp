// The isosurface path's order (docs/surface.md, thesis §4.2): grid and blocks, the
// blocks in parallel (rounds while a surface crossing a seam hands seeds on;
// each block sums its vertex normals), the weld into one indexed mesh with
// normals. The one public entry point, extractSurface
// (include/meniscus/surface.h).
#include "meniscus/surface.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <new>
#include <tuple>
#include <unordered_map>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include "meniscus/memory_budget.h"
#include "meniscus/particles.h"
#include "surface/field.h"
#include "surface/grid.h"
#include "surface/marching_slices.h"
#include "surface/weld.h"

namespace meniscus {

bool surfaceFieldFromName(const std::string& name, SurfaceField* out) {
    if (name == "thesis") *out = SurfaceField::Thesis;
    else if (name == "sph") *out = SurfaceField::Sph;
    else return false;
    return true;
}

const char* surfaceFieldName(SurfaceField field) { return field == SurfaceField::Thesis ? "thesis" : "sph"; }

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// Corner indices are converted to float exactly only below 2^24.
constexpr long kMaxGridCubes = 1L << 24;

Status checkParams(const MeshParams& p) {
    if (auto st = checkRadius(p.radiusM); !st) return st;
    char msg[200];
    if (!(p.cubeSizeRadii >= 0.05f && p.cubeSizeRadii <= 8.0f)) {
        std::snprintf(msg, sizeof msg, "cube size %.3g radii is out of range: it must be between 0.05 and 8",
                      double(p.cubeSizeRadii));
        return makeError("", msg);
    }
    if (!(p.iso > 0.0f && p.iso <= 2.0f)) {
        std::snprintf(msg, sizeof msg, "iso level %.3g is out of range: it is a fraction of the rest value, in (0, 2]",
                      double(p.iso));
        return makeError("", msg);
    }
    if (p.supportRadii != 0.0f && !(p.supportRadii >= 1.0f && p.supportRadii <= 16.0f)) {
        std::snprintf(msg, sizeof msg, "support %.3g radii is out of range: it must be between 1 and 16",
                      double(p.supportRadii));
        return makeError("", msg);
    }
    if (p.blockCubes < 4 || p.blockCubes > 256) return makeError("", "block size must be between 4 and 256 cubes");
    if (p.threads < 0) return makeError("", "thread count must be 0 (all cores) or more");
    return okStatus();
}

struct Prepared {
    surface::Grid grid;
    std::vector<surface::Block> blocks;
};

// The grid over the finite particles, and their blocks (thesis §4.2.2): every
// block whose box grown by the support (plus two cubes, so rounding never
// drops one) holds a particle lists it; a particle lands in at most 8 blocks
// while the margin is under half a block.
Result<Prepared> subdivide(std::span<const glm::vec3> pos, const surface::Field& field, const MeshParams& p) {
    Prepared out;
    surface::Grid& g = out.grid;
    g.cube = p.cubeSizeRadii * p.radiusM;
    g.n = p.blockCubes;
    Bounds box;
    for (const glm::vec3& q : pos)
        if (std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z)) box.extend(q);
    if (box.empty()) return out;
    const float margin = field.support + 2.0f * g.cube;
    const int pad = int(std::ceil(margin / g.cube)) + 1;
    const glm::dvec3 lo = glm::floor(glm::dvec3(box.min) / double(g.cube)) - double(pad);
    const glm::dvec3 hi = glm::floor(glm::dvec3(box.max) / double(g.cube)) + double(pad + 1);
    const glm::dvec3 span = hi - lo;
    if (span.x > kMaxGridCubes || span.y > kMaxGridCubes || span.z > kMaxGridCubes || lo.x < -kMaxGridCubes ||
        lo.y < -kMaxGridCubes || lo.z < -kMaxGridCubes || hi.x > kMaxGridCubes || hi.y > kMaxGridCubes ||
        hi.z > kMaxGridCubes) {
        char msg[240];
        std::snprintf(msg, sizeof msg,
                      "the particles span %.3g m, more than %ld cubes of %.3g m along an axis; use a larger "
                      "cube size or drop far outliers",
                      double(std::max({box.extent().x, box.extent().y, box.extent().z})), kMaxGridCubes, double(g.cube));
        return makeError("", msg);
    }
    g.origin = glm::ivec3(lo);
    g.cubes = glm::ivec3(span);
    g.blocks = (g.cubes + g.n - 1) / g.n;

    // (block, particle) pairs, sorted: blocks in id order, particles by index.
    std::vector<std::uint64_t> pairs;
    pairs.reserve(pos.size() * 2);
    for (std::size_t i = 0; i < pos.size(); ++i) {
        const glm::vec3 q = pos[i];
        if (!(std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z))) continue;
        const glm::ivec3 a = glm::clamp((surface::floorToInt((q - margin) / g.cube) - g.origin) / g.n, glm::ivec3(0),
                                        g.blocks - 1);
        const glm::ivec3 b = glm::clamp((surface::floorToInt((q + margin) / g.cube) - g.origin) / g.n, glm::ivec3(0),
                                        g.blocks - 1);
        for (int z = a.z; z <= b.z; ++z)
            for (int y = a.y; y <= b.y; ++y)
                for (int x = a.x; x <= b.x; ++x) pairs.push_back(g.blockId(x, y, z) << 32 | std::uint64_t(i));
    }
    tbb::parallel_sort(pairs.begin(), pairs.end());
    for (std::size_t k = 0; k < pairs.size();) {
        surface::Block blk;
        blk.id = pairs[k] >> 32;
        blk.coord = g.blockCoord(blk.id);
        std::size_t e = k;
        while (e < pairs.size() && (pairs[e] >> 32) == blk.id) blk.particles.push_back(std::uint32_t(pairs[e++]));
        out.blocks.push_back(std::move(blk));
        k = e;
    }
    // The lookup cache's order: by z, then index.
    tbb::parallel_for(std::size_t(0), out.blocks.size(), [&](std::size_t b) {
        auto& ids = out.blocks[b].particles;
        std::sort(ids.begin(), ids.end(), [&](std::uint32_t x, std::uint32_t y) {
            return pos[x].z < pos[y].z || (pos[x].z == pos[y].z && x < y);
        });
    });
    return out;
}

// ---------------------------------------------------------------- memory
// What an extraction holds at its peak, estimated from the particles before
// anything large is allocated (checked against the memory budget, and printed
// by --stats). The surface is what costs: the march visits the cubes the
// surface crosses, about (|n_x| + |n_y| + |n_z|) A / c^2 of them for area A
// and cube edge c, and a voxel surface's faces over-count a smooth surface's
// area by the same mean projection, so
//   surface cubes ~ kCubesPerFace x exposed faces of the particles'
//                   occupancy in cells of 4r x (4r / c)^2
// (an exposed face: an occupied cell's face whose neighbour is empty; 4r,
// the support, fills a fluid's inside, where 2r cells leave holes between
// the particles). kCubesPerFace is measured: 0.76 on frame 21 of the
// dam break (117,649 particles; 239,986 cubes at c = r against 317,632),
// 0.69 on the demo frame (6,859; 30,721 against 44,672): lone drops'
// six faces over-count their small round surfaces.
constexpr double kCubesPerFace = 0.72;
// Per surface cube: kVerticesPerCube mesh vertices (measured, as below), and
// twice as many triangles (a closed mesh, Euler).
constexpr double kVerticesPerCube = 1.0;
// Bytes per vertex at the weld, when the blocks' outputs and the mesh are
// both alive (marching_slices.h's BlockOutput and weld.cpp):
//   block output: vertex 12, edge key 8, seam flag 1, normal sum 12, and two
//   triangles' 24 bytes of local indices, in vectors grown by doubling
//   (x 1.5 on average)                                                  85.5
//   the weld's remap 4; the mesh: position 12, normal 12, indices 24       52
constexpr double kBytesPerVertex = 1.5 * (33.0 + 24.0) + 4.0 + 48.0;
// Per particle: the contiguous copy (12), and per (block, particle) pair the
// sort key (8, reserved for 2 pairs a particle at least) and the block's
// index list (4).
constexpr double kBytesPerParticle = 12.0;
constexpr double kBytesPerPair = 8.0 + 4.0;

std::uint64_t exposedFaces(std::span<const glm::vec3> pos, float cell) {
    Bounds box;
    for (const glm::vec3& q : pos) box.extend(q);
    if (box.empty()) return 0;
    // 21 bits a coordinate: cells no smaller than a 2^20th of the span.
    cell = std::max(cell, std::max({box.extent().x, box.extent().y, box.extent().z}) / float(1 << 20));
    std::vector<std::uint64_t> keys(pos.size());
    auto key = [](std::uint64_t x, std::uint64_t y, std::uint64_t z) { return (z << 42) | (y << 21) | x; };
    for (std::size_t i = 0; i < pos.size(); ++i) {
        const glm::vec3 c = (pos[i] - box.min) / cell;
        keys[i] = key(std::uint64_t(c.x) + 1, std::uint64_t(c.y) + 1, std::uint64_t(c.z) + 1);
    }
    tbb::parallel_sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    const std::uint64_t mask = (std::uint64_t(1) << 21) - 1;
    std::uint64_t faces = 0;
    for (const std::uint64_t k : keys) {
        const std::uint64_t x = k & mask, y = (k >> 21) & mask, z = k >> 42;
        for (const std::uint64_t n : {key(x - 1, y, z), key(x + 1, y, z), key(x, y - 1, z), key(x, y + 1, z),
                                      key(x, y, z - 1), key(x, y, z + 1)})
            faces += !std::binary_search(keys.begin(), keys.end(), n);
    }
    return faces;
}

std::uint64_t estimateMeshBytes(std::span<const glm::vec3> pos, const surface::Field& field, const MeshParams& p,
                                int threads) {
    const double c = double(p.cubeSizeRadii) * double(p.radiusM), cell = 4.0 * double(p.radiusM);
    const double cubes = kCubesPerFace * double(exposedFaces(pos, float(cell))) * (cell / c) * (cell / c);
    // (block, particle) pairs: along each axis a particle's reach (the
    // support plus two cubes, each side) crosses into the next block with
    // probability 2 margin / block edge.
    const double margin = double(field.support) + 2.0 * c, edge = double(p.blockCubes) * c;
    const double perAxis = 1.0 + std::min(2.0 * margin / edge, 1e6);
    const double pairs = std::max(2.0, perAxis * perAxis * perAxis) * double(pos.size());
    // One marcher per thread: n+1 slices of (n+1)^2 corner values and the
    // three edge maps' ints (marching_slices.h), at most.
    const double n1 = double(p.blockCubes) + 1.0;
    const double marchers = double(threads) * n1 * n1 * n1 * 4.0 * 4.0;
    return std::uint64_t(cubes * kVerticesPerCube * kBytesPerVertex + double(pos.size()) * kBytesPerParticle +
                         pairs * kBytesPerPair + marchers);
}

Result<TriangleMesh> extract(const ParticleView& particles, const MeshParams& p, MeshStats& stats) {
    const auto t0 = Clock::now();
    if (auto st = checkParams(p); !st) return st.error();
    if (auto st = particles.validate(); !st) return st.error();
    if (particles.size() >= (std::size_t(1) << 32)) return makeError("", "more than 2^32 particles");
    // One contiguous array (the view may be strided).
    std::vector<glm::vec3> pos(particles.size());
    for (std::size_t i = 0; i < pos.size(); ++i) pos[i] = particles.positions[i];
    if (auto st = checkCoordinates(pos, ""); !st) return st.error();

    const surface::Field field = surface::makeField(p);
    stats.particles = pos.size();
    stats.cubeSizeM = p.cubeSizeRadii * p.radiusM;
    stats.supportM = field.support;
    stats.isoAbsolute = double(field.isoRaw);
    stats.estimatedBytes = estimateMeshBytes(pos, field, p, stats.threads);
    {
        char what[160];
        std::snprintf(what, sizeof what, "meshing %zu particles at a cube size of %.3g radii (%.3g mm)", pos.size(),
                      double(p.cubeSizeRadii), 1e3 * double(p.cubeSizeRadii) * double(p.radiusM));
        if (auto st = checkMemory(stats.estimatedBytes, what, "raise --cube-size"); !st) return st.error();
    }

    auto prepared = subdivide(pos, field, p);
    if (!prepared) return prepared.error();
    const surface::Grid& grid = prepared->grid;
    const std::vector<surface::Block>& blocks = prepared->blocks;
    stats.blocks = blocks.size();
    stats.msBlocks = msSince(t0);

    // Rounds: every block with its own seeds; then the blocks that were handed
    // a surface cube they had not reached resume with it, until none is.
    const auto t1 = Clock::now();
    std::vector<surface::BlockOutput> outputs(blocks.size());
    std::vector<std::vector<glm::ivec3>> seeds(blocks.size());
    std::unordered_map<std::uint64_t, std::size_t> slotOf;
    for (std::size_t b = 0; b < blocks.size(); ++b) slotOf[blocks[b].id] = b;
    tbb::enumerable_thread_specific<surface::BlockMarcher> marchers(
        [&] { return surface::BlockMarcher(grid, field, p.radiusM, pos); });
    std::vector<std::size_t> todo(blocks.size());
    for (std::size_t b = 0; b < blocks.size(); ++b) todo[b] = b;
    while (!todo.empty()) {
        ++stats.rounds;
        if (stats.rounds > 1) stats.blocksRerun += todo.size();
        tbb::parallel_for(std::size_t(0), todo.size(), [&](std::size_t k) {
            const std::size_t b = todo[k];
            using Mode = surface::BlockMarcher::RunMode;
            const Mode mode = stats.rounds > 1 ? Mode::Resume : p.exhaustive ? Mode::Exhaustive : Mode::Particles;
            marchers.local().run(blocks[b], seeds[b], mode, outputs[b]);
        }, tbb::simple_partitioner());
        for (std::size_t b : todo) seeds[b].clear();
        std::vector<std::uint8_t> again(blocks.size(), 0);
        for (std::size_t b : todo)
            for (const glm::ivec3& cube : outputs[b].handoff) {
                const glm::ivec3 bc = cube / grid.n;
                auto it = slotOf.find(grid.blockId(bc.x, bc.y, bc.z));
                if (it == slotOf.end()) continue;  // no particle within reach: no surface there
                const std::size_t t = it->second;
                const glm::ivec3 local = cube - bc * grid.n;
                if (outputs[t].wasVisited(local.x, local.y, local.z, grid.n)) continue;
                seeds[t].push_back(cube);
                again[t] = 1;
            }
        todo.clear();
        for (std::size_t b = 0; b < blocks.size(); ++b)
            if (again[b]) {
                auto& s = seeds[b];
                std::sort(s.begin(), s.end(), [](const glm::ivec3& a, const glm::ivec3& c) {
                    return std::tie(a.z, a.y, a.x) < std::tie(c.z, c.y, c.x);
                });
                s.erase(std::unique(s.begin(), s.end()), s.end());
                todo.push_back(b);
            }
    }
    stats.msExtract = msSince(t1);

    const auto t2 = Clock::now();
    TriangleMesh mesh;
    surface::weldBlocks(outputs, mesh);
    stats.msMerge = msSince(t2);
    std::size_t keptBytes = 0;
    for (const auto& o : outputs) {
        stats.seedWalks += o.seedWalks;
        stats.cubesVisited += o.cubesVisited;
        stats.cornersEvaluated += o.cornersEvaluated;
        stats.cacheEntries += o.cacheEntries;
        stats.cacheRows += o.cacheRows;
        stats.peakBlockBytes = std::max(stats.peakBlockBytes, o.peakBytes);
        stats.blocksWithSurface += o.triangles.empty() ? 0 : 1;
        keptBytes += o.vertices.capacity() * (2 * sizeof(glm::vec3) + sizeof(std::uint64_t) + 1) +
                     o.triangles.capacity() * sizeof(std::uint32_t) + o.visited.capacity() * sizeof(std::uint64_t);
    }
    outputs = {};
    stats.peakBytes = std::size_t(stats.threads) * stats.peakBlockBytes + keptBytes +
                      mesh.positions.capacity() * sizeof(glm::vec3) * 2 + mesh.indices.capacity() * sizeof(std::uint32_t);
    stats.msTotal = msSince(t0);
    return mesh;
}

}  // namespace

Result<TriangleMesh> extractSurface(const ParticleView& particles, const MeshParams& params, MeshStats* stats) {
    try {
        MeshStats local;
        MeshStats& s = stats ? *stats : local;
        s = MeshStats{};
        // All cores, or fewer where the caller limits oneTBB (global_control).
        const int available = int(std::min<std::size_t>(
            std::size_t(tbb::info::default_concurrency()),
            tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
        const int threads = params.threads > 0 ? params.threads : available;
        s.threads = threads;
        tbb::task_arena arena(threads);
        Result<TriangleMesh> out = makeError("", "");
        arena.execute([&] { out = extract(particles, params, s); });
        return out;
    } catch (const std::bad_alloc&) {
        return makeError("", "extracting the surface: out of memory");
    } catch (const std::exception& e) {
        return makeError("", std::string("extracting the surface: ") + e.what());
    }
}

double surfaceFieldValue(const ParticleView& particles, const MeshParams& params, const glm::vec3& point) {
    const surface::Field field = surface::makeField(params);
    double sum = 0.0;
    for (std::size_t i = 0; i < particles.size(); ++i) {
        const glm::vec3 d = particles.positions[i] - point;
        sum += double(field.kernel(glm::dot(d, d)));
    }
    return sum / field.rest;
}

}  // namespace meniscus
