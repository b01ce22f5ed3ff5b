// Triangle-mesh readers (the simulator's mesh colliders): Wavefront OBJ and
// PLY (ASCII and both binary byte orders), into a TriangleMesh.
//
// OBJ (Wavefront "Object Files (.obj)", Advanced Visualizer manual, appendix
// B1): one statement per line, '#' starts a comment.
//   v x y z [w]         a vertex (w, and colours some writers append, ignored)
//   vn x y z            a normal
//   f a b c ...         a polygon; each corner v, v/t, v//n or v/t/n; indices
//                       count from 1, negative ones back from the last vertex
//                       (or normal) defined so far
// Polygons are split into triangles as a fan from their first corner. Every
// other statement (vt, o, g, s, usemtl, mtllib, l, p, ...) is skipped.
// Normals are kept when the file has one per vertex and every corner uses the
// normal of its vertex's number (as writeMesh writes them); otherwise the mesh
// has none (they are optional).
//
// PLY (ply_format.h): element "vertex" with scalar x y z (nx ny nz optional)
// and element "face" with a list "vertex_indices" (or "vertex_index");
// polygons fanned as in OBJ; other elements and properties are skipped.
//
// Every index is checked against the vertex count, every count against the
// bytes present before anything is allocated from it; problems come back as
// an Error naming the file (and the line or face), never as a crash.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>

#include "io/containers.h"
#include "io/io_util.h"
#include "io/ply_format.h"
#include "meniscus/geometry.h"
#include "meniscus/io.h"

namespace meniscus {

namespace {

using io_util::fail;

constexpr std::uint64_t kMaxVertices = std::numeric_limits<std::uint32_t>::max();

// Runs a parser body, turning a ParseFailure or exception into an Error.
template <class Fn>
Result<TriangleMesh> guardMesh(const std::string& name, const char* format, Fn&& body) {
    try {
        Result<TriangleMesh> r = body();
        if (!r) return r;
        if (r->empty()) return makeError(name, std::string(format) + " file holds no faces");
        if (Status st = r->validate(); !st) return makeError(name, st.error().message);
        return r;
    } catch (const io_util::ParseFailure& f) {
        return makeError(name, f.message);
    } catch (const std::bad_alloc&) {
        return makeError(name, std::string("out of memory reading ") + format + " data");
    } catch (const std::exception& e) {
        return makeError(name, std::string("cannot read ") + format + " data: " + e.what());
    }
}

// Appends the fan (c0, ci, ci+1) of one polygon's corners.
void fan(const std::vector<std::uint32_t>& corners, TriangleMesh& mesh) {
    for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
        mesh.indices.push_back(corners[0]);
        mesh.indices.push_back(corners[i]);
        mesh.indices.push_back(corners[i + 1]);
    }
}

// ---------------------------------------------------------------- OBJ

class ObjParser {
public:
    explicit ObjParser(std::string_view text) : lines_(text) {}

    TriangleMesh run() {
        std::string_view line;
        while (nextLine(line)) statement(line);
        if (mesh_.positions.empty()) fail("OBJ file holds no vertices ('v' lines)");
        if (maxIndex_ > mesh_.positions.size())
            fail("line " + std::to_string(maxIndexLine_) + ": vertex index " + std::to_string(maxIndex_) +
                 " is out of range (the file has " + std::to_string(mesh_.positions.size()) + " vertices)");
        // Per-vertex normals only when every corner used its vertex's own normal.
        if (normalsMatch_ && normals_.size() == mesh_.positions.size()) mesh_.normals = std::move(normals_);
        return std::move(mesh_);
    }

private:
    // The next line without its comment.
    bool nextLine(std::string_view& line) {
        if (!lines_.next(line)) return false;
        if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        return true;
    }

    static bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

    // The next whitespace-separated word of `line` (empty at its end).
    static std::string_view word(std::string_view& line) {
        std::size_t i = 0;
        while (i < line.size() && isSpace(line[i])) ++i;
        std::size_t j = i;
        while (j < line.size() && !isSpace(line[j])) ++j;
        const std::string_view w = line.substr(i, j - i);
        line.remove_prefix(j);
        return w;
    }

    [[noreturn]] void lineFail(const std::string& what) const {
        fail("line " + std::to_string(lines_.number()) + ": " + what);
    }

