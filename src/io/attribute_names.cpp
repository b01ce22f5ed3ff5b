// The alias table of attribute and column names (see attribute_names.h).
// Sources of the names: DualSPHysics' particle output (Pos, Idp, Vel, Rhop
// before v5.2 and Rho after, Type, Mk, Press; its CSV writes vectors as
// NAME.x NAME.y NAME.z with a unit in brackets: DualSPHysics src/source
// JSph.cpp SaveData, JOutputCsv.cpp SaveCsv, JDataArrays.cpp GetUnitsByName;
// tests/data/dualsphysics/README.txt), PySPH's
// particle arrays (x y z u v w rho h; pysph.base.utils), ParaView's CSV export
// (Points:0, Velocity:0), Houdini/partio (P, v), SPlisHSPlasH (velocity,
// density, id).
#include "io/attribute_names.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "io/io_util.h"

namespace meniscus::io_util {

namespace {

constexpr ComponentNames kPositionColumns[] = {
    {"x", "y", "z"},
    {"points:0", "points:1", "points:2"},
    {"pos.x", "pos.y", "pos.z"},
    {"pos_x", "pos_y", "pos_z"},
    {"position_x", "position_y", "position_z"},
    {"position.x", "position.y", "position.z"},
    {"px", "py", "pz"},
};

constexpr ComponentNames kVelocityColumns[] = {
    {"vx", "vy", "vz"},
    {"u", "v", "w"},
    {"vel.x", "vel.y", "vel.z"},
    {"vel_x", "vel_y", "vel_z"},
    {"velocity:0", "velocity:1", "velocity:2"},
    {"velocity_x", "velocity_y", "velocity_z"},
    {"velocity.x", "velocity.y", "velocity.z"},
};

constexpr std::string_view kVelocityNames[] = {"velocity", "vel", "v"};
constexpr std::string_view kDensityNames[] = {"density", "rho", "rhop"};
constexpr std::string_view kIdNames[] = {"id", "idp"};

template <std::size_t N>
bool oneOf(const std::string& key, const std::string_view (&names)[N]) {
    return std::find(std::begin(names), std::end(names), key) != std::end(names);
}

}  // namespace

std::string_view withoutUnit(std::string_view name) {
    auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    while (!name.empty() && blank(name.front())) name.remove_prefix(1);
    while (!name.empty() && blank(name.back())) name.remove_suffix(1);
    if (!name.empty() && name.back() == ']') {
        const std::size_t open = name.rfind('[');
        if (open != std::string_view::npos && open > 0) {
            name = name.substr(0, open);
            while (!name.empty() && blank(name.back())) name.remove_suffix(1);
        }
    }
    return name;
}

std::string attributeKey(std::string_view columnName) { return lower(withoutUnit(columnName)); }

std::string_view canonicalArrayName(std::string_view fileName, int components) {
    const std::string key = attributeKey(fileName);
    if (components == 3 && oneOf(key, kVelocityNames)) return kAttrVelocity;
    if (components == 1 && oneOf(key, kDensityNames)) return kAttrDensity;
    if (components == 1 && oneOf(key, kIdNames)) return kAttrId;
    return {};
}

std::span<const ComponentNames> positionColumns() { return kPositionColumns; }
std::span<const ComponentNames> velocityColumns() { return kVelocityColumns; }

int componentIn(std::span<const ComponentNames> triples, std::string_view columnName) {
    const std::string key = attributeKey(columnName);
    for (const ComponentNames& t : triples)
        for (int c = 0; c < 3; ++c)
            if (key == t[std::size_t(c)]) return c;
    return -1;
}

bool ColumnRoles::assigned(int i) const {
    return std::find(position.begin(), position.end(), i) != position.end() ||
           std::find(velocity.begin(), velocity.end(), i) != velocity.end() || density == i || id == i;
}

ColumnRoles findColumnRoles(std::span<const std::string> names) {
    ColumnRoles roles;
    std::vector<std::string> keys;
    keys.reserve(names.size());
    for (const std::string& n : names) keys.push_back(attributeKey(n));
    // A triple counts only when all three of its columns are present, and the
    // first complete triple in the table's order wins (so "u v w" is the
    // velocity only when no vx/vy/vz or Vel.x/.y/.z columns exist).
    auto completeTriple = [&](std::span<const ComponentNames> triples, std::array<int, 3>& out) {
        for (const ComponentNames& t : triples) {
            std::array<int, 3> found{-1, -1, -1};
            for (int c = 0; c < 3; ++c)
                for (std::size_t i = 0; i < keys.size() && found[std::size_t(c)] < 0; ++i)
                    if (keys[i] == t[std::size_t(c)]) found[std::size_t(c)] = int(i);
            if (found[0] >= 0 && found[1] >= 0 && found[2] >= 0) {
                out = found;
                return;
            }
        }
    };
    completeTriple(kPositionColumns, roles.position);
    completeTriple(kVelocityColumns, roles.velocity);
    // A column called by the canonical name itself wins over an alias, wherever
    // it stands ("rho" before "density": "density" is the density, "rho" is
    // kept by its name); otherwise the first alias.
    auto pick = [&](std::span<const std::string_view> names, int& out) {
        for (std::size_t i = 0; i < keys.size() && out < 0; ++i)
            if (!roles.assigned(int(i)) && keys[i] == names.front()) out = int(i);
        for (std::size_t i = 0; i < keys.size() && out < 0; ++i)
            if (!roles.assigned(int(i)) && std::find(names.begin(), names.end(), keys[i]) != names.end()) out = int(i);
    };
    pick(kDensityNames, roles.density);
    pick(kIdNames, roles.id);
    return roles;
}

std::string nonCanonicalName(std::string name, std::string_view suffix) {
    if (name == kAttrVelocity || name == kAttrDensity || name == kAttrId) name += suffix;
    return name;
}

bool floatIdsToInt(Attribute& a) {
    if (a.type != AttributeType::Float) return a.type == AttributeType::Int;
    std::vector<std::int64_t> ints(a.floats.size());
    for (std::size_t i = 0; i < a.floats.size(); ++i) {
        const float v = a.floats[i];
        if (!std::isfinite(v) || v != std::trunc(v) || std::fabs(v) > 9.0e18f) return false;
        ints[i] = std::int64_t(v);
    }
    a.type = AttributeType::Int;
    a.ints = std::move(ints);
    a.floats.clear();
    return true;
}

void applyCanonicalNames(std::vector<Attribute>& attrs) {
    auto taken = [&](std::string_view n) {
        return std::any_of(attrs.begin(), attrs.end(), [&](const Attribute& b) { return b.name == n; });
    };
    for (Attribute& a : attrs) {
        const std::string_view target = canonicalArrayName(a.name, a.components);
        if (target.empty() || a.name == target || taken(target)) continue;
        const bool fits = target == kAttrId ? floatIdsToInt(a) : a.type == AttributeType::Float;
        if (fits) a.name = std::string(target);
    }
}

std::size_t appendAttribute(std::vector<Attribute>& attrs, std::string name, AttributeType type, int components) {
    Attribute a;
    a.name = std::move(name);
    a.type = type;
    a.components = components;
    attrs.push_back(std::move(a));
    return attrs.size() - 1;
}

}  // namespace meniscus::io_util
