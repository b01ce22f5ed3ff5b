// Legacy VTK writer: binary (big-endian) POLYDATA, after "VTK File Formats"
// (Kitware; docs.vtk.org) and what VTK's own vtkPolyDataWriter writes, which
// ParaView opens:
//   # vtk DataFile Version 4.2 / title / BINARY / DATASET POLYDATA
//   POINTS n float              n x 3 float32
//   VERTICES n 2n               per point: int32 1, int32 index (a vertex cell
//                               each, so that every filter sees the points)
//   POINT_DATA n, then
//     density (if any)              SCALARS density float 1 + LOOKUP_TABLE default
//     velocity (if any)             VECTORS velocity float
//     every other attribute         FIELD FieldData k: NAME components n float|int
// VTK's legacy reader (vtkDataReader, and so ParaView's) keeps only the first
// SCALARS and the first VECTORS array unless told to read all (ReadAllScalars),
// so the others go in the FIELD block, which it always reads whole, as
// SPlisHSPlasH's legacy export does too. Density and velocity become the
// active scalars and vectors that ParaView colours and glyphs by.
// Each block of data ends with a newline, as VTK writes it. Names are encoded
// as VTK does (%XX for spaces, '%', '"' and non-printable bytes), and our
// reader (vtk_legacy.cpp) decodes them, so every name comes back as it was.
#include <cstdio>
#include <limits>

#include "io/particle_writers.h"
#include "io/vtk_names.h"

namespace meniscus::io_write {

namespace {

// The values of `a`, big-endian, then the newline that ends a block.
void values(const ParticleSet& set, const Attribute& a, ByteOut& out) {
    putValues(out, a, set.size(), std::endian::big);
    out.text("\n");
}

}  // namespace

Status checkVtkLegacy(const ParticleSet& set, const std::string& file) {
    // VERTICES counts 2n int32 values.
    if (set.size() > std::size_t(std::numeric_limits<std::int32_t>::max() / 2))
        return makeError(file, "legacy VTK holds at most 2^30 - 1 points as vertex cells; the set has " +
                                   std::to_string(set.size()) + " (write .vtu instead)");
    return okStatus();
}

void writeVtkLegacy(const ParticleSet& set, ByteOut& out) {
    const std::string n = std::to_string(set.size());
    out.text("# vtk DataFile Version 4.2\nparticles written by meniscus\nBINARY\nDATASET POLYDATA\n");
    out.text("POINTS " + n + " float\n");
    for (const glm::vec3& p : set.positions) {
        out.be(p.x);
        out.be(p.y);
        out.be(p.z);
    }
    out.text("\nVERTICES " + n + " " + std::to_string(2 * set.size()) + "\n");
    for (std::size_t i = 0; i < set.size(); ++i) {
        out.be(std::int32_t(1));
        out.be(std::int32_t(i));
    }
    out.text("\n");
    if (set.attributes.empty()) return;

    out.text("POINT_DATA " + n + "\n");
    std::vector<const Attribute*> fields;
    for (const Attribute& a : set.attributes) {
        if (a.name == kAttrDensity) {
            out.text("SCALARS density float 1\nLOOKUP_TABLE default\n");
            values(set, a, out);
        } else if (a.name == kAttrVelocity) {
            out.text("VECTORS velocity float\n");
            values(set, a, out);
        } else {
            fields.push_back(&a);
        }
    }
    if (fields.empty()) return;
    out.text("FIELD FieldData " + std::to_string(fields.size()) + "\n");
    for (const Attribute* a : fields) {
        out.text(vtkLegacyName(a->name) + " " + std::to_string(a->components) + " " + n + " " +
                 (a->type == AttributeType::Int ? "int" : "float") + "\n");
        values(set, *a, out);
    }
}

}  // namespace meniscus::io_write