    void statement(std::string_view line) {
        const std::string_view kw = word(line);
        if (kw == "v") {
            mesh_.positions.push_back(vec3(line, "vertex"));
            if (mesh_.positions.size() > kMaxVertices) lineFail("more than 2^32 - 1 vertices");
        } else if (kw == "vn") {
            normals_.push_back(vec3(line, "normal"));
        } else if (kw == "f") {
            face(line);
        }
    }

    glm::vec3 vec3(std::string_view line, const char* what) {
        glm::vec3 v;
        for (int k = 0; k < 3; ++k) {
            const std::string_view w = word(line);
            if (w.empty()) lineFail(std::string(what) + " has fewer than 3 coordinates");
            const char* b = w.data() + (w.front() == '+' ? 1 : 0);
            const auto r = std::from_chars(b, w.data() + w.size(), v[k]);
            if (r.ec != std::errc() || r.ptr != w.data() + w.size())
                lineFail(io_util::quoteShort(w) + " is not a number (" + what + " coordinate " + std::to_string(k + 1) + ")");
        }
        return v;
    }

    // An index as written: 1-based, or negative counting back from `count`.
    // Returns it 1-based (positive); 0 when the field is empty.
    std::uint64_t index(std::string_view field, std::size_t count, const char* what) const {
        if (field.empty()) return 0;
        std::int64_t v = 0;
        const auto r = std::from_chars(field.data(), field.data() + field.size(), v);
        if (r.ec != std::errc() || r.ptr != field.data() + field.size())
            lineFail(io_util::quoteShort(field) + " is not a " + what + " index");
        if (v == 0) lineFail(std::string(what) + " index 0 (OBJ indices count from 1)");
        if (v > 0) return std::uint64_t(v);
        if (std::uint64_t(-(v + 1)) >= count)  // -(v+1) avoids negating INT64_MIN
            lineFail(std::string(what) + " index " + std::to_string(v) + " reaches before the first " + what + " (" +
                     std::to_string(count) + " defined so far)");
        return std::uint64_t(std::int64_t(count) + v + 1);
    }

    void face(std::string_view line) {
        corners_.clear();
        for (std::string_view w = word(line); !w.empty(); w = word(line)) {
            const std::size_t s1 = w.find('/');
            const std::string_view vField = w.substr(0, s1);
            std::string_view nField;
            if (s1 != std::string_view::npos) {
                const std::size_t s2 = w.find('/', s1 + 1);
                if (s2 != std::string_view::npos) nField = w.substr(s2 + 1);
            }
            if (vField.empty()) lineFail("face corner " + io_util::quoteShort(w) + " has no vertex index");
            const std::uint64_t v = index(vField, mesh_.positions.size(), "vertex");
            if (v > kMaxVertices) lineFail("vertex index " + std::to_string(v) + " is out of range");
            if (v > maxIndex_) {
                maxIndex_ = v;
                maxIndexLine_ = lines_.number();
            }
            const std::uint64_t n = index(nField, normals_.size(), "normal");
            if (n != v) normalsMatch_ = false;
            corners_.push_back(std::uint32_t(v - 1));
        }
        if (corners_.size() < 3)
            lineFail("face has " + std::to_string(corners_.size()) + " corners (a polygon needs at least 3)");
        fan(corners_, mesh_);
    }

