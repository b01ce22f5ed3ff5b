// Whole named arrays -> one particle set (see column_set.h).
#include "io/column_set.h"

#include <algorithm>

#include "io/attribute_names.h"
#include "io/io_util.h"

namespace meniscus::io_util {

namespace {

constexpr std::string_view kPositionArrayNames[] = {"position", "positions", "pos", "points", "p"};

Attribute floatAttribute(std::string name, int components, std::size_t values) {
    Attribute a;
    a.name = std::move(name);
    a.type = AttributeType::Float;
    a.components = components;
    a.floats.resize(values);
    return a;
}

float componentValue(const Column& c, std::size_t k) {
    return c.isInt ? float(c.ints[k]) : float(c.floats[k]);
}

}  // namespace

std::string listNames(const std::vector<std::string>& names, std::size_t max) {
    std::string out;
    for (std::size_t i = 0; i < names.size() && i < max; ++i) out += (i ? ", " : "") + quoteShort(names[i]);
    if (names.size() > max) out += ", ... (" + std::to_string(names.size()) + " in all)";
    return out.empty() ? "nothing" : out;
}

std::string joinNames(const std::vector<std::string>& texts) {
    std::string out;
    for (std::size_t i = 0; i < texts.size(); ++i) out += (i ? ", " : "") + texts[i];
    return out;
}

ParticleSet particlesFromColumns(std::vector<Column> columns, std::size_t count, const std::string& noPositions) {
    // Only scalar columns take part in the x/y/z, u/v/w, rho, id matching: an
    // empty name never matches the table.
    std::vector<std::string> scalarNames;
    for (const Column& c : columns) scalarNames.push_back(c.components == 1 ? c.name : std::string());
    const ColumnRoles roles = findColumnRoles(scalarNames);

    ParticleSet set;
    std::vector<bool> used(columns.size(), false);
    if (roles.hasPosition()) {
        set.positions.resize(count);
        for (int axis = 0; axis < 3; ++axis) {
            const Column& c = columns[std::size_t(roles.position[std::size_t(axis)])];
            for (std::size_t k = 0; k < count; ++k) set.positions[k][axis] = componentValue(c, k);
            used[std::size_t(roles.position[std::size_t(axis)])] = true;
        }
    } else {
        for (std::size_t i = 0; i < columns.size() && set.positions.empty(); ++i) {
            const Column& c = columns[i];
            const std::string key = attributeKey(c.name);
            if (c.components != 3 || std::find(std::begin(kPositionArrayNames), std::end(kPositionArrayNames), key) ==
                                         std::end(kPositionArrayNames))
                continue;
            set.positions.resize(count);
            for (std::size_t k = 0; k < count; ++k)
                for (int axis = 0; axis < 3; ++axis)
                    set.positions[k][axis] = componentValue(c, 3 * k + std::size_t(axis));
            used[i] = true;
        }
        if (set.positions.empty()) fail(noPositions);
    }

    bool haveVelocity = false, haveDensity = false, haveId = false;
    if (roles.hasVelocity()) {
        Attribute v = floatAttribute(std::string(kAttrVelocity), 3, 3 * count);
        for (int axis = 0; axis < 3; ++axis) {
            const std::size_t i = std::size_t(roles.velocity[std::size_t(axis)]);
            for (std::size_t k = 0; k < count; ++k) v.floats[3 * k + std::size_t(axis)] = componentValue(columns[i], k);
            used[i] = true;
        }
        set.attributes.push_back(std::move(v));
        haveVelocity = true;
    }
    if (roles.density >= 0) {
        const Column& c = columns[std::size_t(roles.density)];
        Attribute d = floatAttribute(std::string(kAttrDensity), 1, count);
        for (std::size_t k = 0; k < count; ++k) d.floats[k] = componentValue(c, k);
        set.attributes.push_back(std::move(d));
        used[std::size_t(roles.density)] = true;
        haveDensity = true;
    }
    // An id must be a whole number: a float "id" array stays a Float attribute
    // under its own (non-canonical) name below.
    if (roles.id >= 0 && columns[std::size_t(roles.id)].isInt) {
        Column& c = columns[std::size_t(roles.id)];
        Attribute a;
        a.name = std::string(kAttrId);
        a.type = AttributeType::Int;
        a.ints = std::move(c.ints);
        set.attributes.push_back(std::move(a));
        used[std::size_t(roles.id)] = true;
        haveId = true;
    }

    for (std::size_t i = 0; i < columns.size(); ++i) {
        if (used[i]) continue;
        Column& c = columns[i];
        // A whole three-component velocity array (npz "velocity" of shape (N, 3)).
        std::string name(canonicalArrayName(c.name, c.components));
        const bool taken = (name == kAttrVelocity && (haveVelocity || c.isInt)) ||
                           (name == kAttrDensity && (haveDensity || c.isInt)) || (name == kAttrId && (haveId || !c.isInt));
        if (name.empty() || taken) name = nonCanonicalName(c.name, "_file");
        else if (name == kAttrVelocity) haveVelocity = true;
        else if (name == kAttrDensity) haveDensity = true;
        else if (name == kAttrId) haveId = true;
        for (const Attribute& a : set.attributes)
            if (a.name == name) name += "_" + std::to_string(i);  // two arrays whose names map alike
        Attribute a;
        a.name = std::move(name);
        a.components = c.components;
        if (c.isInt) {
            a.type = AttributeType::Int;
            a.ints = std::move(c.ints);
        } else {
            a.type = AttributeType::Float;
            a.floats.resize(c.floats.size());
            for (std::size_t k = 0; k < c.floats.size(); ++k) a.floats[k] = float(c.floats[k]);
            c.floats = {};
        }
        set.attributes.push_back(std::move(a));
    }
    return set;
}

}  // namespace meniscus::io_util
