// numpy .npz particle files: what numpy.savez and savez_compressed write, a
// zip archive (read with libzip) of one .npy file per array, named
// "<key>.npy". The .npy format (numpy.lib.format; NEP 1): the magic
// "\x93NUMPY", a version byte pair (1.0: a uint16 header length; 2.0, 3.0: a
// uint32 one), then an ASCII (3.0: UTF-8) Python dict literal
// {'descr': '<f8', 'fortran_order': False, 'shape': (100,), } padded with
// spaces, then the elements. Read: integers and floats of 1, 2, 4 or 8 bytes
// ('<f4', '<f8', '<i4', '<i8', '<u4', '|b1', ...) in either byte order, C or
// Fortran order, 1-D (one value per particle) or 2-D (N x k: k components).
//
// Two layouts:
//  - PySPH's output (pysph.solver.utils.dump with a .npz name; NumpyOutput in
//    pysph/solver/output.py): savez(fname, version=2, particles=...,
//    solver_data=...), where `particles` is a dict, stored as a pickled 0-d
//    object array: {array name: {'arrays': {prop: ndarray}, 'properties':
//    {prop: {'name', 'type', 'default', 'stride', ...}}, 'constants': {...},
//    'output_property_arrays': [...]}}. The pickle is read by the restricted
//    reader of pickle.h (plain data and numpy arrays only; no code runs).
//    Version 1 files (an `arrays` member: {array name: {prop: ndarray}}) too.
//    The particle arrays and their properties are read as for PySPH's .hdf5
//    (pysph_hdf5.cpp): `out.npz/fluid` names one; the default is "fluid",
//    else the first with particles; an unstored position is its default.
//  - plain arrays: savez(f, x=..., y=..., z=..., u=..., rho=..., id=...), or
//    per body with keys "fluid/x", "boundary/x", ... (`out.npz/fluid` names
//    one; the default is the keys without a '/', else "fluid", else the
//    first body with positions). A (N, 3) array named position(s), pos or
//    points gives the positions when there are no x, y, z.
// Names go through the shared alias table (column_set.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>

#include "io/attribute_names.h"
#include "io/column_set.h"
#include "io/containers.h"
#include "io/io_util.h"
#include "meniscus/io.h"

#if MENISCUS_HAVE_LIBZIP
#include <zip.h>

#include "io/pickle.h"

namespace meniscus {

namespace {

using namespace io_util;
using pickle::Dtype;

constexpr std::uint64_t kMaxElements = std::uint64_t(1) << 40;
// deflate's largest ratio is about 1032:1 (see hdf5_util.cpp).
constexpr std::uint64_t kMaxCompressionRatio = 1100;
constexpr zip_int64_t kMaxEntries = 100000;
constexpr int kMaxComponents = 64;

// ---------------------------------------------------------------- .npy

struct Npy {
    Dtype dtype;
    std::vector<std::uint64_t> shape;
    bool fortran = false;
    ByteView data;  // the elements (or, for dtype 'O', the pickle)
};

// A reader of the header's dict literal: only what numpy writes (strings,
// True/False, tuples of integers) is understood; a list (a structured
// dtype's descr) makes the array unsupported.
class HeaderDict {
public:
    explicit HeaderDict(std::string_view text) : t_(text) {}

    void parse(std::string& descr, bool& descrIsList, bool& fortran, std::vector<std::uint64_t>& shape,
               bool& haveShape, bool& haveFortran) {
        expect('{');
        for (;;) {
            skip();
            if (peek() == '}') break;
            const std::string key = string();
            expect(':');
            skip();
            if (key == "descr") {
                if (peek() == '[') {
                    descrIsList = true;
                    skipBalanced();
                } else {
                    descr = string();
                }
            } else if (key == "fortran_order") {
                fortran = boolean();
                haveFortran = true;
            } else if (key == "shape") {
                shape = tuple();
                haveShape = true;
            } else {
                skipValue();
            }
            skip();
            if (peek() == ',') ++p_;
            else if (peek() != '}') fail("npy header is not a dict literal");
        }
    }

private:
    std::string_view t_;
    std::size_t p_ = 0;

