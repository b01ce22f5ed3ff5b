// Mesh files: binary little-endian PLY (the default; compact, what splashsurf
// writes), Wavefront OBJ, and VTK PolyData for ParaView (.vtp, .vtk:
// mesh_vtk_writer.cpp). Written in one buffered pass through writeAtomically,
// so a failed write leaves no file behind.
#include <bit>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "atomic_file.h"
#include "io/byte_out.h"
#include "io/particle_writers.h"
#include "io_util.h"
#include "meniscus/io.h"

namespace meniscus {

namespace {

static_assert(std::endian::native == std::endian::little, "the PLY writer writes native floats as little-endian");

Status writeWith(const std::filesystem::path& path, const std::function<bool(std::FILE*)>& body) {
    const std::string name = path.string();
    return writeAtomically(path, [&](const std::filesystem::path& tmp) -> Status {
        std::FILE* fp = std::fopen(tmp.c_str(), "wb");
        if (!fp) return makeError(name, std::string("cannot open for writing: ") + std::strerror(errno));
        std::vector<char> buffer(1 << 20);
        std::setvbuf(fp, buffer.data(), _IOFBF, buffer.size());
        const bool ok = body(fp) && std::fflush(fp) == 0 && !std::ferror(fp);
        const int err = errno;
        const bool closed = std::fclose(fp) == 0;
        if (!ok || !closed) return makeError(name, std::string("write failed: ") + std::strerror(ok ? errno : err));
        return okStatus();
    });
}

// A PLY property name for component c of an attribute: the name (letters,
// digits and '_' kept, anything else '_'), with _x, _y, _z for three
// components and _0, _1, ... for other counts above one.
std::string plyProperty(const Attribute& a, int c) {
    std::string name;
    for (const char ch : a.name) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    if (a.components == 3) return name + "_" + char('x' + c);
    if (a.components > 1) return name + "_" + std::to_string(c);
    return name;
}

bool writePly(std::FILE* fp, const TriangleMesh& m) {
    const bool normals = !m.normals.empty();
    std::string header = "ply\nformat binary_little_endian 1.0\ncomment written by meniscus (isosurface path)\n";
    header += "element vertex " + std::to_string(m.positions.size()) + "\n";
    header += "property float x\nproperty float y\nproperty float z\n";
    if (normals) header += "property float nx\nproperty float ny\nproperty float nz\n";
    std::size_t extra = 0;
    for (const Attribute& a : m.attributes)
        for (int c = 0; c < a.components; ++c, ++extra) header += "property float " + plyProperty(a, c) + "\n";
    header += "element face " + std::to_string(m.triangleCount()) + "\n";
    header += "property list uchar uint vertex_indices\nend_header\n";
    if (std::fwrite(header.data(), 1, header.size(), fp) != header.size()) return false;
    std::vector<float> rec(6 + extra);
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        std::size_t k = 0;
        for (int c = 0; c < 3; ++c) rec[k++] = m.positions[v][c];
        if (normals)
            for (int c = 0; c < 3; ++c) rec[k++] = m.normals[v][c];
        for (const Attribute& a : m.attributes)
            for (int c = 0; c < a.components; ++c) rec[k++] = a.floats[v * std::size_t(a.components) + std::size_t(c)];
        if (std::fwrite(rec.data(), sizeof(float), k, fp) != k) return false;
    }
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        unsigned char rec[13];
        rec[0] = 3;
        std::memcpy(rec + 1, &m.indices[3 * t], 12);
        if (std::fwrite(rec, 1, 13, fp) != 13) return false;
    }
    return true;
}

bool writeObj(std::FILE* fp, const TriangleMesh& m) {
    const bool normals = !m.normals.empty();
    if (std::fprintf(fp, "# written by meniscus (isosurface path): %zu vertices, %zu triangles\n", m.positions.size(),
                     m.triangleCount()) < 0)
        return false;
    // %.9g: a float survives the round trip through text.
    for (const glm::vec3& p : m.positions)
        if (std::fprintf(fp, "v %.9g %.9g %.9g\n", double(p.x), double(p.y), double(p.z)) < 0) return false;
    if (normals)
        for (const glm::vec3& n : m.normals)
            if (std::fprintf(fp, "vn %.6g %.6g %.6g\n", double(n.x), double(n.y), double(n.z)) < 0) return false;
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        const unsigned a = m.indices[3 * t] + 1, b = m.indices[3 * t + 1] + 1, c = m.indices[3 * t + 2] + 1;
        const int r = normals ? std::fprintf(fp, "f %u//%u %u//%u %u//%u\n", a, a, b, b, c, c)
                              : std::fprintf(fp, "f %u %u %u\n", a, b, c);
        if (r < 0) return false;
    }
    return true;
}

}  // namespace

Result<MeshFormat> meshFormatOf(const std::filesystem::path& path) {
    const std::string ext = io_util::lower(path.extension().string());
    if (ext == ".ply") return MeshFormat::Ply;
    if (ext == ".obj") return MeshFormat::Obj;
    if (ext == ".vtp") return MeshFormat::Vtp;
    if (ext == ".vtk") return MeshFormat::VtkLegacy;
    return makeError(path.string(), "output must end in .ply, .obj, .vtp or .vtk");
}

Status writeMesh(const std::filesystem::path& path, const TriangleMesh& mesh, MeshFormat format) {
    if (auto st = mesh.validate(); !st) return makeError(path.string(), "cannot write the mesh: " + st.error().message);
    if (format == MeshFormat::Vtp || format == MeshFormat::VtkLegacy) {
        if (format == MeshFormat::VtkLegacy)
            if (auto st = io_write::checkMeshVtkLegacy(mesh, path.string()); !st) return st;
        return writeAtomically(path, [&](const std::filesystem::path& tmp) -> Status {
            io_write::ByteOut out(tmp, 0);
            if (format == MeshFormat::Vtp) io_write::writeMeshVtp(mesh, out);
            else io_write::writeMeshVtkLegacy(mesh, out);
            out.finish();
            return okStatus();
        });
    }
    return writeWith(path, [&](std::FILE* fp) { return format == MeshFormat::Obj ? writeObj(fp, mesh) : writePly(fp, mesh); });
}

}  // namespace meniscus
