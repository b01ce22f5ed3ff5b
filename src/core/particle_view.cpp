// ParticleView: views of a ParticleSet's canonical attributes, and the checks
// render() applies before it reads any of them.
#include "meniscus/particle_view.h"

#include <string>

namespace meniscus {

namespace {

const Attribute* findTyped(const ParticleSet& set, std::string_view name, AttributeType type, int components) {
    const Attribute* a = set.find(name);
    if (!a || a->type != type || a->components != components || a->count() != set.size()) return nullptr;
    return a;
}

template <class T>
StridedView<T> floatView(const ParticleSet& set, std::string_view name, int components) {
    const Attribute* a = findTyped(set, name, AttributeType::Float, components);
    return a ? StridedView<T>(a->floats.data(), a->count()) : StridedView<T>();
}

StridedView<std::int64_t> intView(const ParticleSet& set, std::string_view name) {
    const Attribute* a = findTyped(set, name, AttributeType::Int, 1);
    return a ? StridedView<std::int64_t>(a->ints.data(), a->count()) : StridedView<std::int64_t>();
}

template <class T>
Status checkView(const StridedView<T>& v, const char* what, std::size_t n) {
    if (!v.present()) return okStatus();
    if (!v.data) return makeError("", std::string("particle ") + what + " view has no data");
    if (v.strideBytes < sizeof(T))
        return makeError("", std::string("particle ") + what + " stride " + std::to_string(v.strideBytes) +
                                 " bytes is smaller than one element (" + std::to_string(sizeof(T)) + " bytes)");
    if (v.count != n)
        return makeError("", std::string("particle ") + what + " has " + std::to_string(v.count) +
                                 " values for " + std::to_string(n) + " positions");
    return okStatus();
}

}  // namespace

ParticleView ParticleView::of(const ParticleSet& set) {
    ParticleView v(std::span<const glm::vec3>(set.positions));
    v.velocity = floatView<glm::vec3>(set, kAttrVelocity, 3);
    v.density = floatView<float>(set, kAttrDensity, 1);
    v.id = intView(set, kAttrId);
    v.fluid = intView(set, kAttrFluid);
    v.color = floatView<glm::vec3>(set, kAttrColor, 3);
    for (std::string_view name : kAttrRadiusNames)
        if (!v.radius.present()) v.radius = floatView<float>(set, name, 1);
    return v;
}

Status ParticleView::validate() const {
    const std::size_t n = positions.count;
    for (const Status& st : {checkView(positions, "positions", n), checkView(velocity, "velocity", n),
                             checkView(density, "density", n),
                             checkView(id, "id", n), checkView(fluid, "fluid index", n),
                             checkView(color, "colour", n), checkView(radius, "radius", n)})
        if (!st) return st;
    return okStatus();
}

}  // namespace meniscus
