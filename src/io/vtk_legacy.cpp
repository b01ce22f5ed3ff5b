// Legacy VTK reader ("# vtk DataFile Version x.y", versions 1.0 to 5.1), after
// the "VTK File Formats" document (Kitware, VTK User's Guide / docs.vtk.org)
// and VTK's own vtkDataReader:
//   line 1 magic + version, line 2 title, line 3 ASCII or BINARY (big-endian),
//   DATASET POLYDATA | UNSTRUCTURED_GRID | STRUCTURED_GRID, then sections:
//   POINTS n type; VERTICES/LINES/POLYGONS/TRIANGLE_STRIPS/CELLS a b (legacy:
//   b int32 values; 5.x: "OFFSETS type" a values + "CONNECTIVITY type" b values);
//   CELL_TYPES n; DIMENSIONS; FIELD; POINT_DATA n / CELL_DATA n followed by
//   SCALARS, VECTORS, NORMALS, TENSORS[6], TEXTURE_COORDINATES, GLOBAL_IDS,
//   PEDIGREE_IDS, EDGE_FLAGS, COLOR_SCALARS, LOOKUP_TABLE and FIELD arrays.
// Any array may be followed by a METADATA block that ends at an empty line.
// In BINARY files the data starts after the end of its header line; the newline
// VTK writes after each block is optional here. Point data is kept by name
// (integer types -> Int, float/double -> Float); cell data is read and dropped.
// "long"/"unsigned_long" are 8 bytes (as VTK writes them on LP64 systems);
// "vtkIdType" is 4 bytes (VTK writes it as int). bit and string arrays are rejected.
#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cstring>
#include <iterator>
#include <new>

#include "io/attribute_names.h"
#include "io/io_util.h"
#include "meniscus/io.h"

