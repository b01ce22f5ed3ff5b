// The built-in simulator's scene as drawn geometry (simulationGeometry,
// include/meniscus/geometry.h): every collider where the simulator puts it,
// so what is drawn is what the particles collide with, and the domain's walls
// as a cut-away box. Here, in the simulator's module, because it knows the
// colliders; the shapes are core's and the mesh reader is io's.
#include <cmath>

#include "meniscus/geometry.h"
#include "meniscus/io.h"
#include "meniscus/sim.h"

namespace meniscus {

Result<SceneGeometry> simulationGeometry(const sim::Scene& scene) {
    using sim::Collider;
    SceneGeometry out;
    const glm::vec3 lo = scene.domain.min, hi = scene.domain.max;
    const glm::vec3 centre = 0.5f * (lo + hi);
    // A plane is infinite to the simulator; drawn, it is a square wide enough
    // to reach across the domain from its point nearest the domain's centre.
    const float reach = std::max(glm::length(hi - lo), 1e-3f);
    for (std::size_t i = 0; i < scene.colliders.size(); ++i) {
        const Collider& c = scene.colliders[i];
        GeometryObject g;
        switch (c.kind) {
            case Collider::Kind::Box:
                g.name = "collider " + std::to_string(i) + " (box)";
                g.mesh = makeBoxMesh(c.box.min, c.box.max);
                break;
            case Collider::Kind::Sphere:
                g.name = "collider " + std::to_string(i) + " (sphere)";
                g.mesh = makeSphereMesh(c.center, c.radius);
                break;
            case Collider::Kind::Plane: {
                g.name = "collider " + std::to_string(i) + " (plane)";
                const glm::vec3 n = glm::normalize(c.normal);
                const glm::vec3 foot = centre - glm::dot(centre - c.point, n) * n;
                g.mesh = makePlaneMesh(foot, n, reach);
                break;
            }
            case Collider::Kind::Mesh: {
                g.name = c.mesh.filename().string();
                // The simulator's own reader (Simulator: readMesh, then
                // p * scale + translate), so the triangles are the very ones
                // the particles collide with.
                auto mesh = readMesh(c.mesh);
                if (!mesh) return mesh.error();
                g.mesh = std::move(mesh.value());
                if (g.mesh.empty()) return makeError(c.mesh.string(), "the collider mesh has no triangles");
                fillMissingNormals(g.mesh);
                glm::mat4 m(1.0f);
                m[0][0] = c.scale.x, m[1][1] = c.scale.y, m[2][2] = c.scale.z;
                m[3] = glm::vec4(c.translate, 1.0f);
                transformMesh(g.mesh, m);
                if (Status st = g.mesh.validate(true); !st) return makeError(c.mesh.string(), st.error().message);
                break;
            }
        }
        if (!c.material.empty()) {
            // Read by the geometry's own reader (one schema, one set of checks),
            // on a placeholder shape that carries it.
            const std::string where = "colliders[" + std::to_string(i) + "]";
            auto carried = parseGeometry(R"({"box": {"min": [0, 0, 0], "max": [1, 1, 1]}, "material": )" + c.material + "}",
                                         where, {});
            if (!carried) return makeError("", where + ".material: " + carried.error().message);
            g.material = carried->objects.front().material;
        }
        out.objects.push_back(std::move(g));
    }
    GeometryObject walls;
    walls.name = "domain";
    walls.mesh = makeBoxMesh(lo, hi);
    walls.cutaway = true;
    out.objects.push_back(std::move(walls));
    return out;
}

}  // namespace meniscus
