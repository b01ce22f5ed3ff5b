// PLY particle reader (the format itself, header and rows: ply_format.h).
//
// Only the "vertex" element is read. Its scalar properties are named through
// the alias table every reader shares (io/attribute_names.h, any case): x y z
// become positions; vx vy vz (or another spelling of the table, e.g. Vel.x ...)
// -> "velocity" (Float, 3); density, rho or Rhop -> "density"; id or Idp -> "id"
// (Int). Other
// scalar vertex properties are kept by name (float types -> Float, integer types
// -> Int), except that a run NAME_0, NAME_1, ... NAME_{k-1} of one kind becomes
// one k-component attribute NAME (as writeParticles stores one); vertex list
// properties and all other elements (faces, edges, ...) are skipped, but still
// checked so that a truncated file is reported.
#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <optional>

#include "io/attribute_names.h"
#include "io/io_util.h"
#include "io/ply_format.h"
#include "meniscus/io.h"

namespace meniscus {

namespace {

using namespace ply;

// ---------------------------------------------------------------- vertex layout

// Where one vertex property's value goes.
enum class Slot { Skip, PosX, PosY, PosZ, Attribute };

struct Column {
    Slot slot = Slot::Skip;
    std::size_t attribute = 0;  // index into VertexLayout::attributes
    int component = 0;
    bool fromInteger = false;   // the property has an integer type
};

struct VertexLayout {
    std::vector<Column> columns;  // one per vertex property, in header order
    std::vector<Attribute> attributes;
    std::vector<std::string> warnings;
};

// How many properties from index i on are named BASE_0, BASE_1, ... (scalars
// of one kind, integer or float), when p[i] is BASE_0 and BASE is free; the
// particle writer stores a k-component attribute so. 0 when there is no run.
int componentRun(const Element& vertex, std::size_t i) {
    const Property& first = vertex.properties[i];
    if (first.isList || !first.name.ends_with("_0")) return 0;
    const std::string base = first.name.substr(0, first.name.size() - 2);
    if (base.empty() || base == kAttrVelocity || base == kAttrDensity || base == kAttrId) return 0;
    for (const Property& q : vertex.properties)
        if (q.name == base) return 0;
    int k = 1;
    while (i + std::size_t(k) < vertex.properties.size()) {
        const Property& q = vertex.properties[i + std::size_t(k)];
        if (q.isList || isIntegerType(q.type) != isIntegerType(first.type) || q.name != base + "_" + std::to_string(k))
            break;
        ++k;
    }
    return k >= 2 ? k : 0;
}

Result<VertexLayout> planVertexLayout(const Element& vertex, const std::string& name) {
    for (std::size_t i = 0; i < vertex.properties.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (vertex.properties[i].name == vertex.properties[j].name)
                return makeError(name, "PLY vertex element has two properties named '" + vertex.properties[i].name + "'");

    // Positions, velocity, density and id through the alias table every reader
    // shares (io/attribute_names.h); list properties take no part.
    std::vector<std::string> scalarNames;
    for (const Property& p : vertex.properties) scalarNames.push_back(p.isList ? std::string() : p.name);
    const io_util::ColumnRoles roles = io_util::findColumnRoles(scalarNames);
    const std::array<int, 3>& xyz = roles.position;
    const std::array<int, 3>& vel = roles.velocity;
    if (!roles.hasPosition()) {
        bool have[3] = {false, false, false};
        for (const std::string& n : scalarNames)
            if (const int c = io_util::componentIn(io_util::positionColumns(), n); c >= 0) have[c] = true;
        for (int c = 0; c < 3; ++c)
            if (!have[c]) return makeError(name, std::string("PLY vertex element has no scalar '") + "xyz"[c] + "' property");
        return makeError(name, "PLY vertex element has no complete set of scalar x, y, z properties");
    }
    const bool hasVelocity = roles.hasVelocity();
    const int density = roles.density;
    const int id = roles.id;

    VertexLayout layout;
    layout.columns.resize(vertex.properties.size());
    std::optional<std::size_t> velocityAttr;
    for (std::size_t i = 0; i < vertex.properties.size(); ++i) {
        const Property& p = vertex.properties[i];
        Column& col = layout.columns[i];
        col.fromInteger = isIntegerType(p.type);
        if (p.isList) {
            layout.warnings.push_back(name + ": skipped PLY vertex list property '" + p.name + "'");
            continue;
        }
        const int pi = int(i);
        if (pi == xyz[0] || pi == xyz[1] || pi == xyz[2]) {
            col.slot = pi == xyz[0] ? Slot::PosX : pi == xyz[1] ? Slot::PosY : Slot::PosZ;
            continue;
        }
        col.slot = Slot::Attribute;
        if (hasVelocity && (pi == vel[0] || pi == vel[1] || pi == vel[2])) {
            if (!velocityAttr)
                velocityAttr =
                    io_util::appendAttribute(layout.attributes, std::string(kAttrVelocity), AttributeType::Float, 3);
            col.attribute = *velocityAttr;
            col.component = pi == vel[0] ? 0 : pi == vel[1] ? 1 : 2;
        } else if (pi == density) {
            col.attribute =
                io_util::appendAttribute(layout.attributes, std::string(kAttrDensity), AttributeType::Float, 1);
        } else if (pi == id) {
            col.attribute = io_util::appendAttribute(layout.attributes, std::string(kAttrId), AttributeType::Int, 1);
        } else if (const int k = componentRun(vertex, i); k > 0) {
            const std::size_t a = io_util::appendAttribute(layout.attributes, p.name.substr(0, p.name.size() - 2),
                                                           col.fromInteger ? AttributeType::Int : AttributeType::Float, k);
            for (int c = 0; c < k; ++c) {
                Column& part = layout.columns[i + std::size_t(c)];
                part = {Slot::Attribute, a, c, col.fromInteger};
            }
            i += std::size_t(k - 1);
        } else {
            // Kept by name; a name that would clash with a canonical attribute
            // (a second density column, a scalar "velocity") gets a suffix.
            std::string attrName = io_util::nonCanonicalName(p.name, "_ply");
            col.attribute = io_util::appendAttribute(layout.attributes, attrName,
                                                     col.fromInteger ? AttributeType::Int : AttributeType::Float, 1);
        }
    }
    return layout;
}

// ---------------------------------------------------------------- vertices

Status storeVertex(std::size_t i, const std::vector<double>& values, const std::vector<Column>& columns,
                   ParticleSet& set, const std::string& name) {
    std::size_t k = 0;  // index into values (scalars only)
    for (const Column& col : columns) {
        if (col.slot == Slot::Skip) {
            continue;  // a list property: it has no entry in values
        }
        const double v = values[k++];
        switch (col.slot) {
            case Slot::PosX: set.positions[i].x = float(v); break;
            case Slot::PosY: set.positions[i].y = float(v); break;
            case Slot::PosZ: set.positions[i].z = float(v); break;
            case Slot::Attribute: {
                Attribute& a = set.attributes[col.attribute];
                const std::size_t at = i * std::size_t(a.components) + std::size_t(col.component);
                if (a.type == AttributeType::Float) {
                    a.floats[at] = float(v);
                } else {
                    if (!(std::isfinite(v) && v == std::trunc(v) && std::fabs(v) < 9.0e18))
                        return makeError(name, "PLY vertex " + std::to_string(i) + ": '" + a.name + "' value " +
                                                   std::to_string(v) + " is not an integer");
                    a.ints[at] = std::int64_t(v);
                }
                break;
            }
            case Slot::Skip: break;
        }
    }
    return okStatus();
}

Status readVertices(RowSource& source, const Element& vertex, ParticleSet& set, const std::string& name) {
    auto layout = planVertexLayout(vertex, name);
    if (!layout) return layout.error();
    Status fits = source.checkCount(vertex);
    if (!fits) return fits;

    const std::size_t n = std::size_t(vertex.count);
    set.positions.assign(n, glm::vec3(0.0f));
    set.attributes = std::move(layout->attributes);
    for (Attribute& a : set.attributes) {
        if (a.type == AttributeType::Float)
            a.floats.assign(n * std::size_t(a.components), 0.0f);
        else
            a.ints.assign(n * std::size_t(a.components), 0);
    }
    set.warnings.insert(set.warnings.end(), layout->warnings.begin(), layout->warnings.end());

    std::vector<double> values;
    for (std::size_t i = 0; i < n; ++i) {
        Status s = source.readRow(vertex, i, values);
        if (!s) return s;
        s = storeVertex(i, values, layout->columns, set, name);
        if (!s) return s;
    }
    return okStatus();
}

Result<ParticleSet> parsePlyImpl(ByteView data, const std::string& name) {
    const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
    if (data.empty()) return makeError(name, "file is empty");
    auto header = parseHeader(text, name);
    if (!header) return header.error();
    const Header& h = header.value();

    const auto vertexCount = std::count_if(h.elements.begin(), h.elements.end(),
                                           [](const Element& e) { return e.name == "vertex"; });
    if (vertexCount == 0) return makeError(name, "PLY file has no 'vertex' element");
    if (vertexCount > 1) return makeError(name, "PLY file has more than one 'vertex' element");

    const std::unique_ptr<RowSource> source = makeRowSource(h, data, name);

    ParticleSet set;
    for (const Element& e : h.elements) {
        Status s = e.name == "vertex" ? readVertices(*source, e, set, name) : source->skipElement(e);
        if (!s) return s.error();
    }
    return set;
}

}  // namespace

Result<ParticleSet> parsePly(ByteView data, const std::string& name) {
    return io_util::guardParse(name, "PLY", [&] { return parsePlyImpl(data, name); });
}

}  // namespace meniscus
