// Collider distances and the guard (see colliders.h).
#include "sim/colliders.h"

#include <algorithm>
#include <cmath>

namespace meniscus::sim {

namespace {

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, §5.1.5).
glm::vec3 closestOnTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const glm::vec3 bp = p - b;
    const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
    const glm::vec3 cp = p - c;
    const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const float denom = 1.0f / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

// Sign by the generalised winding number (Jacobson et al. 2013): robust for
// closed meshes whatever the query point; > 0.5 inside.
float windingNumber(const TriangleMesh& m, const glm::vec3& p) {
    double sum = 0.0;
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        const glm::vec3 a = m.positions[m.indices[t]] - p, b = m.positions[m.indices[t + 1]] - p,
                        c = m.positions[m.indices[t + 2]] - p;
        const float la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
        const float num = glm::dot(a, glm::cross(b, c));
        const float den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
        sum += 2.0 * std::atan2(double(num), double(den));
    }
    return float(sum / (4.0 * 3.14159265358979323846));
}

}  // namespace

SurfacePoint colliderDistance(const Collider& c, const TriangleMesh* mesh, const glm::vec3& x) {
    switch (c.kind) {
        case Collider::Kind::Plane: {
            const glm::vec3 n = glm::normalize(c.normal);
            return {glm::dot(x - c.point, n), n};
        }
        case Collider::Kind::Sphere: {
            const glm::vec3 d = x - c.center;
            const float len = glm::length(d);
            return {len - c.radius, len > 0.0f ? d / len : glm::vec3(0, 1, 0)};
        }
        case Collider::Kind::Box: {
            const glm::vec3 centre = 0.5f * (c.box.min + c.box.max), half = 0.5f * (c.box.max - c.box.min);
            const glm::vec3 q = glm::abs(x - centre) - half;
            const glm::vec3 sgn = glm::sign(x - centre) + glm::vec3(glm::equal(x, centre));  // 0 -> +1
            if (glm::all(glm::lessThanEqual(q, glm::vec3(0.0f)))) {
                // Inside or on the surface: out through the nearest face.
                int axis = 0;
                if (q.y > q[axis]) axis = 1;
                if (q.z > q[axis]) axis = 2;
                glm::vec3 n(0.0f);
                n[axis] = sgn[axis];
                return {q[axis], n};
            }
            const glm::vec3 out = glm::max(q, glm::vec3(0.0f));
            const float len = glm::length(out);
            return {len, sgn * out / len};
        }
        case Collider::Kind::Mesh: {
            float best = 1e30f;
            glm::vec3 bestPoint = x;
            for (std::size_t t = 0; t + 2 < mesh->indices.size(); t += 3) {
                const glm::vec3 p = closestOnTriangle(x, mesh->positions[mesh->indices[t]],
                                                      mesh->positions[mesh->indices[t + 1]],
                                                      mesh->positions[mesh->indices[t + 2]]);
                const float d2 = glm::dot(p - x, p - x);
                if (d2 < best) best = d2, bestPoint = p;
            }
            const float d = std::sqrt(best);
            const bool inside = windingNumber(*mesh, x) > 0.5f;
            glm::vec3 n = d > 0.0f ? (x - bestPoint) / d : glm::vec3(0, 1, 0);
            if (inside) n = -n;
            return {inside ? -d : d, n};
        }
    }
    return {1e30f, glm::vec3(0, 1, 0)};
}

bool keepOutside(const Scene& scene, const std::vector<ColliderMesh>& meshes, float radius, glm::vec3& x,
                 glm::vec3& v, const glm::vec3& before) {
    bool moved = false;
    // Onto the surface, not beyond: a jump into the fluid would compress it
    // and push back, putting energy into the flow.
    const float back = 0.0f * radius;
    // Domain walls: the centre stays inside the tank.
    auto inTank = [&] {
        for (int a = 0; a < 3; ++a) {
            if (!(x[a] >= scene.domain.min[a])) {  // also catches NaN
                x[a] = scene.domain.min[a] + back, v[a] = std::max(v[a], 0.0f), moved = true;
            } else if (x[a] > scene.domain.max[a]) {
                x[a] = scene.domain.max[a] - back, v[a] = std::min(v[a], 0.0f), moved = true;
            }
        }
    };
    inTank();
    bool pushed = false;
    forEachCollider(scene, meshes, x, 0.0f, [&](const Collider&, const SurfacePoint& s) {
        if (s.distance < 0.0f) {
            x += s.normal * (back - s.distance);
            const float vn = glm::dot(v, s.normal);
            if (vn < 0.0f) v -= vn * s.normal;
            moved = pushed = true;
        }
    });
    if (!pushed) return moved;
    // A collider's nearest face may lie on or beyond a tank wall (a box on the
    // floor, a ball sunk into it): out through it is out of the tank, and the
    // tank putting it back puts it into the collider again. Then the particle
    // goes back to where the step began (outside everything), at rest, as
    // SPlisHSPlasH's fallback for a particle its boundary could not hold.
    inTank();
    bool inside = false;
    forEachCollider(scene, meshes, x, 0.0f, [&](const Collider&, const SurfacePoint& s) { inside |= s.distance < 0.0f; });
    if (inside) x = before, v = glm::vec3(0.0f);
    return moved;
}

bool projectOutside(const Scene& scene, const std::vector<ColliderMesh>& meshes, float gap, glm::vec3& x) {
    bool moved = false;
    forEachCollider(scene, meshes, x, gap, [&](const Collider&, const SurfacePoint& s) {
        if (s.distance < gap) x += s.normal * (gap - s.distance), moved = true;
    });
    // The tank last: a collider may lie against a wall, and its way out must
    // not be out of the tank. A tank thinner than two gaps keeps the centre.
    for (int a = 0; a < 3; ++a) {
        const float lo = scene.domain.min[a] + gap, hi = scene.domain.max[a] - gap;
        const float c = lo <= hi ? std::clamp(x[a], lo, hi) : 0.5f * (scene.domain.min[a] + scene.domain.max[a]);
        moved = moved || c != x[a];
        x[a] = c;
    }
    return moved;
}

}  // namespace meniscus::sim
