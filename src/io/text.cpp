// Text particle readers: CSV with a header row, and plain XYZ.
//
// CSV follows RFC 4180 (https://www.rfc-editor.org/rfc/rfc4180) loosely: the
// header is the first non-blank line that names all three positions (lines
// before it are skipped; when no line among the first 64 does, the first
// non-blank line is the header, and the error names the missing column);
// fields are separated by ',' or, when the header uses them instead, ';' or
// tab; names may be double-quoted and are trimmed. Column names go through the
// alias table every reader shares (io/attribute_names.h): case-insensitive,
// a trailing unit in brackets ignored ("Pos.x [m]"):
//   x y z, Points:0 Points:1 Points:2 (ParaView's "Save Data" CSV), Pos.x
//   Pos.y Pos.z (DualSPHysics), pos_x ..., position_x ...   -> positions
//   vx vy vz, Velocity:0 ... (ParaView), Vel.x ... (DualSPHysics),
//   velocity_x ..., vel_x ..., u v w                        -> "velocity" (Float, 3)
//   density, rho, Rhop (DualSPHysics before v5.2, Rho after)    -> "density"
//   id, Idp (DualSPHysics)                                  -> "id" (Int)
// Every other named column is kept as a Float attribute under its name
// without the unit ("Press [Pa]" -> "Press", "Type" stays "Type"); columns with
// an empty name (a trailing separator) are ignored, and a row may have or lack
// the trailing separator whatever the header does. Blank lines are skipped; a
// row with the wrong number of fields or a non-numeric field is an error
// naming the line.
//
// DualSPHysics' particle CSV (PartCsv_XXXX.csv of `DualSPHysics -sv:csv`,
// PartVTK -savecsv) is written by JOutputCsv::SaveCsv (DualSPHysics
// src/source/JOutputCsv.cpp, LGPL): optional free "head" lines, then one
// header cell per scalar, a vector as NAME.x NAME.y NAME.z, each followed by
// its unit (JDataArrays::GetUnitsByName: " [m]", " [m/s]", " [kg/m^3]",
// " [Pa]", ...) and the separator (';', or ',' with -csvsep:1), the line
// ending in one; then the rows, floats as "%15.7E", integers as "%u", each
// value followed by the separator too. Its Type column holds 0 fixed, 1
// moving, 2 floating boundary, 3 fluid (see particles.h, DualSphysicsType).
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

#include "io/attribute_names.h"
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

struct CsvLayout {
    std::vector<Column> columns;
    std::vector<Attribute> attributes;
};

// The error for a header without a complete set of position columns: the
// first of x, y, z that no column names in any of the table's spellings.
Error missingPositionError(const std::vector<std::string>& names, const std::string& name) {
    bool have[3] = {false, false, false};
    for (const std::string& n : names)
        if (const int c = io_util::componentIn(io_util::positionColumns(), n); c >= 0) have[c] = true;
    for (int c = 0; c < 3; ++c)
        if (!have[c])
            return makeError(name, std::string("CSV header has no '") + "xyz"[c] +
                                       "' column (expected x,y,z, Points:0,Points:1,Points:2 or Pos.x,Pos.y,Pos.z)");
    return makeError(name, "CSV header has no complete set of position columns (x,y,z, Points:0,Points:1,Points:2 "
                           "or Pos.x,Pos.y,Pos.z, one spelling for all three)");
}

