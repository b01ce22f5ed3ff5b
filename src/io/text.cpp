// Text particle readers: CSV with a header row, and plain XYZ.
//
// CSV follows RFC 4180 (https://www.rfc-editor.org/rfc/rfc4180) loosely: the
// first non-blank line names the columns; fields are separated by ',' or, when
// the header uses them instead, ';' or tab; names may be double-quoted and are
// trimmed. Column names are matched case-insensitively:
//   x y z, Points:0 Points:1 Points:2 (ParaView's "Save Data" CSV), pos_x ...,
//   position_x ...                                        -> positions
//   vx vy vz, Velocity:0 ... (ParaView), velocity_x ..., vel_x ...
//                                                         -> "velocity" (Float, 3)
//   density, rho                                          -> "density"
//   id                                                    -> "id" (Int)
// Every other named column is kept by its name as a Float attribute; columns
// with an empty name (a trailing separator) are ignored. Blank lines are
// skipped; a row with the wrong number of fields or a non-numeric field is an
// error naming the line.
//
// XYZ is the plain point-cloud format: one point per line, "x y z" separated by
// whitespace (commas are accepted too). Columns after the third carry no names,
// so they are ignored. '#' starts a comment; blank lines are skipped.
//
// Numbers may be "nan" or "inf" (any case, optional sign): they are returned as
// they are, and parseParticles() drops such particles afterwards.
#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <exception>
#include <new>
#include <optional>

#include "io/io_util.h"
#include "meniscus/io.h"

namespace meniscus {

namespace {

using io_util::Lines;
using io_util::parseNumber;
using io_util::quoteShort;

// ---------------------------------------------------------------- small helpers

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

std::string_view trim(std::string_view s) {
    while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
    while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
    return s;
}

std::string lower(std::string_view s) {
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return out;
}

// An integer, also written as a float with no fraction ("12.0").
bool parseInteger(std::string_view token, std::int64_t& out) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    const char* end = token.data() + token.size();
    if (const auto [ptr, ec] = std::from_chars(token.data(), end, out); ec == std::errc() && ptr == end && !token.empty())
        return true;
    double d = 0;
    if (!parseNumber(token, d) || !std::isfinite(d) || d != std::trunc(d) || std::fabs(d) >= 9.0e18) return false;
    out = std::int64_t(d);
    return true;
}

std::string_view asText(ByteView data) { return {reinterpret_cast<const char*>(data.data()), data.size()}; }

// ---------------------------------------------------------------- CSV

// Splits a CSV line on `delim`; double-quoted fields may hold the delimiter and
// "" for a quote. Fields are trimmed and unquoted.
void splitCsv(std::string_view line, char delim, std::vector<std::string>& out) {
    out.clear();
    std::string field;
    bool quoted = false;
    for (std::size_t i = 0; i <= line.size(); ++i) {
        const bool atEnd = i == line.size();
        const char c = atEnd ? delim : line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
                field += '"';
                ++i;
            } else if (c == '"') {
                quoted = false;
            } else if (!atEnd) {
                field += c;
            } else {
                quoted = false;  // unterminated quote: take what there is
                --i;
            }
        } else if (c == '"' && trim(field).empty()) {
            field.clear();
            quoted = true;
        } else if (c == delim) {
            out.emplace_back(trim(field));
            field.clear();
        } else {
            field += c;
        }
    }
}

char detectDelimiter(std::string_view header) {
    for (char d : {',', ';', '\t'})
        if (header.find(d) != std::string_view::npos) return d;
    return ',';
}

// Where one CSV column's values go.
enum class Slot { Ignore, PosX, PosY, PosZ, Attribute };

struct Column {
    Slot slot = Slot::Ignore;
    std::size_t attribute = 0;
    int component = 0;
    std::string name;  // as written, for messages
};

using NameTriple = std::array<std::string_view, 3>;

// The component 0..2 that `key` (lower case) names in one of the triples, or -1.
int componentOf(const std::string& key, std::initializer_list<NameTriple> triples) {
    for (const NameTriple& t : triples)
        for (int c = 0; c < 3; ++c)
            if (key == t[std::size_t(c)]) return c;
    return -1;
}

