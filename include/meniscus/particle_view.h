// What render() reads of a particle set: positions plus the optional
// per-particle attributes later stages use (velocity for spray/foam, density,
// id, fluid index for several fluids, a colour), each as a strided view into
// the caller's memory, so an array of structs, separate arrays, or a
// ParticleSet as the readers return it are all rendered without a copy.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>

#include <glm/glm.hpp>

#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus {

// Element i of a StridedView is the T at byte offset i * strideBytes from
// data. No alignment is assumed (elements are copied out with memcpy), so a
// view may point into packed records. count == 0 means "absent".
template <class T>
struct StridedView {
    const std::byte* data = nullptr;
    std::size_t count = 0;
    std::size_t strideBytes = sizeof(T);

    StridedView() = default;
    StridedView(const void* first, std::size_t n, std::size_t stride = sizeof(T))
        : data(static_cast<const std::byte*>(first)), count(n), strideBytes(stride) {}
    StridedView(std::span<const T> values) : StridedView(values.data(), values.size()) {}  // NOLINT: implicit on purpose

    // A view of one member of an array of records: StridedView<glm::vec3>::of(records, &Rec::pos).
    template <class Record>
    static StridedView of(std::span<const Record> records, T Record::*member) {
        if (records.empty()) return {};
        return {&(records.data()->*member), records.size(), sizeof(Record)};
    }

    bool present() const { return count > 0; }
    bool contiguous() const { return strideBytes == sizeof(T); }
    T operator[](std::size_t i) const {
        T v;
        std::memcpy(&v, data + i * strideBytes, sizeof(T));
        return v;
    }
};

// Canonical names of the attributes a ParticleView carries (see types.h for
// id, velocity and density; the readers map their columns to these names).
inline constexpr std::string_view kAttrFluid = "fluid";  // Int, 1 component: which fluid (0, 1, ...)
inline constexpr std::string_view kAttrColor = "color";  // Float, 3 components: linear RGB in [0, 1]
// Float, 1 component, metres: each particle's own radius. ParticleView::of
// takes the first of these names a set has (Houdini writes pscale).
inline constexpr std::string_view kAttrRadiusNames[] = {"radius", "pscale", "particle_radius"};
// Float, 1 component, metres: each particle's SPH smoothing length h
// (PySPH's h, GADGET-style hsml). Not a radius: addRadiusFromSmoothingLength
// (particles.h) turns it into one.
inline constexpr std::string_view kAttrSmoothingLengthNames[] = {"h", "smoothing_length", "SmoothingLength", "hsml"};

// The particles [begin, end) of a view.
struct ParticleRange {
    std::size_t begin = 0, end = 0;
};

struct ParticleView {
    StridedView<glm::vec3> positions;   // metres, world space (required)
    StridedView<glm::vec3> velocity;    // m/s
    StridedView<float> density;         // kg/m^3
    StridedView<std::int64_t> id;       // the simulation's particle id
    StridedView<std::int64_t> fluid;    // fluid index, 0-based
    StridedView<glm::vec3> color;       // linear RGB
    StridedView<float> radius;          // metres, each particle's own (variable resolution)

    ParticleView() = default;
    // Positions alone (every existing caller of render(span) keeps working).
    ParticleView(std::span<const glm::vec3> p) : positions(p) {}  // NOLINT: implicit on purpose
    ParticleView(const std::vector<glm::vec3>& p) : positions(std::span<const glm::vec3>(p)) {}  // NOLINT

    std::size_t size() const { return positions.count; }

    // Views of a set's positions and of the attributes it has under the
    // canonical names with the expected type and components (others are left
    // out). The set must outlive the view.
    static ParticleView of(const ParticleSet& set);

    // OK when every attribute present has one value per position and the
    // strides are at least the element size; otherwise an error saying which
    // attribute is wrong.
    Status validate() const;
};

}  // namespace meniscus
