// DualSPHysics' boundary particles drawn as solid walls (docs/geometry.md,
// "DualSPHysics boundaries"). DualSPHysics writes its boundary particles (the
// tank's walls, obstacles, pistons, floating bodies) in the same output as
// the fluid, told apart by the Type array: 0 fixed, 1 moving, 2 floating
// boundary, 3 fluid (DualSphysicsType, particles.h). The renderer takes them
// out of the liquid and draws each kind as an opaque surface: the project's
// own isosurface mesher (surface.h) over the boundary particles at their own
// spacing, a closed mesh around a wall of one particle layer or several.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/geometry.h"
#include "meniscus/mesh.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus {

// What the renderer does with a frame's DualSPHysics boundary particles
// (--boundary-particles): walls (meshed, drawn as scene geometry), liquid
// (drawn as the liquid, as any particle), hidden (dropped).
enum class BoundaryMode { Walls, Liquid, Hidden };
bool boundaryModeFromName(const std::string& name, BoundaryMode* out);
const char* boundaryModeName(BoundaryMode mode);

// The attribute of `set` holding DualSPHysics' Type: one component, named
// "Type" as DualSPHysics names it (the readers keep the name); null when the
// set has none.
const Attribute* dualSphysicsTypeAttribute(const ParticleSet& set);

// A frame's boundary particles by kind, positions in the set's coordinates.
struct BoundaryParticles {
    std::vector<glm::vec3> fixed;   // Type 0: walls that never move (the tank)
    std::vector<glm::vec3> moving;  // Type 1 and 2: moving boundaries (pistons, gates) and floating bodies
    bool empty() const { return fixed.empty() && moving.empty(); }
    std::size_t size() const { return fixed.size() + moving.size(); }
};

// Takes the boundary particles (Type 0, 1 and 2) out of `set`, from its
// positions and every attribute alike (order kept), and returns them. A set
// without a Type attribute is left as it is (nothing returned), and so is one
// whose Type holds a value that is not one of DualSPHysics' types (a whole
// number 0 to 3: another program's "Type"), with a warning in set.warnings.
// An error, naming `name` (the file), when the Type attribute's value count
// is not one per particle.
Result<BoundaryParticles> takeBoundaryParticles(ParticleSet& set, const std::string& name);

// The meshing of a boundary made of particles at spacing dp: the SPH field
// (cubic spline of support 2 dp, the particles' radius r = dp / 2) at
// kBoundaryIso of the field inside fluid at rest, on cubes of dp / 2. A
// single flat layer of particles at spacing dp has the field 0.70 in its
// plane (0.38 where one particle is missing), so the level 0.35 wraps it in a
// closed, hole-free slab whose faces are ~0.7 dp from the particles' plane.
inline constexpr float kBoundaryIso = 0.35f;
inline constexpr float kBoundaryCubeRadii = 1.0f;  // cube edge in r = dp / 2

// The particles' spacing dp: their median nearest-neighbour distance
// (estimateRadius); 0 for fewer than two distinct positions.
float boundarySpacing(std::span<const glm::vec3> positions);

// The closed surface around boundary particles at spacing `spacingM` (> 0;
// 0: boundarySpacing of the particles), the mesher's
// errors passed on (never throws).
Result<TriangleMesh> meshBoundaryParticles(std::span<const glm::vec3> positions, float spacingM = 0.0f);

// Orients a boundary's mesh as a container's (GeometryObject::cutaway): each
// triangle wound so that its outside faces away from `centre` (the tank's
// middle). Both faces of a thin wall then face away from the inside, so the
// scene layer's cut-away (sceneFaces, facesSeenFrom: per triangle, by the side
// its outside faces) hides the whole of each wall between the camera and the
// liquid and keeps both faces of the far walls. The vertices and their
// normals are left as they are (the shading faces a normal to the viewer).
void orientAwayFrom(TriangleMesh& mesh, const glm::vec3& centre);

// Meshes of fixed boundaries kept by the particles' positions (a hash of
// their bytes, their count and the spacing), so a sequence whose walls never
// move meshes them once. The last kEntries are kept (bounded memory: a
// sequence has one tank; the viewer may switch between two inputs).
class BoundaryMeshCache {
public:
    static constexpr std::size_t kEntries = 2;
    // The mesh of `positions` (meshBoundaryParticles), from the cache when the
    // same positions were meshed before.
    Result<std::shared_ptr<const TriangleMesh>> mesh(std::span<const glm::vec3> positions);
    // How many meshes were made (not found in the cache) so far.
    std::size_t meshed() const;

private:
    struct Entry {
        std::uint64_t hash = 0;
        std::size_t count = 0;
        std::shared_ptr<const TriangleMesh> mesh;
    };
    mutable std::mutex mutex_;
    std::vector<Entry> entries_;  // most recent last
    std::size_t meshed_ = 0;
};

// The process-wide cache prepareBoundary (options.h) keeps the fixed walls'
// meshes in: every frame of a sequence, and the viewer, share it.
BoundaryMeshCache& boundaryMeshCache();

// 64-bit FNV-1a of the positions' bytes (the cache's key).
std::uint64_t hashPositions(std::span<const glm::vec3> positions);

// The scene geometry of a frame's boundary particles, opaque with the
// default material: "boundary particles (fixed)", a container cut away
// (GeometryObject::cutaway) when `cutAway` and it encloses the liquid's
// middle `liquidCentre`, its mesh from `cache` (null: meshed here); and
// "boundary particles (moving)", meshed each time, drawn whole. Kinds without
// particles are left out.
Result<SceneGeometry> boundaryGeometry(const BoundaryParticles& boundary, bool cutAway,
                                       const glm::vec3& liquidCentre, BoundaryMeshCache* cache);

}  // namespace meniscus