int positionComponent(const std::string& key) {
    return componentOf(key, {{"x", "y", "z"},
                             {"points:0", "points:1", "points:2"},
                             {"pos_x", "pos_y", "pos_z"},
                             {"position_x", "position_y", "position_z"}});
}

int velocityComponent(const std::string& key) {
    return componentOf(key, {{"vx", "vy", "vz"},
                             {"velocity:0", "velocity:1", "velocity:2"},
                             {"velocity_x", "velocity_y", "velocity_z"},
                             {"vel_x", "vel_y", "vel_z"}});
}

struct CsvLayout {
    std::vector<Column> columns;
    std::vector<Attribute> attributes;
};

std::size_t addAttribute(CsvLayout& layout, std::string attrName, AttributeType type, int components) {
    Attribute a;
    a.name = std::move(attrName);
    a.type = type;
    a.components = components;
    layout.attributes.push_back(std::move(a));
    return layout.attributes.size() - 1;
}

Result<CsvLayout> planCsvLayout(const std::vector<std::string>& names, const std::string& name) {
    // First pass: which column feeds each position / velocity component.
    int pos[3] = {-1, -1, -1}, vel[3] = {-1, -1, -1};
    int density = -1, id = -1;
    for (std::size_t i = 0; i < names.size(); ++i) {
        const std::string key = lower(names[i]);
        if (const int c = positionComponent(key); c >= 0 && pos[c] < 0) pos[c] = int(i);
        else if (const int v = velocityComponent(key); v >= 0 && vel[v] < 0) vel[v] = int(i);
        else if ((key == "density" || key == "rho") && density < 0) density = int(i);
        else if (key == "id" && id < 0) id = int(i);
    }
    for (int c = 0; c < 3; ++c)
        if (pos[c] < 0)
            return makeError(name, std::string("CSV header has no '") + "xyz"[c] + "' column (expected x,y,z or Points:0,Points:1,Points:2)");
    const bool hasVelocity = vel[0] >= 0 && vel[1] >= 0 && vel[2] >= 0;

    CsvLayout layout;
    layout.columns.resize(names.size());
    std::optional<std::size_t> velocityAttr;
    for (std::size_t i = 0; i < names.size(); ++i) {
        Column& col = layout.columns[i];
        col.name = names[i];
        const int ii = int(i);
        if (names[i].empty()) continue;  // Slot::Ignore
        col.slot = Slot::Attribute;
        if (ii == pos[0] || ii == pos[1] || ii == pos[2]) {
            col.slot = ii == pos[0] ? Slot::PosX : ii == pos[1] ? Slot::PosY : Slot::PosZ;
        } else if (hasVelocity && (ii == vel[0] || ii == vel[1] || ii == vel[2])) {
            if (!velocityAttr) velocityAttr = addAttribute(layout, std::string(kAttrVelocity), AttributeType::Float, 3);
            col.attribute = *velocityAttr;
            col.component = ii == vel[0] ? 0 : ii == vel[1] ? 1 : 2;
        } else if (ii == density) {
            col.attribute = addAttribute(layout, std::string(kAttrDensity), AttributeType::Float, 1);
        } else if (ii == id) {
            col.attribute = addAttribute(layout, std::string(kAttrId), AttributeType::Int, 1);
        } else {
            std::string attrName = names[i];
            if (attrName == kAttrVelocity || attrName == kAttrDensity || attrName == kAttrId) attrName += "_csv";
            for (const Attribute& a : layout.attributes)
                if (a.name == attrName) return makeError(name, "CSV header names column '" + attrName + "' twice");
            col.attribute = addAttribute(layout, attrName, AttributeType::Float, 1);
        }
    }
    return layout;
}