    void skip() {
        while (p_ < t_.size() && (t_[p_] == ' ' || t_[p_] == '\t' || t_[p_] == '\n' || t_[p_] == '\r')) ++p_;
    }
    char peek() const { return p_ < t_.size() ? t_[p_] : '\0'; }
    void expect(char c) {
        skip();
        if (peek() != c) fail(std::string("npy header is not a dict literal (expected '") + c + "')");
        ++p_;
    }
    std::string string() {
        skip();
        const char q = peek();
        if (q != '\'' && q != '"') fail("npy header is not a dict literal (expected a quoted key or string)");
        const std::size_t end = t_.find(q, p_ + 1);
        if (end == std::string_view::npos) fail("npy header has an unterminated string");
        std::string s(t_.substr(p_ + 1, end - p_ - 1));
        p_ = end + 1;
        return s;
    }
    bool boolean() {
        if (t_.substr(p_, 4) == "True") {
            p_ += 4;
            return true;
        }
        if (t_.substr(p_, 5) == "False") {
            p_ += 5;
            return false;
        }
        fail("npy header's fortran_order is not True or False");
    }
    std::vector<std::uint64_t> tuple() {
        if (peek() != '(') fail("npy header's shape is not a tuple");
        ++p_;
        std::vector<std::uint64_t> dims;
        for (;;) {
            skip();
            if (peek() == ')') {
                ++p_;
                return dims;
            }
            std::uint64_t v = 0;
            int digits = 0;
            while (p_ < t_.size() && t_[p_] >= '0' && t_[p_] <= '9') {
                if (++digits > 15) fail("npy header's shape has a dimension too large");
                v = v * 10 + std::uint64_t(t_[p_++] - '0');
            }
            if (digits == 0) fail("npy header's shape is not a tuple of counts");
            if (peek() == 'L') ++p_;  // Python 2's long literal
            dims.push_back(v);
            if (dims.size() > 32) fail("npy header's shape has more than 32 dimensions");
            skip();
            if (peek() == ',') ++p_;
            else if (peek() != ')') fail("npy header's shape is not a tuple of counts");
        }
    }
    void skipBalanced() {
        int depth = 0;
        do {
            const char c = peek();
            if (c == '\0') fail("npy header is not a dict literal (unbalanced brackets)");
            if (c == '[' || c == '(' || c == '{') ++depth;
            if (c == ']' || c == ')' || c == '}') --depth;
            if (c == '\'' || c == '"') {
                string();
                continue;
            }
            ++p_;
        } while (depth > 0);
    }
    void skipValue() {
        const char c = peek();
        if (c == '\'' || c == '"') string();
        else if (c == '[' || c == '(' || c == '{') skipBalanced();
        else
            while (p_ < t_.size() && t_[p_] != ',' && t_[p_] != '}') ++p_;
    }
};

std::uint64_t elementCount(const std::vector<std::uint64_t>& shape) {
    std::uint64_t n = 1;
    for (std::uint64_t d : shape) {
        if (d > kMaxElements || (d > 0 && n > kMaxElements / d)) fail("declares more than 2^40 elements");
        n *= d;
    }
    return n;
}

Npy parseNpy(ByteView bytes, const std::string& what) {
    static constexpr std::uint8_t kMagic[] = {0x93, 'N', 'U', 'M', 'P', 'Y'};
    if (bytes.size() < 10 || !std::equal(std::begin(kMagic), std::end(kMagic), bytes.begin()))
        fail(what + " is not a .npy array (no \\x93NUMPY magic)");
    const int major = bytes[6];
    std::size_t headerStart = 10;
    std::uint64_t headerLength = 0;
    if (major == 1) {
        headerLength = std::uint64_t(bytes[8]) | std::uint64_t(bytes[9]) << 8;
    } else if (major == 2 || major == 3) {
        if (bytes.size() < 12) fail(what + ": the .npy header is truncated");
        headerLength = std::uint64_t(bytes[8]) | std::uint64_t(bytes[9]) << 8 | std::uint64_t(bytes[10]) << 16 |
                       std::uint64_t(bytes[11]) << 24;
        headerStart = 12;
    } else {
        fail(what + ": .npy format version " + std::to_string(major) + "." + std::to_string(bytes[7]) +
             " (1.0, 2.0 and 3.0 are read)");
    }
    if (headerLength > bytes.size() - headerStart) fail(what + ": the .npy header is truncated");
    const std::string_view header(reinterpret_cast<const char*>(bytes.data()) + headerStart, std::size_t(headerLength));

    std::string descr;
    bool descrIsList = false, haveShape = false, haveFortran = false;
    Npy npy;
    try {
        HeaderDict(header).parse(descr, descrIsList, npy.fortran, npy.shape, haveShape, haveFortran);
    } catch (const ParseFailure& f) {
        fail(what + ": " + f.message);
    }
    if (descrIsList) {
        npy.dtype.kind = 'V';  // a structured dtype: unsupported, reported by the caller
    } else if (descr.empty()) {
        fail(what + ": the .npy header has no 'descr'");
    } else if (!pickle::parseDtype(descr, npy.dtype)) {
        npy.dtype = Dtype{'?', 0, '|'};  // e.g. '<M8[ns]': not a number type we read
    }
    if (!haveShape || !haveFortran) fail(what + ": the .npy header lacks 'shape' or 'fortran_order'");
    npy.data = bytes.subspan(headerStart + std::size_t(headerLength));
    // The size check for the types that are read; others are skipped whole.
    if (std::string_view("fiub").find(npy.dtype.kind) != std::string_view::npos) {
        std::uint64_t count = 0;
        try {
            count = elementCount(npy.shape);
        } catch (const ParseFailure& f) {
            fail(what + ": the .npy header " + f.message);
        }
        const std::uint64_t bytesNeeded = count * std::uint64_t(npy.dtype.size);
        if (count > 0 && bytesNeeded / count != std::uint64_t(npy.dtype.size)) fail(what + ": the .npy header's size overflows");
        if (bytesNeeded != npy.data.size())
            fail(what + ": the .npy header declares " + std::to_string(count) + " elements (" +
                 std::to_string(bytesNeeded) + " bytes) but " + std::to_string(npy.data.size()) +
                 " bytes follow it; the file is damaged or truncated");
    }
    return npy;
}

// ---------------------------------------------------------------- arrays -> columns

// Why a numeric array cannot be a column ("" when it can).
std::string unsupportedWhy(const Dtype& d, const std::vector<std::uint64_t>& shape) {
    const bool intKind = (d.kind == 'i' || d.kind == 'u') && (d.size == 1 || d.size == 2 || d.size == 4 || d.size == 8);
    const bool floatKind = d.kind == 'f' && (d.size == 4 || d.size == 8);
    const bool boolKind = d.kind == 'b' && d.size == 1;
    if (!intKind && !floatKind && !boolKind) {
        if (d.kind == 'O') return "it holds Python objects";
        if (d.kind == 'V') return "it has a structured dtype";
        if (d.kind == '?') return "its dtype is not a number type meniscus reads (integers, float32, float64, bool)";
        return std::string("its dtype '") + d.kind + std::to_string(d.size) +
               "' is not a number type meniscus reads (integers, float32, float64, bool)";
    }
    if (shape.empty()) return "it is a single value, not one per particle";
    if (shape.size() > 2) return "it has " + std::to_string(shape.size()) + " dimensions";
    if (shape.size() == 2 && (shape[1] < 1 || shape[1] > std::uint64_t(kMaxComponents)))
        return "it has " + std::to_string(shape[1]) + " values per particle";
    return {};
}

// One array (its dtype, shape and element bytes, checked to match) as a column.
Column toColumn(const std::string& name, const Dtype& d, const std::vector<std::uint64_t>& shape, bool fortran,
                std::string_view raw) {
    Column c;
    c.name = name;
    const std::uint64_t rows = shape.empty() ? 1 : shape[0];
    const int k = shape.size() == 2 ? int(shape[1]) : 1;
    c.components = k;
    c.isInt = d.kind != 'f';
    const std::size_t n = std::size_t(rows) * std::size_t(k);
    if (c.isInt) c.ints.resize(n);
    else c.floats.resize(n);
    const bool swap = d.order == '>';
    for (std::size_t e = 0; e < n; ++e) {
        // Element e of the file; Fortran order stores (i, j) at j * rows + i.
        const std::size_t row = fortran ? e % std::size_t(rows) : e / std::size_t(k);
        const std::size_t col = fortran ? e / std::size_t(rows) : e % std::size_t(k);
        std::uint8_t b[8] = {};
        std::memcpy(b, raw.data() + e * std::size_t(d.size), std::size_t(d.size));
        if (swap) std::reverse(b, b + d.size);
        const std::size_t out = row * std::size_t(k) + col;
        if (d.kind == 'f') {
            if (d.size == 4) {
                float v;
                std::memcpy(&v, b, 4);
                c.floats[out] = v;
            } else {
                std::memcpy(&c.floats[out], b, 8);
            }
        } else {
            std::uint64_t u = 0;
            std::memcpy(&u, b, 8);
            if (d.kind == 'i' && d.size < 8 && (b[d.size - 1] & 0x80)) u |= ~std::uint64_t(0) << (8 * d.size);
            if (d.kind == 'u' && d.size == 8 && u > std::uint64_t(INT64_MAX)) u = std::uint64_t(INT64_MAX);
            c.ints[out] = std::int64_t(u);
        }
    }
    return c;
}

// ---------------------------------------------------------------- zip

struct ZipEntry {
    std::string key;  // the name without ".npy"
    zip_uint64_t index = 0;
};

class Zip {
public:
    Zip(ByteView data) : size_(data.size()) {
        zip_error_t error;
        zip_error_init(&error);
        zip_source_t* src = zip_source_buffer_create(data.data(), data.size(), 0, &error);
        if (src) {
            archive_ = zip_open_from_source(src, ZIP_RDONLY | ZIP_CHECKCONS, &error);
            if (!archive_) zip_source_free(src);
        }
        if (!archive_) {
            const std::string why = zip_error_strerror(&error);
            zip_error_fini(&error);
            fail("not a readable .npz (zip) archive: " + why);
        }
        zip_error_fini(&error);
        const zip_int64_t n = zip_get_num_entries(archive_, 0);
        if (n < 0 || n > kMaxEntries) fail(".npz archive lists " + std::to_string(n) + " members");
        for (zip_int64_t i = 0; i < n; ++i) {
            const char* name = zip_get_name(archive_, zip_uint64_t(i), ZIP_FL_ENC_RAW);
            if (!name) fail(".npz archive member " + std::to_string(i) + " has no name");
            std::string key = name;
            if (!endsWith(key, ".npy")) continue;  // savez names every member KEY.npy
            key.resize(key.size() - 4);
            entries_.push_back({std::move(key), zip_uint64_t(i)});
        }
    }
    ~Zip() {
        if (archive_) zip_discard(archive_);
    }
    Zip(const Zip&) = delete;
    Zip& operator=(const Zip&) = delete;