    io_util::Lines lines_;
    TriangleMesh mesh_;
    std::vector<glm::vec3> normals_;
    std::vector<std::uint32_t> corners_;
    std::uint64_t maxIndex_ = 0;  // largest 1-based vertex index used, and its line
    std::size_t maxIndexLine_ = 0;
    bool normalsMatch_ = true;
};

// ---------------------------------------------------------------- PLY

// An index read as a double, for a message: 12, -3, 2.5.
std::string shown(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

Result<TriangleMesh> parsePlyBody(ByteView data, const std::string& name) {
    if (data.empty()) return makeError(name, "file is empty");
    const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
    auto header = ply::parseHeader(text, name);
    if (!header) return header.error();
    const ply::Header& h = *header;

    const ply::Element* vertex = nullptr;
    const ply::Element* face = nullptr;
    for (const ply::Element& e : h.elements) {
        if (e.name != "vertex" && e.name != "face") continue;
        const ply::Element*& found = e.name == "vertex" ? vertex : face;
        if (found) return makeError(name, "PLY file has more than one '" + e.name + "' element");
        found = &e;
    }
    if (!vertex) return makeError(name, "PLY file has no 'vertex' element");
    if (!face) return makeError(name, "PLY file has no 'face' element: not a mesh");
    if (vertex->count > kMaxVertices) return makeError(name, "PLY file has more than 2^32 - 1 vertices");
    int xyz[3], nxyz[3];
    for (int c = 0; c < 3; ++c) {
        xyz[c] = ply::findScalar(*vertex, std::string(1, "xyz"[c]));
        nxyz[c] = ply::findScalar(*vertex, std::string("n") + "xyz"[c]);
        if (xyz[c] < 0) return makeError(name, std::string("PLY vertex element has no scalar '") + "xyz"[c] + "' property");
    }
    const bool normals = nxyz[0] >= 0 && nxyz[1] >= 0 && nxyz[2] >= 0;
    int list = -1;
    for (std::size_t i = 0; i < face->properties.size(); ++i) {
        const ply::Property& p = face->properties[i];
        if (p.isList && (p.name == "vertex_indices" || p.name == "vertex_index") && list < 0) list = int(i);
    }
    if (list < 0) return makeError(name, "PLY face element has no 'vertex_indices' list");

    // Scalar values of a row come in property order, lists left out: the
    // position of property k among them.
    auto valueSlot = [&](int k) {
        int slot = 0;
        for (int i = 0; i < k; ++i) slot += vertex->properties[std::size_t(i)].isList ? 0 : 1;
        return std::size_t(slot);
    };

    const std::unique_ptr<ply::RowSource> rows = ply::makeRowSource(h, data, name);
    TriangleMesh mesh;
    std::vector<double> values, items;
    std::vector<std::uint32_t> corners;
    for (const ply::Element& e : h.elements) {
        if (&e != vertex && &e != face) {
            if (Status s = rows->skipElement(e); !s) return s.error();
            continue;
        }
        if (Status s = rows->checkCount(e); !s) return s.error();
        if (&e == vertex) {
            mesh.positions.resize(std::size_t(e.count));
            if (normals) mesh.normals.resize(std::size_t(e.count));
            for (std::uint64_t r = 0; r < e.count; ++r) {
                if (Status s = rows->readRow(e, r, values); !s) return s.error();
                for (int c = 0; c < 3; ++c) {
                    mesh.positions[r][c] = float(values[valueSlot(xyz[c])]);
                    if (normals) mesh.normals[r][c] = float(values[valueSlot(nxyz[c])]);
                }
            }
            continue;
        }
        for (std::uint64_t r = 0; r < e.count; ++r) {
            if (Status s = rows->readRow(e, r, values, list, &items); !s) return s.error();
            if (items.size() < 3)
                return makeError(name, "PLY face " + std::to_string(r) + " has " + std::to_string(items.size()) +
                                           " vertices (a polygon needs at least 3)");
            corners.clear();
            for (const double v : items) {
                if (!(v >= 0 && v < double(vertex->count) && v == std::trunc(v)))
                    return makeError(name, "PLY face " + std::to_string(r) + " has vertex index " + shown(v) +
                                               ", out of range (" + std::to_string(vertex->count) + " vertices)");
                corners.push_back(std::uint32_t(v));
            }
            fan(corners, mesh);
        }
    }
    return mesh;
}

}  // namespace

Result<TriangleMesh> parseObjMesh(ByteView data, const std::string& name) {
    return guardMesh(name, "OBJ", [&]() -> Result<TriangleMesh> {
        if (data.empty()) return makeError(name, "file is empty");
        return ObjParser({reinterpret_cast<const char*>(data.data()), data.size()}).run();
    });
}

Result<TriangleMesh> parsePlyMesh(ByteView data, const std::string& name) {
    return guardMesh(name, "PLY", [&] { return parsePlyBody(data, name); });
}

Result<TriangleMesh> readMesh(const std::filesystem::path& path) {
    const auto format = meshFormatOf(path);
    if (!format) return makeError(path.string(), "a mesh file must end in .obj or .ply");
    // Checked from its first bytes ('ply' on line 1, or text), and read
    // whole only within the size a mesh file may have (geometry.h).
    const bool obj = *format == MeshFormat::Obj;
    auto bytes = io_util::readFileChecked(path, geometry_limits::kMaxMeshFileBytes, [&](ByteView head) {
        return io_util::checkParticleHead(head, path.string(), obj ? ParticleFormat::Xyz : ParticleFormat::Ply);
    });
    if (!bytes) return bytes.error();
    return *format == MeshFormat::Obj ? parseObjMesh(*bytes, path.string()) : parsePlyMesh(*bytes, path.string());
}

}  // namespace meniscus