Result<CsvLayout> planCsvLayout(const std::vector<std::string>& names, const std::string& name) {
    // Which columns are positions, velocity, density and id: the alias table
    // shared by every reader (attribute_names.h).
    const io_util::ColumnRoles roles = io_util::findColumnRoles(names);
    if (!roles.hasPosition()) return missingPositionError(names, name);

    CsvLayout layout;
    layout.columns.resize(names.size());
    std::optional<std::size_t> velocityAttr;
    for (std::size_t i = 0; i < names.size(); ++i) {
        Column& col = layout.columns[i];
        col.name = names[i];
        const int ii = int(i);
        if (names[i].empty()) continue;  // Slot::Ignore (a trailing separator)
        col.slot = Slot::Attribute;
        const auto& pos = roles.position;
        const auto& vel = roles.velocity;
        if (ii == pos[0] || ii == pos[1] || ii == pos[2]) {
            col.slot = ii == pos[0] ? Slot::PosX : ii == pos[1] ? Slot::PosY : Slot::PosZ;
        } else if (roles.hasVelocity() && (ii == vel[0] || ii == vel[1] || ii == vel[2])) {
            if (!velocityAttr)
                velocityAttr =
                    io_util::appendAttribute(layout.attributes, std::string(kAttrVelocity), AttributeType::Float, 3);
            col.attribute = *velocityAttr;
            col.component = ii == vel[0] ? 0 : ii == vel[1] ? 1 : 2;
        } else if (ii == roles.density) {
            col.attribute =
                io_util::appendAttribute(layout.attributes, std::string(kAttrDensity), AttributeType::Float, 1);
        } else if (ii == roles.id) {
            col.attribute = io_util::appendAttribute(layout.attributes, std::string(kAttrId), AttributeType::Int, 1);
        } else {
            // Kept by its name without the unit ("Press [Pa]" -> "Press"), which
            // --select and the fluid index then use.
            std::string attrName = io_util::nonCanonicalName(std::string(io_util::withoutUnit(names[i])), "_csv");
            if (attrName.empty()) attrName = names[i];
            for (const Attribute& a : layout.attributes)
                if (a.name == attrName) return makeError(name, "CSV header names column '" + attrName + "' twice");
            col.attribute = io_util::appendAttribute(layout.attributes, attrName, AttributeType::Float, 1);
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

// Lines before the header that are looked through for it (see parseCsvImpl).
constexpr int kMaxPreambleLines = 64;

Result<ParticleSet> parseCsvImpl(ByteView data, const std::string& name) {
    // The header row: the first non-blank line whose columns name all three
    // positions, so that lines before it (DualSPHysics' JOutputCsv::SaveCsv
    // writes its optional "head" text there; a title; '#' comments) are
    // skipped. Without such a line among the first kMaxPreambleLines, the first
    // non-blank line is the header and its error names the missing column.
    Lines scan(asText(data));
    std::optional<Lines> afterHeader, afterFirst;
    std::string_view line, header, first;
    std::vector<std::string> fields;
    for (int seen = 0; seen < kMaxPreambleLines && scan.next(line);) {
        if (trim(line).empty()) continue;
        ++seen;
        if (!afterFirst) {
            first = line;
            afterFirst = scan;
        }
        splitCsv(line, detectDelimiter(line), fields);
        if (io_util::findColumnRoles(fields).hasPosition()) {
            header = line;
            afterHeader = scan;
            break;
        }
    }
    if (!afterFirst) return makeError(name, "CSV file is empty (no header row)");
    if (!afterHeader) {
        header = first;
        afterHeader = afterFirst;
    }
    Lines& lines = *afterHeader;

    const char delim = detectDelimiter(header);
    splitCsv(header, delim, fields);
    auto layout = planCsvLayout(fields, name);
    if (!layout) return layout.error();
    const std::size_t width = fields.size();
    const bool headerEndsInSeparator = layout->columns.back().slot == Slot::Ignore && fields.back().empty();

    ParticleSet set;
    set.attributes = std::move(layout->attributes);
    while (lines.next(line)) {
        if (trim(line).empty()) continue;
        splitCsv(line, delim, fields);
        // DualSPHysics ends the header and every row with a separator; one
        // without the other is accepted too.
        if (fields.size() == width + 1 && fields.back().empty()) fields.pop_back();
        else if (fields.size() + 1 == width && headerEndsInSeparator) fields.emplace_back();
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