Status storeCsvRow(const std::vector<std::string>& fields, const std::vector<Column>& columns, std::size_t lineNo,
                   ParticleSet& set, const std::string& name) {
    glm::vec3 p(0.0f);
    const std::size_t row = set.positions.size();
    for (Attribute& a : set.attributes) {
        const std::size_t n = (row + 1) * std::size_t(a.components);
        if (a.type == AttributeType::Float) a.floats.resize(n, 0.0f);
        else a.ints.resize(n, 0);
    }
    for (std::size_t i = 0; i < columns.size(); ++i) {
        const Column& col = columns[i];
        if (col.slot == Slot::Ignore) continue;
        auto bad = [&](const char* what) {
            return makeError(name, "line " + std::to_string(lineNo) + ": " + quoteShort(fields[i]) + " in column '" +
                                       col.name + "' is not " + what);
        };
        if (col.slot == Slot::Attribute && set.attributes[col.attribute].type == AttributeType::Int) {
            std::int64_t v = 0;
            if (!parseInteger(fields[i], v)) return bad("an integer");
            set.attributes[col.attribute].ints[row] = v;
            continue;
        }
        double v = 0;
        if (!parseNumber(fields[i], v)) return bad("a number");
        switch (col.slot) {
            case Slot::PosX: p.x = float(v); break;
            case Slot::PosY: p.y = float(v); break;
            case Slot::PosZ: p.z = float(v); break;
            case Slot::Attribute: {
                Attribute& a = set.attributes[col.attribute];
                a.floats[row * std::size_t(a.components) + std::size_t(col.component)] = float(v);
                break;
            }
            case Slot::Ignore: break;
        }
    }
    set.positions.push_back(p);
    return okStatus();
}

Result<ParticleSet> parseCsvImpl(ByteView data, const std::string& name) {
    Lines lines(asText(data));
    std::string_view line;
    while (lines.next(line) && trim(line).empty()) {
    }
    if (trim(line).empty()) return makeError(name, "CSV file is empty (no header row)");

    const char delim = detectDelimiter(line);
    std::vector<std::string> fields;
    splitCsv(line, delim, fields);
    auto layout = planCsvLayout(fields, name);
    if (!layout) return layout.error();
    const std::size_t width = fields.size();

    ParticleSet set;
    set.attributes = std::move(layout->attributes);
    while (lines.next(line)) {
        if (trim(line).empty()) continue;
        splitCsv(line, delim, fields);
        if (fields.size() != width)
            return makeError(name, "line " + std::to_string(lines.number()) + ": expected " + std::to_string(width) +
                                       " fields as in the header, found " + std::to_string(fields.size()));
        Status s = storeCsvRow(fields, layout->columns, lines.number(), set, name);
        if (!s) return s.error();
    }
    return set;
}

// ---------------------------------------------------------------- XYZ

Result<ParticleSet> parseXyzImpl(ByteView data, const std::string& name) {
    if (trim(asText(data)).empty()) return makeError(name, "XYZ file is empty");
    Lines lines(asText(data));
    ParticleSet set;
    std::string_view line;
    std::vector<std::string_view> words;
    while (lines.next(line)) {
        line = line.substr(0, line.find('#'));
        words.clear();
        std::size_t i = 0;
        while (i < line.size() && words.size() < 3) {
            while (i < line.size() && (isSpace(line[i]) || line[i] == ',')) ++i;
            const std::size_t start = i;
            while (i < line.size() && !isSpace(line[i]) && line[i] != ',') ++i;
            if (i > start) words.push_back(line.substr(start, i - start));
        }
        if (words.empty()) continue;
        if (words.size() < 3)
            return makeError(name, "line " + std::to_string(lines.number()) + ": expected 3 coordinates (x y z), found " +
                                       std::to_string(words.size()));
        double v[3];
        for (int c = 0; c < 3; ++c)
            if (!parseNumber(words[std::size_t(c)], v[c]))
                return makeError(name, "line " + std::to_string(lines.number()) + ": " + quoteShort(words[std::size_t(c)]) +
                                           " is not a number");
        set.positions.emplace_back(float(v[0]), float(v[1]), float(v[2]));
    }
    return set;
}

}  // namespace

Result<ParticleSet> parseCsv(ByteView data, const std::string& name) {
    return io_util::guardParse(name, "CSV", [&] { return parseCsvImpl(data, name); });
}

Result<ParticleSet> parseXyz(ByteView data, const std::string& name) {
    return io_util::guardParse(name, "XYZ", [&] { return parseXyzImpl(data, name); });
}

}  // namespace meniscus
