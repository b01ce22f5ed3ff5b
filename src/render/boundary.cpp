// DualSPHysics' boundary particles drawn as walls (include/meniscus/boundary.h).
#include "meniscus/boundary.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include "meniscus/options.h"
#include "meniscus/particle_view.h"
#include "meniscus/particles.h"
#include "meniscus/surface.h"

namespace meniscus {

bool boundaryModeFromName(const std::string& name, BoundaryMode* out) {
    if (name == "walls") *out = BoundaryMode::Walls;
    else if (name == "liquid") *out = BoundaryMode::Liquid;
    else if (name == "hidden") *out = BoundaryMode::Hidden;
    else return false;
    return true;
}

const char* boundaryModeName(BoundaryMode mode) {
    switch (mode) {
        case BoundaryMode::Walls: return "walls";
        case BoundaryMode::Liquid: return "liquid";
        case BoundaryMode::Hidden: return "hidden";
    }
    return "walls";
}

const Attribute* dualSphysicsTypeAttribute(const ParticleSet& set) {
    // DualSPHysics names the array "Type" (JSph::SaveData; PartVTK's -vars:+type);
    // the readers keep the name as written.
    const Attribute* a = set.find("Type");
    if (!a || a->components != 1) return nullptr;
    return a;
}

namespace {

// Value k of a one-component attribute as a type code, or -1 when it is not
// one of DualSPHysics' (a whole number 0 to 3).
int typeCode(const Attribute& a, std::size_t k) {
    if (a.type == AttributeType::Int) {
        const std::int64_t v = a.ints[k];
        return v >= 0 && v <= 3 ? int(v) : -1;
    }
    const float v = a.floats[k];
    return v == 0.0f || v == 1.0f || v == 2.0f || v == 3.0f ? int(v) : -1;
}

}  // namespace

Result<BoundaryParticles> takeBoundaryParticles(ParticleSet& set, const std::string& name) {
    BoundaryParticles out;
    const Attribute* type = dualSphysicsTypeAttribute(set);
    if (!type) return out;
    const std::size_t n = set.size();
    if (type->count() != n || (type->type == AttributeType::Float ? type->floats.size() : type->ints.size()) != n)
        return makeError(name, "attribute '" + type->name + "' (DualSPHysics' particle type) has " +
                                   std::to_string(type->count()) + " values for " + std::to_string(n) +
                                   " particles");
    // Another program's "Type" (not 0 to 3, or not whole): not DualSPHysics'
    // types, the particles are left as they are, with a warning.
    for (std::size_t k = 0; k < n; ++k)
        if (typeCode(*type, k) < 0) {
            set.warnings.push_back("attribute '" + type->name + "' holds values other than DualSPHysics' particle "
                                   "types (0 fixed, 1 moving, 2 floating, 3 fluid), e.g. at particle " +
                                   std::to_string(k) + ": every particle drawn as the liquid");
            return out;
        }
    std::vector<char> keep(n, 1);
    std::size_t kept = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const int code = typeCode(*type, k);
        if (code == int(DualSphysicsType::Fluid)) {
            ++kept;
            continue;
        }
        keep[k] = 0;
        (code == int(DualSphysicsType::Fixed) ? out.fixed : out.moving).push_back(set.positions[k]);
    }
    if (out.empty()) return out;
    // The rest of the set, every attribute alike (one value group per particle).
    std::vector<glm::vec3> positions;
    positions.reserve(kept);
    for (std::size_t k = 0; k < n; ++k)
        if (keep[k]) positions.push_back(set.positions[k]);
    set.positions = std::move(positions);
    for (Attribute& a : set.attributes) {
        const std::size_t c = std::size_t(std::max(a.components, 1));
        const auto compact = [&](auto& values) {
            if (values.size() != n * c) return;  // not per particle: left as the reader gave it
            std::size_t w = 0;
            for (std::size_t k = 0; k < n; ++k)
                if (keep[k]) {
                    for (std::size_t j = 0; j < c; ++j) values[w * c + j] = values[k * c + j];
                    ++w;
                }
            values.resize(w * c);
        };
        if (a.type == AttributeType::Float) compact(a.floats);
        else compact(a.ints);
    }
    return out;
}

float boundarySpacing(std::span<const glm::vec3> positions) {
    if (positions.size() < 2) return 0.0f;
    return estimateRadius(positions).medianNeighbourDistance;
}

Result<TriangleMesh> meshBoundaryParticles(std::span<const glm::vec3> positions, float spacingM) {
    if (positions.empty()) return TriangleMesh{};
    float dp = spacingM > 0.0f ? spacingM : boundarySpacing(positions);
    if (!(dp > 0.0f)) {
        // One particle (or all at one place): a ball of the bounds' 1 %, as estimateRadius falls back.
        dp = 2.0f * estimateRadius(positions).radius;
        if (!(dp > 0.0f)) dp = 0.01f;
    }
    MeshParams p;
    p.radiusM = 0.5f * dp;
    p.field = SurfaceField::Sph;  // cubic spline, support 4 r = 2 dp
    p.cubeSizeRadii = kBoundaryCubeRadii;
    p.iso = kBoundaryIso;
    return extractSurface(ParticleView(positions), p);
}

