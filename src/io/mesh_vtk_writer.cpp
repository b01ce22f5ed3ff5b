// Meshes for ParaView: VTK PolyData, the triangles as polygons, the vertex
// normals and attributes as point data ("VTK File Formats", docs.vtk.org;
// what vtkXMLPolyDataWriter and vtkPolyDataWriter write):
//   .vtp  XML, every array appended raw little-endian with UInt64 headers
//         (as the particle writer, vtu_writer.cpp): <PointData Normals=..>
//         Normals and each attribute, <Points>, <Polys> connectivity (three
//         per triangle) and offsets (3, 6, ...), Int32, or Int64 past 2^31 - 1.
//   .vtk  legacy binary (big-endian) POLYDATA: POINTS, POLYGONS T 4T (3 a b
//         c per triangle, int32), POINT_DATA with NORMALS, the density as
//         SCALARS, the velocity as VECTORS, every other attribute in FIELD
//         (which VTK's legacy reader always reads whole).
// The density and velocity are the active scalars and vectors ParaView
// colours by, the normals the ones it shades with.
#include <limits>

#include "io/particle_writers.h"
#include "io/vtk_names.h"

namespace meniscus::io_write {

namespace {

template <class Index>
void polys(const TriangleMesh& m, ByteOut& out) {
    const std::size_t t = m.triangleCount();
    out.le(std::uint64_t(3 * t * sizeof(Index)));
    for (const std::uint32_t i : m.indices) out.le(Index(i));
    out.le(std::uint64_t(t * sizeof(Index)));
    for (std::size_t k = 0; k < t; ++k) out.le(Index(3 * (k + 1)));
}

void vec3s(const std::vector<glm::vec3>& v, ByteOut& out, std::endian order) {
    for (const glm::vec3& p : v) {
        out.put(p.x, order);
        out.put(p.y, order);
        out.put(p.z, order);
    }
}

}  // namespace

void writeMeshVtp(const TriangleMesh& m, ByteOut& out) {
    const std::size_t v = m.vertexCount(), t = m.triangleCount();
    const bool wide = 3 * t > std::size_t(std::numeric_limits<std::int32_t>::max());
    const std::string indexType = wide ? "Int64" : "Int32";
    const std::uint64_t indexBytes = wide ? 8 : 4;
    const bool normals = !m.normals.empty();
    std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
                      "header_type=\"UInt64\">\n  <PolyData>\n    <Piece NumberOfPoints=\"" +
                      std::to_string(v) +
                      "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
                      std::to_string(t) + "\">\n      <PointData";
    if (normals) xml += " Normals=\"Normals\"";
    for (const Attribute& a : m.attributes) {
        if (a.name == kAttrDensity && a.components == 1) xml += " Scalars=\"density\"";
        if (a.name == kAttrVelocity && a.components == 3) xml += " Vectors=\"velocity\"";
    }
    xml += ">\n";
    std::uint64_t offset = 0;
    if (normals) xml += place({dataArray("Float32", "Normals", 3), std::uint64_t(v) * 12}, offset, "        ");
    for (const Attribute& a : m.attributes)
        xml += place({dataArray("Float32", a.name, a.components), std::uint64_t(v) * std::uint64_t(a.components) * 4},
                     offset, "        ");
    xml += "      </PointData>\n      <Points>\n";
    xml += place({dataArray("Float32", "Points", 3), std::uint64_t(v) * 12}, offset, "        ");
    xml += "      </Points>\n      <Polys>\n";
    xml += place({dataArray(indexType, "connectivity", 1), 3 * std::uint64_t(t) * indexBytes}, offset, "        ");
    xml += place({dataArray(indexType, "offsets", 1), std::uint64_t(t) * indexBytes}, offset, "        ");
    xml += "      </Polys>\n    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _";
    out.text(xml);
    if (normals) {
        out.le(std::uint64_t(v) * 12);
        vec3s(m.normals, out, std::endian::little);
    }
    for (const Attribute& a : m.attributes) {
        out.le(std::uint64_t(a.floats.size()) * 4);
        for (const float f : a.floats) out.le(f);
    }
    out.le(std::uint64_t(v) * 12);
    vec3s(m.positions, out, std::endian::little);
    if (wide)
        polys<std::int64_t>(m, out);
    else
        polys<std::int32_t>(m, out);
    out.text("\n  </AppendedData>\n</VTKFile>\n");
}

Status checkMeshVtkLegacy(const TriangleMesh& m, const std::string& file) {
    // POLYGONS counts 4 int32 values per triangle.
    if (m.triangleCount() > std::size_t(std::numeric_limits<std::int32_t>::max() / 4))
        return makeError(file, "legacy VTK holds at most 536,870,911 triangles; the mesh has " +
                                   std::to_string(m.triangleCount()) + " (write .vtp instead)");
    return okStatus();
}

void writeMeshVtkLegacy(const TriangleMesh& m, ByteOut& out) {
    const std::string v = std::to_string(m.vertexCount()), t = std::to_string(m.triangleCount());
    out.text("# vtk DataFile Version 4.2\nsurface mesh written by meniscus\nBINARY\nDATASET POLYDATA\n");
    out.text("POINTS " + v + " float\n");
    vec3s(m.positions, out, std::endian::big);
    out.text("\nPOLYGONS " + t + " " + std::to_string(4 * m.triangleCount()) + "\n");
    for (std::size_t k = 0; k < m.triangleCount(); ++k) {
        out.be(std::int32_t(3));
        for (int c = 0; c < 3; ++c) out.be(std::int32_t(m.indices[3 * k + std::size_t(c)]));
    }
    out.text("\n");
    if (m.normals.empty() && m.attributes.empty()) return;
    out.text("POINT_DATA " + v + "\n");
    if (!m.normals.empty()) {
        out.text("NORMALS Normals float\n");
        vec3s(m.normals, out, std::endian::big);
        out.text("\n");
    }
    auto values = [&](const Attribute& a) {
        for (const float f : a.floats) out.be(f);
        out.text("\n");
    };
    std::vector<const Attribute*> fields;
    for (const Attribute& a : m.attributes) {
        if (a.name == kAttrDensity && a.components == 1) {
            out.text("SCALARS density float 1\nLOOKUP_TABLE default\n");
            values(a);
        } else if (a.name == kAttrVelocity && a.components == 3) {
            out.text("VECTORS velocity float\n");
            values(a);
        } else {
            fields.push_back(&a);
        }
    }
    if (fields.empty()) return;
    out.text("FIELD FieldData " + std::to_string(fields.size()) + "\n");
    for (const Attribute* a : fields) {
        out.text(vtkLegacyName(a->name) + " " + std::to_string(a->components) + " " + v + " float\n");
        values(*a);
    }
}

}  // namespace meniscus::io_write
