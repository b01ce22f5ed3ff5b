// The key light's camera for the shadows (shadow_camera.h).
#include "core/shadow_camera.h"

#include <algorithm>
#include <cmath>

#include "core/geometry_draw.h"
#include "shared/shadow.h"
#include "shared/sky.h"

namespace meniscus {

bool drawsShadows(const RenderSettings& s) {
    if (s.shadows == ShadowMode::On) return true;
    return s.shadows != ShadowMode::Off && drawsAnyObject(s.geometry.get());
}

ShadowLight shadowLight(const FrameSettings& s) {
    Bounds b;
    const auto& p = s.particles.positions;
    for (std::size_t i = 0; i < p.count; ++i) {
        const glm::vec3 q = p[i];
        if (std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z)) b.extend(q);
    }
    // The particles of a host's GL buffer: the box the host gave for them.
    if (s.hostParticles && !s.hostParticles->bounds.empty()) {
        b.extend(s.hostParticles->bounds.min);
        b.extend(s.hostParticles->bounds.max);
    }
    const float r = std::isfinite(s.radius) ? std::max(s.radius, 0.0f) : 0.0f;
    if (!b.empty()) {
        b.extend(b.min - glm::vec3(r));
        b.extend(b.max + glm::vec3(r));
    }
    if (s.geometry) {
        for (const GeometryObject& o : s.geometry->objects)
            if (drawsObject(o))
                for (const glm::vec3& q : o.mesh.positions) b.extend(q);
    }
    if (b.empty()) b = Bounds{glm::vec3(-1.0f), glm::vec3(1.0f)};
    // Snapped, so that the light's camera (and the texels of the geometry's
    // shadow) stays the same while the particles move a little: the radius
    // rounded up to a power of 2^(1/4), the centre to 1/16 of it (the sphere
    // grown by that to still cover the bounds).
    const float exact = std::max(0.5f * glm::length(b.extent()), 1e-3f);
    const float radius = std::exp2(std::ceil(4.0f * std::log2(exact / (1.0f - std::sqrt(3.0f) / 32.0f))) / 4.0f);
    const float step = radius / 16.0f;
    const glm::vec3 centre = glm::round(b.center() / step) * step;
    const glm::vec3 light = shared::sunDirection(s.studio.lightDirWorld);
    const float distance = 50.0f * radius;
    ShadowLight out;
    Camera& c = out.camera;
    c.eye = centre + light * distance;
    c.target = centre;
    c.up = std::abs(light.y) < 0.99f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(0.0f, 0.0f, 1.0f);
    c.fovYDegrees = 2.0f * std::asin(std::min(1.0f, 1.01f * radius / distance)) * (180.0f / 3.14159265358979f);
    c.nearM = distance - 1.05f * radius;
    c.farM = distance + 1.05f * radius;
    c.width = c.height = shared::kShadowMapPx;
    out.texelM = 2.0f * 1.01f * radius / float(shared::kShadowMapPx);
    return out;
}

void shadowCasters(const SceneGeometry* geometry, const glm::vec3& lightEye, TriangleMesh& out) {
    out.positions.clear();
    out.normals.clear();
    out.indices.clear();
    if (!geometry) return;
    std::vector<std::uint32_t> scratch;
    for (const GeometryObject& object : geometry->objects) {
        if (!drawsObject(object) || object.material.glass) continue;
        const TriangleMesh& m = object.mesh;
        const std::span<const std::uint32_t> kept = facesSeenFrom(m, lightEye, sceneFaces(object), &scratch);
        const auto base = std::uint32_t(out.positions.size());
        out.positions.insert(out.positions.end(), m.positions.begin(), m.positions.end());
        out.normals.insert(out.normals.end(), m.normals.begin(), m.normals.end());
        for (const std::uint32_t i : kept) out.indices.push_back(base + i);
    }
}

}  // namespace meniscus