void orientAwayFrom(TriangleMesh& mesh, const glm::vec3& centre) {
    const std::size_t n = mesh.positions.size();
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
        if (a >= n || b >= n || c >= n) continue;
        const glm::vec3 pa = mesh.positions[a], pb = mesh.positions[b], pc = mesh.positions[c];
        const glm::vec3 outward = glm::cross(pb - pa, pc - pa);
        const glm::vec3 middle = (pa + pb + pc) / 3.0f;
        if (glm::dot(outward, middle - centre) < 0.0f) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
    }
}

std::uint64_t hashPositions(std::span<const glm::vec3> positions) {
    std::uint64_t h = 14695981039346656037ull;  // FNV-1a, 64-bit
    const auto* bytes = reinterpret_cast<const unsigned char*>(positions.data());
    const std::size_t size = positions.size() * sizeof(glm::vec3);
    for (std::size_t i = 0; i < size; ++i) {
        h ^= bytes[i];
        h *= 1099511628211ull;
    }
    return h;
}

Result<std::shared_ptr<const TriangleMesh>> BoundaryMeshCache::mesh(std::span<const glm::vec3> positions) {
    const std::uint64_t hash = hashPositions(positions);
    {
        std::lock_guard lock(mutex_);
        for (std::size_t k = 0; k < entries_.size(); ++k)
            if (entries_[k].hash == hash && entries_[k].count == positions.size()) {
                Entry e = entries_[k];  // most recent last
                entries_.erase(entries_.begin() + std::ptrdiff_t(k));
                entries_.push_back(e);
                return e.mesh;
            }
    }
    auto made = meshBoundaryParticles(positions);
    if (!made) return made.error();
    auto shared = std::make_shared<const TriangleMesh>(std::move(*made));
    std::lock_guard lock(mutex_);
    ++meshed_;
    entries_.push_back({hash, positions.size(), shared});
    if (entries_.size() > kEntries) entries_.erase(entries_.begin());
    return shared;
}

std::size_t BoundaryMeshCache::meshed() const {
    std::lock_guard lock(mutex_);
    return meshed_;
}

BoundaryMeshCache& boundaryMeshCache() {
    static BoundaryMeshCache cache;
    return cache;
}

Result<SceneGeometry> boundaryGeometry(const BoundaryParticles& boundary, bool cutAway, const glm::vec3& liquidCentre,
                                       BoundaryMeshCache* cache) {
    SceneGeometry out;
    if (!boundary.fixed.empty()) {
        GeometryObject o;
        o.name = "boundary particles (fixed)";
        if (cache) {
            auto m = cache->mesh(boundary.fixed);
            if (!m) return m.error();
            o.mesh = **m;
        } else {
            auto m = meshBoundaryParticles(boundary.fixed);
            if (!m) return m.error();
            o.mesh = std::move(*m);
        }
        o.cutaway = cutAway;
        if (cutAway) {
            // A tank (its box holds the liquid's middle) is turned about its
            // own middle, which stays put from frame to frame; a floor or a
            // ramp away from the liquid's middle about that middle, so both
            // its faces face away from the liquid.
            const Bounds b = computeBounds(boundary.fixed);
            const bool encloses = glm::all(glm::greaterThanEqual(liquidCentre, b.min)) &&
                                  glm::all(glm::lessThanEqual(liquidCentre, b.max));
            orientAwayFrom(o.mesh, encloses ? 0.5f * (b.min + b.max) : liquidCentre);
        }
        if (o.mesh.triangleCount() > 0) out.objects.push_back(std::move(o));
    }
    if (!boundary.moving.empty()) {
        GeometryObject o;
        o.name = "boundary particles (moving)";
        auto m = meshBoundaryParticles(boundary.moving);
        if (!m) return m.error();
        o.mesh = std::move(*m);
        if (o.mesh.triangleCount() > 0) out.objects.push_back(std::move(o));
    }
    return out;
}

Result<std::shared_ptr<const SceneGeometry>> prepareBoundary(ParticleSet& set, const RenderOptions& o,
                                                             std::shared_ptr<const SceneGeometry> base,
                                                             const std::string& name) {
    BoundaryMode mode = BoundaryMode::Walls;
    if (!boundaryModeFromName(o.boundaryParticles, &mode))
        return makeError("", "--boundary-particles " + o.boundaryParticles + ": expected walls, liquid or hidden");
    if (mode == BoundaryMode::Liquid || !dualSphysicsTypeAttribute(set)) return base;
    auto boundary = takeBoundaryParticles(set, name);
    if (!boundary) return boundary.error();
    if (mode == BoundaryMode::Hidden || boundary->empty()) return base;
    const Bounds liquid = computeBounds(set.positions);
    Bounds all = liquid;
    for (const glm::vec3& p : boundary->fixed) all.extend(p);
    for (const glm::vec3& p : boundary->moving) all.extend(p);
    const glm::vec3 centre = liquid.empty() ? 0.5f * (all.min + all.max) : 0.5f * (liquid.min + liquid.max);
    // The fixed walls of a sequence are meshed once: the last few kept.
    auto walls = boundaryGeometry(*boundary, o.cutAway == "on", centre, &boundaryMeshCache());
    if (!walls) return makeError(name, "--boundary-particles walls: " + walls.error().message);
    auto combined = std::make_shared<SceneGeometry>(base ? *base : SceneGeometry{});
    combined->append(std::move(*walls));
    return std::shared_ptr<const SceneGeometry>(std::move(combined));
}

}  // namespace meniscus