namespace meniscus {

namespace {

// Internal failure, turned into an Error at the parse entry; never escapes.
using io_util::fail;

struct TypeInfo {
    std::string_view name;  // lower case, as in the file
    int bytes;
    bool isInt;
    bool isSigned;
};

constexpr TypeInfo kTypes[] = {
    {"unsigned_char", 1, true, false}, {"char", 1, true, true},          {"signed_char", 1, true, true},
    {"unsigned_short", 2, true, false}, {"short", 2, true, true},         {"unsigned_int", 4, true, false},
    {"int", 4, true, true},             {"unsigned_long", 8, true, false}, {"long", 8, true, true},
    {"vtktypeint64", 8, true, true},    {"vtktypeuint64", 8, true, false}, {"vtkidtype", 4, true, true},
    {"float", 4, false, true},          {"double", 8, false, true},
};

// Words that start a section; seeing one where a value was expected means the
// array before it is short.
constexpr std::string_view kKeywords[] = {
    "points",      "vertices",       "lines",     "polygons",     "triangle_strips", "cells",
    "cell_types",  "point_data",     "cell_data", "scalars",      "vectors",         "normals",
    "tensors",     "tensors6",       "field",     "lookup_table", "color_scalars",   "texture_coordinates",
    "global_ids",  "pedigree_ids",   "edge_flags", "metadata",    "offsets",         "connectivity",
    "dimensions",  "dataset",
};

using io_util::lower;

std::string upper(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = char(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

// A token quoted for an error message: at most 40 characters, non-printables as '?'.
std::string shown(std::string_view s) {
    std::string out = "'";
    for (std::size_t i = 0; i < s.size() && i < 40; ++i)
        out += std::isprint(static_cast<unsigned char>(s[i])) ? s[i] : '?';
    if (s.size() > 40) out += "...";
    return out + "'";
}

bool isKeyword(std::string_view token) {
    const std::string t = lower(token);
    return std::find(std::begin(kKeywords), std::end(kKeywords), t) != std::end(kKeywords);
}

// VTK encodes special characters in names as %XX.
std::string decodeName(std::string_view s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        unsigned value = 0;
        if (s[i] == '%' && i + 2 < s.size() &&
            std::from_chars(s.data() + i + 1, s.data() + i + 3, value, 16).ptr == s.data() + i + 3) {
            out += char(value);
            i += 2;
        } else {
            out += s[i];
        }
    }
    return out;
}

// True when every byte could belong to ASCII numbers separated by whitespace.
bool looksLikeAsciiNumbers(const std::uint8_t* p, std::size_t n) {
    if (n == 0) return false;
    for (std::size_t i = 0; i < n; ++i) {
        const char c = char(p[i]);
        if (!(std::isdigit(static_cast<unsigned char>(c)) || (c != '\0' && std::strchr(" \t\r\n+-.eE", c))))
            return false;
    }
    return true;
}

// Values of one array: Float or Int, `components` per tuple.
struct Array {
    bool isInt = false;
    int components = 1;
    std::vector<float> floats;
    std::vector<std::int64_t> ints;
};

class Parser {
public:
    explicit Parser(ByteView data) : d_(data) {}

    ParticleSet run() {
        try {
            readHeader();
            readDataset();
            while (!atEnd()) readSection();
            if (!havePoints_) fail("no POINTS section: the file holds no particle positions");
        } catch (io_util::ParseFailure& f) {
            if (!asciiSuspect_.empty() && f.message.find("BINARY") == std::string::npos)
                f.message += " (the data of " + asciiSuspect_ + " looks like ASCII text although the header says BINARY)";
            throw;
        }
        applyCanonicalNames();
        return std::move(set_);
    }

private:
    enum class Section { None, Point, Cell };

    ByteView d_;
    std::size_t pos_ = 0;
    bool binary_ = false;
    int major_ = 0, minor_ = 0;
    ParticleSet set_;
    bool havePoints_ = false;
    std::size_t nPoints_ = 0;
    Section section_ = Section::None;
    std::size_t sectionCount_ = 0;
    std::string asciiSuspect_;  // a BINARY block that starts like ASCII numbers

    // ------------------------------------------------------------ lexing

    static bool isSpace(std::uint8_t c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }
    std::size_t remaining() const { return d_.size() - pos_; }

    void skipSpace() {
        while (pos_ < d_.size() && isSpace(d_[pos_])) ++pos_;
    }
    bool atEnd() {
        skipSpace();
        return pos_ >= d_.size();
    }
    // Next whitespace-delimited token; empty at end of data.
    std::string_view nextToken() {
        skipSpace();
        const std::size_t start = pos_;
        while (pos_ < d_.size() && !isSpace(d_[pos_])) ++pos_;
        return {reinterpret_cast<const char*>(d_.data()) + start, pos_ - start};
    }
    std::string_view token(const std::string& what) {
        const std::string_view t = nextToken();
        if (t.empty()) fail("truncated: file ends where " + what + " was expected");
        return t;
    }
    std::string_view peekToken() {
        const std::size_t saved = pos_;
        const std::string_view t = nextToken();
        pos_ = saved;
        return t;
    }
    bool peekIs(std::string_view keyword) { return lower(peekToken()) == keyword; }
    void expect(std::string_view keyword, const std::string& context) {
        const std::string_view t = token(upper(keyword) + " " + context);
        if (lower(t) != keyword) fail("expected " + upper(keyword) + " " + context + ", found " + shown(t));
    }
    // The rest of the current line (without '\r'); consumes the newline.
    std::string_view line() {
        const std::size_t start = pos_;
        while (pos_ < d_.size() && d_[pos_] != '\n') ++pos_;
        std::size_t end = pos_;
        if (pos_ < d_.size()) ++pos_;
        if (end > start && d_[end - 1] == '\r') --end;
        return {reinterpret_cast<const char*>(d_.data()) + start, end - start};
    }
    // A count: a non-negative integer token.
    std::size_t count(const std::string& what) {
        const std::string_view t = token(what);
        std::uint64_t v = 0;
        const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
        if (r.ec != std::errc() || r.ptr != t.data() + t.size())
            fail("bad " + what + ": expected a non-negative integer, found " + shown(t));
        return std::size_t(v);
    }
    std::string name(const std::string& what) { return decodeName(token(what)); }

    // ------------------------------------------------------------ header

    void readHeader() {
        static constexpr std::string_view magic = "# vtk DataFile Version";
        const std::size_t n = std::min(d_.size(), magic.size());
        if (n > 0 && std::memcmp(d_.data(), magic.data(), n) != 0)
            fail("bad magic: not a legacy VTK file (expected '# vtk DataFile Version' on line 1)");
        if (d_.size() <= magic.size()) fail("truncated header: the file ends inside the '# vtk DataFile Version' line");
        const std::string_view first = line();
        const std::string_view ver = first.substr(magic.size());
        const std::size_t b = ver.find_first_not_of(" \t");
        const char* p = b == std::string_view::npos ? ver.data() + ver.size() : ver.data() + b;
        const char* end = ver.data() + ver.size();
        auto r = std::from_chars(p, end, major_);
        if (r.ec == std::errc() && r.ptr < end && *r.ptr == '.') r = std::from_chars(r.ptr + 1, end, minor_);
        if (r.ec != std::errc()) fail("bad header: cannot read the version in " + shown(first));
        if (major_ < 1 || major_ > 5)
            fail("unsupported VTK file version " + std::to_string(major_) + "." + std::to_string(minor_) +
                 " (legacy versions 1.0 to 5.1 are supported)");
        if (pos_ >= d_.size()) fail("truncated header: the title line (line 2) is missing");
        line();  // title
        const std::string mode = lower(token("ASCII or BINARY (line 3)"));
        if (mode == "ascii")
            binary_ = false;
        else if (mode == "binary")
            binary_ = true;
        else
            fail("bad header: line 3 must be ASCII or BINARY, found " + shown(mode));
    }

    void readDataset() {
        const std::string_view kw = token("DATASET");
        if (lower(kw) != "dataset") fail("expected DATASET after the header, found " + shown(kw));
        const std::string type = lower(token("the dataset type"));
        if (type == "polydata" || type == "unstructured_grid" || type == "structured_grid") return;
        if (type == "structured_points" || type == "rectilinear_grid")
            fail("unsupported dataset " + shown(type) +
                 ": only POLYDATA, UNSTRUCTURED_GRID and STRUCTURED_GRID list point positions");
        fail("unsupported dataset type " + shown(type));
    }

    // ------------------------------------------------------------ sections

    void readSection() {
        const std::string_view raw = token("a section keyword");
        const std::string kw = lower(raw);
        if (kw == "points") return readPoints();
        if (kw == "vertices" || kw == "lines" || kw == "polygons" || kw == "triangle_strips" || kw == "cells")
            return skipCells(kw);
        if (kw == "cell_types") return skipCellTypes();
        if (kw == "dimensions") {
            for (int i = 0; i < 3; ++i) count("DIMENSIONS value");
            return;
        }
        if (kw == "point_data") return startPointData();
        if (kw == "cell_data") {
            section_ = Section::Cell;
            sectionCount_ = count("CELL_DATA count");
            return;
        }
        if (kw == "metadata") return skipMetadataBody();
        if (kw == "field") return readField(section_);
        if (kw == "scalars" || kw == "vectors" || kw == "normals" || kw == "tensors" || kw == "tensors6" ||
            kw == "texture_coordinates" || kw == "global_ids" || kw == "pedigree_ids" || kw == "edge_flags" ||
            kw == "color_scalars" || kw == "lookup_table") {
            if (section_ == Section::None) fail(std::string(raw) + " appears before POINT_DATA or CELL_DATA");
            return readAttribute(kw);
        }
        if (std::any_of(raw.begin(), raw.end(), [](char c) { return !std::isprint(static_cast<unsigned char>(c)); }))
            fail("unexpected binary data where a section keyword was expected (an array is longer than declared, "
                 "or the file is corrupt)");
        fail("unexpected " + shown(raw) + " where a section keyword was expected");
    }

    void readPoints() {
        if (havePoints_) fail("more than one POINTS section");
        const std::size_t n = count("POINTS count");
        const std::string type = lower(token("the POINTS data type"));
        const Array a = readArray(type, n, 3, "POINTS", true);
        set_.positions.resize(n);
        for (std::size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k)
                set_.positions[i][k] = a.isInt ? float(a.ints[3 * i + std::size_t(k)]) : a.floats[3 * i + std::size_t(k)];
        nPoints_ = n;
        havePoints_ = true;
    }

    // VERTICES/LINES/POLYGONS/TRIANGLE_STRIPS/CELLS: topology is not needed.
    void skipCells(const std::string& kw) {
        const std::string label = upper(kw);
        const std::size_t a = count(label + " count");
        const std::size_t b = count(label + " size");
        if (peekIs("offsets")) {  // VTK 5.x: offsets + connectivity arrays
            expect("offsets", "after " + label);
            readArray(lower(token("the OFFSETS data type")), a, 1, label + " OFFSETS", false);
            expect("connectivity", "after " + label + " OFFSETS");
            readArray(lower(token("the CONNECTIVITY data type")), b, 1, label + " CONNECTIVITY", false);
        } else if (major_ >= 5) {
            if (a > 0) fail("expected OFFSETS after " + label + " in a version 5 file, found " + shown(peekToken()));
        } else {
            readArray("int", b, 1, label, false);  // legacy: n, id, id, ... per cell
        }
    }

    void skipCellTypes() {
        const std::size_t n = count("CELL_TYPES count");
        readArray("int", n, 1, "CELL_TYPES", false);
    }

    void startPointData() {
        const std::size_t n = count("POINT_DATA count");
        if (!havePoints_) fail("POINT_DATA appears before POINTS");
        if (n != nPoints_)
            fail("count mismatch: POINT_DATA has " + std::to_string(n) + " values but POINTS has " +
                 std::to_string(nPoints_) + " points");
        section_ = Section::Point;
        sectionCount_ = n;
    }

    // FIELD name k, then k arrays "name ncomp ntuples type". At dataset level
    // (section None) tuple counts are free and the arrays are dropped.
    void readField(Section section) {
        token("the FIELD name");
        const std::size_t k = count("FIELD array count");
        for (std::size_t i = 0; i < k; ++i) {
            const std::string_view rawName = token("a FIELD array name");
            if (rawName == "NULL_ARRAY") continue;
            const std::string arrName = decodeName(rawName);
            const std::string what = "FIELD array '" + arrName + "'";
            const std::size_t nComp = count(what + " component count");
            const std::size_t nTuples = count(what + " tuple count");
            const std::string type = lower(token(what + " data type"));
            if (nComp < 1) fail(what + " has 0 components");
            if (section != Section::None && nTuples != sectionCount_)
                fail("count mismatch: " + what + " has " + std::to_string(nTuples) + " tuples but " +
                     (section == Section::Point ? "POINT_DATA" : "CELL_DATA") + " has " +
                     std::to_string(sectionCount_));
            const bool keep = section == Section::Point;
            Array a = readArray(type, nTuples, nComp, what, keep);
            if (keep) addAttribute(arrName, std::move(a));
        }
    }

    // SCALARS, VECTORS, ... in the current POINT_DATA or CELL_DATA section.
    void readAttribute(const std::string& kw) {
        const bool keep = section_ == Section::Point;
        const std::size_t n = sectionCount_;
        if (kw == "lookup_table") {  // a colour table: 4 values per entry
            token("the LOOKUP_TABLE name");
            const std::size_t size = count("LOOKUP_TABLE size");
            readArray(binary_ ? "unsigned_char" : "float", size, 4, "LOOKUP_TABLE", false);
            return;
        }
        const std::string attrName = name(upper(kw) + " name");
        const std::string what = upper(kw) + " '" + attrName + "'";
        std::size_t nComp = 1;
        std::string type;
        if (kw == "color_scalars") {
            nComp = count(what + " component count");
            type = binary_ ? "unsigned_char" : "float";
        } else if (kw == "texture_coordinates") {
            nComp = count(what + " dimension");
            if (nComp < 1 || nComp > 3) fail(what + " has dimension " + std::to_string(nComp) + " (1 to 3 allowed)");
            type = lower(token(what + " data type"));
        } else {
            type = lower(token(what + " data type"));
            if (kw == "vectors" || kw == "normals") nComp = 3;
            if (kw == "tensors") nComp = 9;
            if (kw == "tensors6") nComp = 6;
        }
        if (kw == "scalars") {
            const std::string_view next = peekToken();
            if (!next.empty() && std::isdigit(static_cast<unsigned char>(next[0]))) nComp = count(what + " component count");
            if (nComp < 1) fail(what + " has 0 components");
            if (peekIs("lookup_table")) {
                nextToken();
                token("the LOOKUP_TABLE name");
            }
        }
        Array a = readArray(type, n, nComp, what, keep);
        if (kw == "color_scalars" && binary_ && keep) {  // bytes 0..255 -> floats 0..1, as in ASCII files
            a.isInt = false;
            a.floats.reserve(a.ints.size());
            for (std::int64_t v : a.ints) a.floats.push_back(float(v) / 255.0f);
            a.ints.clear();
        }
        if (keep) addAttribute(attrName, std::move(a));
    }

    // ------------------------------------------------------------ arrays

    static const TypeInfo& typeInfo(const std::string& type, const std::string& what) {
        for (const TypeInfo& t : kTypes)
            if (t.name == type) return t;
        if (type == "bit") fail(what + " has type 'bit', which is not supported");
        if (type == "string" || type == "utf8_string" || type == "variant")
            fail(what + " has type " + shown(type) + "; string arrays are not supported");
        fail(what + " has unknown data type " + shown(type));
    }

    // Reads nTuples x nComp values of `type`; stores them only when `keep`.
    Array readArray(const std::string& type, std::size_t nTuples, std::size_t nComp, const std::string& what,
                    bool keep) {
        const TypeInfo& t = typeInfo(type, what);
        std::size_t total = 0;
        if (__builtin_mul_overflow(nTuples, nComp, &total) || total > d_.size())
            fail("truncated: " + what + " declares " + std::to_string(nTuples) + " x " + std::to_string(nComp) +
                 " values, more than the file's " + std::to_string(d_.size()) + " bytes can hold");
        Array a;
        a.isInt = t.isInt;
        a.components = int(nComp);
        if (binary_)
            readBinary(t, total, what, keep, a);
        else
            readAscii(t, total, what, keep, a);
        skipTrailingMetadata();
        return a;
    }

    void readBinary(const TypeInfo& t, std::size_t total, const std::string& what, bool keep, Array& a) {
        if (total == 0) return;
        // The data starts after the end of the header line.
        while (pos_ < d_.size() && d_[pos_] != '\n') ++pos_;
        if (pos_ >= d_.size()) fail("truncated: " + what + " has no data after its header line");
        ++pos_;
        const std::size_t bytes = total * std::size_t(t.bytes);
        const std::uint8_t* p = d_.data() + pos_;
        // Numbers written as text where BINARY was declared. Binary multi-byte
        // values practically never consist of digits, signs, dots and spaces
        // only: if all we look at is such text, fail now; if the block merely
        // starts with it, remember it to explain any later failure.
        const std::size_t probe = std::min<std::size_t>({bytes, remaining(), 64});
        std::size_t run = 0;
        while (run < probe && looksLikeAsciiNumbers(p + run, 1)) ++run;
        if (t.bytes >= 2 && run >= 8 && std::any_of(p, p + run, [](std::uint8_t c) { return std::isdigit(c); }) &&
            std::any_of(p, p + run, [](std::uint8_t c) { return isSpace(c); })) {
            if (run == probe) fail(what + ": the data looks like ASCII text although the header says BINARY");
            if (asciiSuspect_.empty()) asciiSuspect_ = what;
        }
        if (bytes > remaining()) {
            std::string msg = "truncated: " + what + " needs " + std::to_string(bytes) +
                              " bytes of binary data, only " + std::to_string(remaining()) + " remain";
            if (looksLikeAsciiNumbers(p, remaining()))
                msg += " (the data looks like ASCII text although the header says BINARY)";
            fail(msg);
        }
        pos_ += bytes;
        if (!keep) return;
        if (t.isInt)
            a.ints.resize(total);
        else
            a.floats.resize(total);
        for (std::size_t i = 0; i < total; ++i, p += t.bytes) {
            std::uint64_t u = 0;
            for (int k = 0; k < t.bytes; ++k) u = (u << 8) | p[k];
            if (t.isInt) {
                if (t.isSigned && t.bytes < 8 && (u >> (8 * t.bytes - 1)) != 0) u |= ~std::uint64_t(0) << (8 * t.bytes);
                a.ints[i] = std::int64_t(u);
            } else if (t.bytes == 4) {
                a.floats[i] = std::bit_cast<float>(std::uint32_t(u));
            } else {
                a.floats[i] = float(std::bit_cast<double>(u));
            }
        }
    }

    void readAscii(const TypeInfo& t, std::size_t total, const std::string& what, bool keep, Array& a) {
        if (keep) {
            if (t.isInt)
                a.ints.reserve(total);
            else
                a.floats.reserve(total);
        }
        for (std::size_t i = 0; i < total; ++i) {
            const std::string_view tok = nextToken();
            if (tok.empty())
                fail("truncated: " + what + " has only " + std::to_string(i) + " of " + std::to_string(total) +
                     " values before the end of the file");
            std::string_view s = tok;
            if (s.size() > 1 && s[0] == '+') s.remove_prefix(1);
            const char* b = s.data();
            const char* e = s.data() + s.size();
            bool ok = false;
            if (t.isInt) {
                std::int64_t v = 0;
                auto r = std::from_chars(b, e, v);
                if (r.ec == std::errc() && r.ptr == e) {
                    ok = true;
                } else if (!t.isSigned) {
                    std::uint64_t u = 0;
                    r = std::from_chars(b, e, u);
                    ok = r.ec == std::errc() && r.ptr == e;
                    v = std::int64_t(u);
                }
                if (ok && keep) a.ints.push_back(v);
            } else if (t.bytes == 4) {
                float v = 0;
                const auto r = std::from_chars(b, e, v);
                ok = r.ec == std::errc() && r.ptr == e;
                if (ok && keep) a.floats.push_back(v);
            } else {
                double v = 0;
                const auto r = std::from_chars(b, e, v);
                ok = r.ec == std::errc() && r.ptr == e;
                if (ok && keep) a.floats.push_back(float(v));
            }
            if (!ok) {
                if (isKeyword(tok))
                    fail("truncated: " + what + " has only " + std::to_string(i) + " of " + std::to_string(total) +
                         " values before " + shown(tok));
                fail("non-numeric value " + shown(tok) + " in " + what + " (value " + std::to_string(i + 1) +
                     " of " + std::to_string(total) + ")");
            }
        }
    }

    // After an array, VTK 5 may write "METADATA" lines ended by an empty line.
    void skipTrailingMetadata() {
        const std::size_t saved = pos_;
        // Only blank lines may stand between an array and its METADATA.
        while (pos_ < d_.size() && isSpace(d_[pos_])) ++pos_;
        if (lower(peekToken()) != "metadata") {
            pos_ = saved;
            return;
        }
        nextToken();
        skipMetadataBody();
    }
    void skipMetadataBody() {
        line();  // rest of the METADATA line
        while (pos_ < d_.size()) {
            const std::string_view l = line();
            if (l.find_first_not_of(" \t\r") == std::string_view::npos) break;
        }
    }

    // ------------------------------------------------------------ results

    void addAttribute(const std::string& attrName, Array&& a) {
        Attribute attr;
        attr.name = attrName;
        attr.components = a.components;
        attr.type = a.isInt ? AttributeType::Int : AttributeType::Float;
        attr.floats = std::move(a.floats);
        attr.ints = std::move(a.ints);
        set_.attributes.push_back(std::move(attr));
    }

    // Vel/velocity/v -> velocity, Rhop/rho/density -> density, Idp/id -> id
    // (any case; DualSPHysics' PartVTK names its arrays Vel, Rhop or Rho, Idp),
    // through the alias table every reader shares (io/attribute_names.h), when
    // the type fits and the canonical name is free.
    void applyCanonicalNames() { io_util::applyCanonicalNames(set_.attributes); }
};

}  // namespace

Result<ParticleSet> parseVtkLegacy(ByteView data, const std::string& name) {
    return io_util::guardParse(name, "VTK", [&] { return Parser(data).run(); });
}

}  // namespace meniscus
