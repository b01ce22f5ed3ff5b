// The isosurface path (docs/surface.md; thesis §4.2 after Rosenberg & Birdwell, I3D
// 2008): a closed, indexed triangle mesh of the liquid, extracted on the CPU
// from the particles by block-parallel, surface-following marching cubes with a
// per-block particle lookup cache. No rendering code: the mesh goes to a file
// (writeMesh, include/meniscus/io.h) or to the renderer's mesh path
// (RenderSettings::mesh).
#pragma once

#include <cstddef>
#include <string>

#include "meniscus/mesh.h"
#include "meniscus/params.h"
#include "meniscus/particle_view.h"
#include "meniscus/result.h"

namespace meniscus {

// CLI names: thesis, sph.
bool surfaceFieldFromName(const std::string& name, SurfaceField* out);
const char* surfaceFieldName(SurfaceField field);

// What one extraction did (the bench prints it).
struct MeshStats {
    std::size_t particles = 0;
    std::size_t blocks = 0;            // blocks holding particles
    std::size_t blocksWithSurface = 0;
    std::size_t rounds = 0;            // block passes (a surface crossing a block seam hands seeds on)
    std::size_t blocksRerun = 0;       // block runs after the first round (resumed with handed-on cubes)
    std::size_t seedWalks = 0;         // walks from particles toward the outside
    std::size_t cubesVisited = 0;      // surface cubes polygonised
    std::size_t cacheEntries = 0;      // lookup-cache entries filled (all runs)
    std::size_t cacheRows = 0;         // lookup-cache rows filled
    std::size_t cornersEvaluated = 0;  // field evaluations (corners recomputed after a slice was freed count again)
    std::size_t peakBlockBytes = 0;    // largest working memory of one block (slices, lookup cache, vertex map)
    std::size_t peakBytes = 0;         // bound on the peak: threads x the largest block's working memory + the blocks' results + the mesh
    std::size_t estimatedBytes = 0;    // the estimate made from the particles before extracting (checked against the memory budget)
    int threads = 0;
    float cubeSizeM = 0.0f;
    float supportM = 0.0f;
    double isoAbsolute = 0.0;  // the iso level in the field's own units (thesis: sum of f; sph: density / mass)
    double msBlocks = 0.0;     // subdivision into blocks
    double msExtract = 0.0;    // the blocks' marching and their normal sums (all rounds)
    double msMerge = 0.0;      // one indexed mesh, seams welded, normals summed and normalised
    double msTotal = 0.0;
};

// Extracts the surface of the particles' positions. Errors (never throws) for a
// radius or parameter out of range, non-finite positions, or a grid too large
// for memory. Deterministic: the same particles and parameters give the same
// mesh (same vertices, triangles and order) for any thread count.
Result<TriangleMesh> extractSurface(const ParticleView& particles, const MeshParams& params,
                                    MeshStats* stats = nullptr);

// Attributes on the vertices (docs/meshes.md#attributes): each particle
// attribute named (velocity, density, fluid, any other the set carries)
// interpolated at every vertex by the SPH cubic spline of support `supportM`
// (metres; the mesher's SPH support, MeshStats::supportM) normalised by the
// kernel sum, and appended to mesh.attributes as Float values of the same
// name and components (an Int attribute, such as the fluid index, becomes a
// weighted mean). The same values for any thread count (0: all cores). An
// error names an attribute the particles do not have (listing those they
// have), one named twice, or a vertex no particle reaches (a mesh not made
// from these particles); mesh.attributes is then as it was.
Status interpolateAttributes(const ParticleSet& particles, const std::vector<std::string>& names, float supportM,
                             TriangleMesh& mesh, int threads = 0);

// Weighted Laplacian smoothing (docs/meshes.md#smoothing; Löschner et al.
// 2023): `iterations` steps moving each vertex toward the mean of its edge
// neighbours by its weight, 1 on the bulk's surface and near 0 on splashes
// and drops (the particles' distance-weighted neighbour counts, interpolated
// onto the vertices, over `normalization`, eased), or 1 everywhere with
// weights off; the normals made again from the smoothed triangles. The
// particles are the mesh's own, supportM the sph field's support (metres).
// The same mesh for any thread count (0: all cores). weightsOut, when given,
// receives each vertex's weight.
struct MeshSmoothing {
    int iterations = 0;           // 0: none
    bool weights = true;          // the particles' weights (off: plain Laplacian smoothing)
    float normalization = 13.0f;  // the weighted neighbour count that gives a full weight
};
Status smoothMesh(const ParticleSet& particles, const MeshSmoothing& params, float supportM, TriangleMesh& mesh,
                  int threads = 0, std::vector<float>* weightsOut = nullptr);

// The field's value (normalised: 1 = fluid at rest) at a point, summed over all
// particles directly (no grid): what the tests check vertices against.
double surfaceFieldValue(const ParticleView& particles, const MeshParams& params, const glm::vec3& point);

}  // namespace meniscus
