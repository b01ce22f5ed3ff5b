// Core value types: images, bounds and particle sets. No GL, no I/O.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace meniscus {

using ByteView = std::span<const std::uint8_t>;

// A W×H image of T, row-major, row 0 is the TOP row (docs/conventions.md#conventions).
template <class T>
struct Image {
    int width = 0;
    int height = 0;
    std::vector<T> pixels;

    Image() = default;
    Image(int w, int h, const T& fill = T{}) : width(w), height(h), pixels(std::size_t(w) * std::size_t(h), fill) {}

    T& at(int x, int y) { return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
    const T& at(int x, int y) const { return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
    std::size_t size() const { return pixels.size(); }
    bool empty() const { return pixels.empty(); }
};

// Axis-aligned box in world space (metres). Default-constructed bounds are empty.
struct Bounds {
    glm::vec3 min{std::numeric_limits<float>::infinity()};
    glm::vec3 max{-std::numeric_limits<float>::infinity()};

    void extend(const glm::vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
    glm::vec3 center() const { return 0.5f * (min + max); }
    glm::vec3 extent() const { return max - min; }
};

// A per-particle attribute, kept by name. Values of particle k occupy
// [k*components, (k+1)*components) of `floats` (type Float) or `ints` (type Int).
enum class AttributeType { Float, Int };

struct Attribute {
    std::string name;
    AttributeType type = AttributeType::Float;
    int components = 1;
    std::vector<float> floats;         // used when type == Float
    std::vector<std::int64_t> ints;    // used when type == Int

    std::size_t count() const {
        const std::size_t n = type == AttributeType::Float ? floats.size() : ints.size();
        return components > 0 ? n / std::size_t(components) : 0;
    }
};

// Canonical attribute names every reader maps its columns to.
inline constexpr std::string_view kAttrId = "id";              // Int, 1 component
inline constexpr std::string_view kAttrVelocity = "velocity";  // Float, 3 components, m/s
inline constexpr std::string_view kAttrDensity = "density";    // Float, 1 component, kg/m^3

// One frame of particles: positions in metres (world space) plus any attributes.
struct ParticleSet {
    std::vector<glm::vec3> positions;
    std::vector<Attribute> attributes;
    std::vector<std::string> warnings;  // non-fatal notes from reading (dropped NaNs, ...)

    std::size_t size() const { return positions.size(); }

    const Attribute* find(std::string_view name) const {
        for (const auto& a : attributes)
            if (a.name == name) return &a;
        return nullptr;
    }
    Attribute* find(std::string_view name) {
        for (auto& a : attributes)
            if (a.name == name) return &a;
        return nullptr;
    }
};

}  // namespace meniscus
