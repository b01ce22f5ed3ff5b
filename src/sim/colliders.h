// The last line of defence behind the boundary particles: a particle whose
// centre has crossed a wall of the domain or entered a collider is put back
// just outside it (half a radius), its velocity into the surface removed.
// With the boundary particles working this never fires in a normal run (the
// tests check that it does not); it keeps the promise "no particle leaves the
// domain or passes a collider" when a step is too large, e.g. in ballistic
// mode, which has no boundary particles at all.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "meniscus/mesh.h"
#include "meniscus/sim.h"

namespace meniscus::sim {

// A mesh collider's triangles (scaled and moved into place) and their bounds.
struct ColliderMesh {
    TriangleMesh mesh;
    glm::vec3 lo{0.0f}, hi{0.0f};
};

// Signed distance from a collider's surface (negative inside the solid) and
// the outward normal there. Mesh colliders need their triangles.
struct SurfacePoint {
    float distance;
    glm::vec3 normal;
};
SurfacePoint colliderDistance(const Collider& c, const TriangleMesh* mesh, const glm::vec3& x);

// Calls f(collider, surface point) for every collider of the scene, with
// the signed distance from x; a mesh collider only when x lies within its
// bounds grown by `reach` (farther, its distance is not needed).
template <class F>
void forEachCollider(const Scene& scene, const std::vector<ColliderMesh>& meshes, const glm::vec3& x, float reach,
                     F&& f) {
    std::size_t mesh = 0;
    for (const Collider& c : scene.colliders) {
        const ColliderMesh* cm = c.kind == Collider::Kind::Mesh ? &meshes[mesh++] : nullptr;
        if (cm && (glm::any(glm::lessThan(x, cm->lo - glm::vec3(reach))) ||
                   glm::any(glm::greaterThan(x, cm->hi + glm::vec3(reach)))))
            continue;
        f(c, colliderDistance(c, cm ? &cm->mesh : nullptr, x));
    }
}

// Returns true when x was corrected (moved out, v's inward part removed);
// `before` is where the step began (inside the tank, outside the colliders),
// where x goes back to if no surface point outside both can be found.
bool keepOutside(const Scene& scene, const std::vector<ColliderMesh>& meshes, float radius, glm::vec3& x,
                 glm::vec3& v, const glm::vec3& before);

// Position-based collision response (Macklin & Muller 2013, Algorithm 1):
// moves x to at least `gap` metres inside the tank's walls and outside every
// collider, along the nearest surface's normal. Returns true when it moved.
bool projectOutside(const Scene& scene, const std::vector<ColliderMesh>& meshes, float gap, glm::vec3& x);

}  // namespace meniscus::sim