    const std::vector<ZipEntry>& entries() const { return entries_; }
    const ZipEntry* find(std::string_view key) const {
        for (const ZipEntry& e : entries_)
            if (e.key == key) return &e;
        return nullptr;
    }

    // The member's bytes, its declared size checked against what the archive
    // can hold before anything is allocated, and read in pieces so memory
    // follows the bytes that really come out.
    std::vector<std::uint8_t> read(const ZipEntry& entry) const {
        const std::string what = "member " + quoteShort(entry.key + ".npy");
        zip_stat_t st;
        zip_stat_init(&st);
        if (zip_stat_index(archive_, entry.index, 0, &st) != 0) fail(what + ": " + zip_strerror(archive_));
        if ((st.valid & ZIP_STAT_SIZE) == 0 || (st.valid & ZIP_STAT_COMP_SIZE) == 0)
            fail(what + " has no recorded size");
        if ((st.valid & ZIP_STAT_ENCRYPTION_METHOD) && st.encryption_method != ZIP_EM_NONE)
            fail(what + " is encrypted");
        if ((st.valid & ZIP_STAT_COMP_METHOD) && !zip_compression_method_supported(st.comp_method, 0))
            fail(what + " uses zip compression method " + std::to_string(st.comp_method) +
                 ", which this libzip cannot read (savez stores, savez_compressed deflates)");
        const bool stored = (st.valid & ZIP_STAT_COMP_METHOD) && st.comp_method == ZIP_CM_STORE;
        const std::uint64_t limit = stored ? st.comp_size : st.comp_size * kMaxCompressionRatio + 65536;
        if (st.comp_size > size_ || st.size > limit)
            fail(what + " declares " + std::to_string(st.size) + " bytes (" + std::to_string(st.comp_size) +
                 " compressed) in an archive of " + std::to_string(size_) + "; the file is damaged or truncated");
        zip_file_t* f = zip_fopen_index(archive_, entry.index, 0);
        if (!f) fail(what + ": " + zip_strerror(archive_));
        std::vector<std::uint8_t> out;
        out.reserve(std::size_t(std::min<std::uint64_t>(st.size, std::uint64_t(1) << 24)));
        std::uint8_t buffer[1 << 16];
        for (;;) {
            const zip_int64_t got = zip_fread(f, buffer, sizeof buffer);
            if (got < 0) {
                const std::string why = zip_error_strerror(zip_file_get_error(f));
                zip_fclose(f);
                fail(what + " cannot be read: " + why);
            }
            if (got == 0) break;
            if (out.size() + std::size_t(got) > st.size) {
                zip_fclose(f);
                fail(what + " holds more than the " + std::to_string(st.size) + " bytes it declares");
            }
            out.insert(out.end(), buffer, buffer + got);
        }
        zip_fclose(f);
        if (out.size() != st.size)
            fail(what + " holds " + std::to_string(out.size()) + " of the " + std::to_string(st.size) +
                 " bytes it declares; the file is damaged or truncated");
        return out;
    }

private:
    zip_t* archive_ = nullptr;
    std::size_t size_ = 0;
    std::vector<ZipEntry> entries_;
};

// ---------------------------------------------------------------- PySPH layout

struct PySphArray {
    std::string name;
    std::size_t info = pickle::Document::npos;  // its dict {'arrays': ..., 'properties': ...}
    std::size_t props = pickle::Document::npos; // {prop: ndarray}
    std::uint64_t count = 0;
};

// The particle arrays of a PySPH npz pickle, in the file's order.
std::vector<PySphArray> pysphArrays(const pickle::Document& doc, std::size_t particles, bool version1) {
    std::vector<PySphArray> out;
    const pickle::Value& dict = doc.at(particles);
    if (dict.kind != pickle::Kind::Dict) fail("PySPH .npz: 'particles' is not a dict of particle arrays");
    for (std::size_t k = 0; k + 1 < dict.items.size(); k += 2) {
        const pickle::Value& key = doc.at(dict.items[k]);
        if (key.kind != pickle::Kind::Str && key.kind != pickle::Kind::Bytes) continue;
        PySphArray a;
        a.name = key.s;
        a.info = doc.unwrap(dict.items[k + 1]);
        a.props = version1 ? a.info : doc.get(a.info, "arrays");
        if (a.props != pickle::Document::npos && doc.at(a.props).kind == pickle::Kind::Dict)
            for (const char* p : {"x", "y", "z"}) {
                const std::size_t v = doc.get(a.props, p);
                if (v != pickle::Document::npos && doc.at(v).kind == pickle::Kind::Array && doc.at(v).built &&
                    doc.at(v).shape.size() == 1)
                    a.count = std::max(a.count, doc.at(v).shape[0]);
            }
        else
            a.props = pickle::Document::npos;
        out.push_back(std::move(a));
    }
    return out;
}

// A number in the `properties` entry of a prop (stride, default).
double propertyNumber(const pickle::Document& doc, std::size_t info, const std::string& prop, std::string_view key,
                      double fallback) {
    const std::size_t properties = doc.get(info, "properties");
    const std::size_t entry = doc.get(properties, prop);
    const std::size_t v = doc.get(entry, key);
    if (v == pickle::Document::npos) return fallback;
    const pickle::Value& n = doc.at(v);
    if (n.kind == pickle::Kind::Int || n.kind == pickle::Kind::Bool) return double(n.i);
    if (n.kind == pickle::Kind::Float) return n.f;
    return fallback;
}

pickle::Document loadPickledMember(const Zip& zip, const ZipEntry& entry, std::vector<std::uint8_t>& bytes) {
    bytes = zip.read(entry);
    const std::string what = "member " + quoteShort(entry.key + ".npy");
    const Npy npy = parseNpy(bytes, what);
    if (npy.dtype.kind != 'O') fail("PySPH .npz: " + what + " is not a pickled object");
    try {
        return pickle::load(npy.data);
    } catch (const ParseFailure& f) {
        fail("PySPH .npz: " + what + ": " + f.message);
    }
}

ParticleSet readPySphNpz(const Zip& zip, const std::string& innerPath, const std::string& name,
                         std::vector<std::pair<std::string, std::uint64_t>>* listOnly) {
    const ZipEntry* member = zip.find("particles");
    const bool version1 = !member;
    if (!member) member = zip.find("arrays");
    std::vector<std::uint8_t> bytes;
    const pickle::Document doc = loadPickledMember(zip, *member, bytes);
    const std::size_t particles = doc.unwrap(doc.root());
    const std::vector<PySphArray> arrays = pysphArrays(doc, particles, version1);
    if (listOnly) {
        for (const PySphArray& a : arrays) listOnly->emplace_back(a.name, a.count);
        return {};
    }
    std::vector<std::string> arrayNames;
    for (const PySphArray& a : arrays) arrayNames.push_back(a.name);
    if (arrays.empty()) fail("PySPH .npz has no particle arrays");

    std::vector<std::string> warnings;
    std::string inner = innerPath;
    if (inner.rfind("particles/", 0) == 0) inner = inner.substr(10);
    const PySphArray* chosen = nullptr;
    auto named = [&](const std::string& n) {
        const auto it = std::find_if(arrays.begin(), arrays.end(), [&](const PySphArray& a) { return a.name == n; });
        return it == arrays.end() ? nullptr : &*it;
    };
    if (!inner.empty()) {
        chosen = named(inner);
        if (!chosen) fail("PySPH .npz has no particle array " + quoteShort(inner) + " (it has " + listNames(arrayNames) + ")");
    } else if ((chosen = named("fluid")) == nullptr) {
        std::vector<std::string> withParticles;
        for (const PySphArray& a : arrays)
            if (a.count > 0) {
                withParticles.push_back(quoteShort(a.name) + " (" + std::to_string(a.count) + ")");
                if (!chosen) chosen = &a;
            }
        if (!chosen) chosen = &arrays.front();
        if (withParticles.size() > 1)
            warnings.push_back(name + ": PySPH particle arrays " + joinNames(withParticles) + " and none named 'fluid': read " +
                               quoteShort(chosen->name) + " (name another as " + name + "/NAME)");
    }
    const std::string where = "particle array " + quoteShort(chosen->name) + ": ";
    if (chosen->props == pickle::Document::npos) fail(where + "no property arrays");
    const pickle::Value& props = doc.at(chosen->props);
    const std::uint64_t count = chosen->count;

    std::vector<Column> columns;
    bool anyPosition = false;
    for (std::size_t k = 0; k + 1 < props.items.size(); k += 2) {
        const pickle::Value& key = doc.at(props.items[k]);
        if (key.kind != pickle::Kind::Str && key.kind != pickle::Kind::Bytes) continue;
        const std::string& prop = key.s;
        const bool isPosition = prop == "x" || prop == "y" || prop == "z";
        const pickle::Value& a = doc.at(props.items[k + 1]);
        std::string why = a.kind != pickle::Kind::Array || !a.built ? "it is not a numpy array"
                                                                     : unsupportedWhy(a.dtype, a.shape);
        if (why.empty() && a.shape.size() != 1) why = "it is not one-dimensional";
        if (!why.empty()) {
            if (isPosition) fail(where + "property " + quoteShort(prop) + ": " + why);
            warnings.push_back(name + ": property " + quoteShort(prop) + " skipped: " + why);
            continue;
        }
        anyPosition = anyPosition || isPosition;
        const std::uint64_t length = a.shape[0];
        if (length == 0 && count > 0) continue;  // not stored
        const double strideValue = isPosition ? 1.0 : propertyNumber(doc, chosen->info, prop, "stride", 1.0);
        if (!(strideValue >= 1.0 && strideValue <= kMaxComponents && std::floor(strideValue) == strideValue))
            fail(where + "property " + quoteShort(prop) + " has a stride of " + std::to_string(strideValue));
        const int stride = int(strideValue);
        if (length != count * std::uint64_t(stride))
            fail(where + "property " + quoteShort(prop) + " has " + std::to_string(length) + " values for " +
                 std::to_string(count) + " particles" + (stride > 1 ? " of stride " + std::to_string(stride) : "") +
                 " (x, y, z have " + std::to_string(count) + ")");
        Column c = toColumn(prop, a.dtype, {count, std::uint64_t(stride)}, false, doc.arrayBytes(props.items[k + 1]));
        if (stride == 1) c.components = 1;
        columns.push_back(std::move(c));
    }
    if (!anyPosition) fail(where + "no property x, y or z");
    // Unstored positions (and velocity components, when another is stored)
    // are their defaults, as in pysph_hdf5.cpp.
    for (const auto& triple : {std::array<const char*, 3>{"x", "y", "z"}, std::array<const char*, 3>{"u", "v", "w"}}) {
        const auto stored = [&](const char* p) {
            return std::any_of(columns.begin(), columns.end(), [&](const Column& c) { return c.name == p; });
        };
        if (std::string_view(triple[0]) != "x" && !std::any_of(triple.begin(), triple.end(), stored)) continue;
        for (const char* p : triple) {
            if (stored(p)) continue;
            Column c;
            c.name = p;
            c.floats.assign(std::size_t(count), propertyNumber(doc, chosen->info, p, "default", 0.0));
            columns.push_back(std::move(c));
        }
    }
    ParticleSet set = particlesFromColumns(std::move(columns), std::size_t(count), where + "no positions");
    set.warnings = std::move(warnings);
    return set;
}

// ---------------------------------------------------------------- plain layout

// Members by body: "fluid/x" -> ("fluid", "x"); "x" -> ("", "x").
std::map<std::string, std::vector<const ZipEntry*>> bodies(const Zip& zip) {
    std::map<std::string, std::vector<const ZipEntry*>> out;
    for (const ZipEntry& e : zip.entries()) {
        const std::size_t slash = e.key.rfind('/');
        out[slash == std::string::npos ? std::string() : e.key.substr(0, slash)].push_back(&e);
    }
    return out;
}

std::string propName(const ZipEntry& e) {
    const std::size_t slash = e.key.rfind('/');
    return slash == std::string::npos ? e.key : e.key.substr(slash + 1);
}

bool namesPositions(const std::vector<const ZipEntry*>& members) {
    std::vector<std::string> names;
    for (const ZipEntry* e : members) names.push_back(propName(*e));
    if (findColumnRoles(names).hasPosition()) return true;
    for (const std::string& n : names) {
        const std::string key = attributeKey(n);
        if (key == "position" || key == "positions" || key == "pos" || key == "points") return true;
    }
    return false;
}

ParticleSet readPlainNpz(const Zip& zip, const std::string& inner, const std::string& name,
                         std::vector<std::pair<std::string, std::uint64_t>>* listOnly) {
    const auto groups = bodies(zip);
    if (groups.empty()) fail(".npz archive holds no .npy arrays");
    std::vector<std::string> groupNames;
    for (const auto& [g, members] : groups)
        if (!g.empty()) groupNames.push_back(g);
    if (listOnly) {
        for (const auto& [g, members] : groups)
            if (!g.empty() && namesPositions(members)) listOnly->emplace_back(g, 0);
        return {};
    }
    std::string chosen;
    if (!inner.empty()) {
        if (!groups.count(inner))
            fail(".npz has no arrays under " + quoteShort(inner + "/") + " (it has " +
                 (groupNames.empty() ? std::string("only top-level arrays") : listNames(groupNames)) + ")");
        chosen = inner;
    } else if (groups.count("") && namesPositions(groups.at(""))) {
        chosen = "";
    } else if (groups.count("fluid")) {
        chosen = "fluid";
    } else {
        const auto it = std::find_if(groups.begin(), groups.end(), [](const auto& g) { return namesPositions(g.second); });
        chosen = it != groups.end() ? it->first : groups.begin()->first;
    }
    const std::string where = chosen.empty() ? std::string() : "arrays " + quoteShort(chosen + "/") + ": ";

    std::vector<std::string> warnings;
    std::vector<Column> columns;
    std::vector<std::string> names;
    std::uint64_t count = 0;
    std::string countFrom;
    for (const ZipEntry* e : groups.at(chosen)) {
        const std::string prop = propName(*e);
        names.push_back(prop);
        const std::vector<std::uint8_t> bytes = zip.read(*e);
        const std::string what = "member " + quoteShort(e->key + ".npy");
        const Npy npy = parseNpy(bytes, what);
        const std::string why = unsupportedWhy(npy.dtype, npy.shape);
        if (!why.empty()) {
            warnings.push_back(name + ": " + what + " skipped: " + why);
            continue;
        }
        if (countFrom.empty()) {
            count = npy.shape[0];
            countFrom = prop;
        } else if (npy.shape[0] != count) {
            fail(where + "array " + quoteShort(prop) + " has " + std::to_string(npy.shape[0]) + " rows but " +
                 quoteShort(countFrom) + " has " + std::to_string(count) + " (every array holds one row per particle)");
        }
        columns.push_back(toColumn(prop, npy.dtype, npy.shape, npy.fortran,
                                   std::string_view(reinterpret_cast<const char*>(npy.data.data()), npy.data.size())));
    }
    ParticleSet set = particlesFromColumns(std::move(columns), std::size_t(count),
                                           where + "no position arrays (x, y, z, or an N x 3 'position'); it has: " +
                                               listNames(names));
    set.warnings = std::move(warnings);
    return set;
}

ParticleSet readNpz(ByteView data, const std::string& inner, const std::string& name,
                    std::vector<std::pair<std::string, std::uint64_t>>* listOnly = nullptr) {
    const Zip zip(data);
    // PySPH writes `particles` (version 2) or `arrays` (version 1) beside `version`.
    if (zip.find("particles") || (zip.find("arrays") && zip.find("version")))
        return readPySphNpz(zip, inner, name, listOnly);
    return readPlainNpz(zip, inner, name, listOnly);
}

}  // namespace

Result<ParticleSet> parseNpz(ByteView data, const std::string& name, const std::string& inner) {
    return guardParse(name, "npz", [&]() -> Result<ParticleSet> { return readNpz(data, inner, name); });
}

Result<std::vector<ParticleArrayInfo>> io_util::listNpzParticleArrays(const std::filesystem::path& path) {
    const std::string name = path.string();
    auto bytes = readFileChecked(path, kMaxParticleFileBytes,
                                 [&](ByteView head) { return checkParticleHead(head, name, ParticleFormat::Npz); });
    if (!bytes) return bytes.error();
    try {
        std::vector<std::pair<std::string, std::uint64_t>> list;
        readNpz(*bytes, "", name, &list);
        std::vector<ParticleArrayInfo> out;
        for (auto& [n, count] : list) out.push_back({n, std::size_t(count)});
        return out;
    } catch (const ParseFailure& f) {
        return makeError(name, f.message);
    } catch (const std::exception& e) {
        return makeError(name, std::string("cannot read npz data: ") + e.what());
    }
}

}  // namespace meniscus

#else  // !MENISCUS_HAVE_LIBZIP

namespace meniscus {

namespace {
const char* const kNoLibzip = "built without libzip, so .npz files cannot be read (install libzip-dev and rebuild)";
}

Result<ParticleSet> parseNpz(ByteView, const std::string& name, const std::string&) { return makeError(name, kNoLibzip); }

Result<std::vector<ParticleArrayInfo>> io_util::listNpzParticleArrays(const std::filesystem::path& path) {
    return makeError(path.string(), kNoLibzip);
}

}  // namespace meniscus

#endif  // MENISCUS_HAVE_LIBZIP
