// libFuzzer target: scene files (src/sim/scene.cpp). Parses the input as a
// scene, then checks what docs/scenes.md promises for any input:
//  - an error names the file it was given and says what is wrong;
//  - a scene that parses holds only what the reader lets through: finite
//    numbers, boxes with min <= max (a volume for the domain and fluid
//    blocks), fluid blocks and nozzles inside the domain, positive radii,
//    speeds and frame rates, emitters that end after they start, drains
//    that overlap the domain, mesh files named .obj or .ply.
#include <cctype>
#include <cmath>
#include <string>
#include <string_view>

#include "fuzz_reader.h"
#include "meniscus/sim.h"

namespace meniscus::fuzz {
namespace {

void checkFinite(const glm::vec3& v, const char* what) {
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) broken("a non-finite vector", what);
}

void checkBox(const sim::Box& b, bool solid, const char* what) {
    checkFinite(b.min, what);
    checkFinite(b.max, what);
    for (int i = 0; i < 3; ++i)
        if (b.max[i] < b.min[i] || (solid && !(b.max[i] > b.min[i]))) broken("a box with min > max", what);
}

bool inside(const sim::Box& inner, const sim::Box& outer) {
    for (int i = 0; i < 3; ++i)
        if (inner.min[i] < outer.min[i] || inner.max[i] > outer.max[i]) return false;
    return true;
}

bool positive(float v) { return std::isfinite(v) && v > 0.0f; }
bool nonNegative(float v) { return std::isfinite(v) && v >= 0.0f; }

void checkScene(const sim::Scene& s) {
    const sim::SimParams& p = s.params;
    if (!positive(p.radius) || !positive(p.restDensity) || !positive(p.stiffness) || !positive(p.cfl) ||
        !positive(p.minDt) || !positive(p.maxDt) || p.maxDt < p.minDt)
        broken("a parameter out of range", "params");
    if (!positive(p.densityTolerance) || p.densityTolerance >= 1.0f || !positive(p.divergenceTolerance) ||
        p.divergenceTolerance >= 1.0f || p.maxIterations < 1 || p.resortEvery < 1)
        broken("a solver parameter out of range", "params");
    if (!nonNegative(p.viscosity) || !nonNegative(p.surfaceTension) || !nonNegative(p.lifetime))
        broken("a negative parameter", "params");
    checkFinite(p.gravity, "gravity");
    if (!(std::isfinite(s.fps) && s.fps > 0.0) || !(std::isfinite(s.duration) && s.duration >= 0.0))
        broken("fps or duration out of range", s.name);
    checkBox(s.domain, true, "domain");
    if (s.fluid.empty() && s.emitters.empty()) broken("a scene with nothing to simulate", s.name);
    for (const sim::FluidBlock& b : s.fluid) {
        checkBox(b.box, true, "fluid block");
        checkFinite(b.velocity, "fluid velocity");
        if (!inside(b.box, s.domain)) broken("a fluid block outside the domain", s.name);
        if (b.shape == sim::FluidBlock::Shape::Sphere && !positive(b.radius)) broken("a ball without a radius", s.name);
    }
    for (const sim::Collider& c : s.colliders) {
        checkBox(c.box, false, "collider box");
        checkFinite(c.center, "collider centre");
        checkFinite(c.point, "plane point");
        checkFinite(c.normal, "plane normal");
        checkFinite(c.translate, "mesh translate");
        if (c.kind == sim::Collider::Kind::Sphere && !positive(c.radius)) broken("a sphere without a radius", s.name);
        if (c.kind == sim::Collider::Kind::Plane && !(glm::dot(c.normal, c.normal) > 0.0f))
            broken("a plane without a normal", s.name);
        if (c.kind == sim::Collider::Kind::Mesh) {
            if (!positive(c.scale.x) || !positive(c.scale.y) || !positive(c.scale.z)) broken("a mesh scale <= 0", s.name);
            std::string ext = c.mesh.extension().string();
            for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
            if (ext != ".obj" && ext != ".ply") broken("a mesh that is not OBJ or PLY", c.mesh.string());
        }
    }
    for (const sim::Emitter& e : s.emitters) {
        checkFinite(e.position, "emitter position");
        if (!inside(sim::Box{e.position, e.position}, s.domain)) broken("a nozzle outside the domain", s.name);
        if (!(glm::dot(e.direction, e.direction) > 0.0f) || !nonNegative(e.radius) || !positive(e.speed) ||
            !nonNegative(e.rate) || !nonNegative(e.start) || !(e.end >= e.start))
            broken("an emitter out of range", s.name);
    }
    for (const sim::Drain& d : s.drains) {
        checkBox(d.box, false, "drain");
        for (int i = 0; i < 3; ++i)
            if (d.box.max[i] < s.domain.min[i] || d.box.min[i] > s.domain.max[i]) broken("a drain outside the domain", s.name);
    }
}

}  // namespace
}  // namespace meniscus::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string name = "fuzz.json";
    const auto scene =
        meniscus::sim::parseScene(std::string_view(reinterpret_cast<const char*>(data), size), name);
    if (meniscus::fuzz::checkError(scene, name)) meniscus::fuzz::checkScene(scene.value());
    return 0;
}
