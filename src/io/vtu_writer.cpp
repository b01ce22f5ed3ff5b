// VTK XML writer: UnstructuredGrid (.vtu) or PolyData (.vtp), every array
// "appended" as raw little-endian binary with UInt64 headers, as VTK's
// vtkXMLUnstructuredGridWriter / vtkXMLPolyDataWriter write them in their
// default appended mode (without compression) and ParaView opens them
// ("VTK File Formats", section "XML File Formats", docs.vtk.org):
//   <VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">
//     <UnstructuredGrid><Piece NumberOfPoints="n" NumberOfCells="n">
//       <PointData Scalars=".." Vectors=".."> a DataArray per attribute </PointData>
//       <Points> DataArray Float32 x 3 </Points>
//       <Cells> connectivity, offsets, types (one VTK_VERTEX cell per point) </Cells>
//   <AppendedData encoding="raw"> _ then per array: UInt64 byte count, the bytes
// (.vtp: <PolyData><Piece ... NumberOfVerts="n"> with <Verts> connectivity, offsets.)
// offset="k" counts from the byte after '_'. Float attributes are Float32,
// Int attributes Int32; connectivity and offsets are Int32, or Int64 past
// 2^31 - 1 points.
#include <limits>

#include "io/particle_writers.h"
#include "io/vtk_names.h"

namespace meniscus::io_write {

namespace {

template <class Index>
void cellArrays(std::size_t n, bool polyData, ByteOut& out) {
    out.le(std::uint64_t(n * sizeof(Index)));
    for (std::size_t i = 0; i < n; ++i) out.le(Index(i));  // connectivity
    out.le(std::uint64_t(n * sizeof(Index)));
    for (std::size_t i = 0; i < n; ++i) out.le(Index(i + 1));  // offsets: the end of each cell
    if (polyData) return;
    out.le(std::uint64_t(n));
    for (std::size_t i = 0; i < n; ++i) out.u8(1);  // VTK_VERTEX
}

}  // namespace

void writeVtu(const ParticleSet& set, ByteOut& out, bool polyData) {
    const std::size_t n = set.size();
    const bool wide = n > std::size_t(std::numeric_limits<std::int32_t>::max());
    const std::string indexType = wide ? "Int64" : "Int32";
    const std::uint64_t indexBytes = n * (wide ? 8 : 4);
    const std::string count = std::to_string(n);
    const std::string grid = polyData ? "PolyData" : "UnstructuredGrid";

    std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"" + grid +
                      "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <" + grid + ">\n";
    xml += "    <Piece NumberOfPoints=\"" + count + "\"" +
           (polyData ? " NumberOfVerts=\"" + count + "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\""
                     : " NumberOfCells=\"" + count + "\"") +
           ">\n";
    std::uint64_t offset = 0;
    // The canonical attributes are the active ones ParaView colours by.
    xml += "      <PointData";
    if (const Attribute* d = set.find(kAttrDensity)) xml += " Scalars=\"" + xmlEscaped(d->name) + "\"";
    if (const Attribute* v = set.find(kAttrVelocity)) xml += " Vectors=\"" + xmlEscaped(v->name) + "\"";
    xml += ">\n";
    for (const Attribute& a : set.attributes) {
        const Block b{dataArray(a.type == AttributeType::Int ? "Int32" : "Float32", a.name, a.components),
                      std::uint64_t(n) * std::uint64_t(a.components) * 4};
        xml += place(b, offset, "        ");
    }
    xml += "      </PointData>\n      <Points>\n";
    xml += place({dataArray("Float32", "Points", 3), std::uint64_t(n) * 12}, offset, "        ");
    xml += polyData ? "      </Points>\n      <Verts>\n" : "      </Points>\n      <Cells>\n";
    xml += place({dataArray(indexType, "connectivity", 1), indexBytes}, offset, "        ");
    xml += place({dataArray(indexType, "offsets", 1), indexBytes}, offset, "        ");
    if (!polyData) xml += place({dataArray("UInt8", "types", 1), std::uint64_t(n)}, offset, "        ");
    xml += polyData ? "      </Verts>\n" : "      </Cells>\n";
    xml += "    </Piece>\n  </" + grid + ">\n  <AppendedData encoding=\"raw\">\n   _";
    out.text(xml);

    for (const Attribute& a : set.attributes) {
        out.le(std::uint64_t(n) * std::uint64_t(a.components) * 4);
        putValues(out, a, n, std::endian::little);
    }
    out.le(std::uint64_t(n) * 12);
    for (const glm::vec3& p : set.positions) {
        out.le(p.x);
        out.le(p.y);
        out.le(p.z);
    }
    if (wide)
        cellArrays<std::int64_t>(n, polyData, out);
    else
        cellArrays<std::int32_t>(n, polyData, out);
    out.text("\n  </AppendedData>\n</VTKFile>\n");
}

}  // namespace meniscus::io_write
