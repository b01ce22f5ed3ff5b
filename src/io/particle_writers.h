// The particle writers of each format, behind writeParticles()
// (write_particles.cpp, which checks what every format needs first: one value
// per particle and component, finite positions, Int values within int32, the
// canonical attributes with their canonical types). Internal to src/io.
#pragma once

#include <bit>
#include <cstdint>
#include <string>

#include "io/byte_out.h"
#include "meniscus/mesh.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus::io_write {

// Each check says, before a byte is written, whether the format can hold the
// set (name lengths, counts, characters in names); errors name `file`.
// Each write encodes the set, header and all, into `out`.
Status checkBgeo(const ParticleSet& set, const std::string& file);  // bgeo_writer.cpp
void writeBgeo(const ParticleSet& set, ByteOut& out);
Status checkVtkLegacy(const ParticleSet& set, const std::string& file);  // vtk_legacy_writer.cpp
void writeVtkLegacy(const ParticleSet& set, ByteOut& out);
// UnstructuredGrid (.vtu) or PolyData (.vtp).
void writeVtu(const ParticleSet& set, ByteOut& out, bool polyData);  // vtu_writer.cpp
Status checkPly(const ParticleSet& set, const std::string& file);    // ply_writer.cpp
void writePly(const ParticleSet& set, ByteOut& out);
// Meshes as VTK PolyData (mesh_vtk_writer.cpp): XML (.vtp) and legacy (.vtk).
void writeMeshVtp(const TriangleMesh& mesh, ByteOut& out);
Status checkMeshVtkLegacy(const TriangleMesh& mesh, const std::string& file);
void writeMeshVtkLegacy(const TriangleMesh& mesh, ByteOut& out);

// Component c of particle i of `a` in the given byte order: int32 for an Int
// attribute (writeParticles has checked that the values fit), float32 for Float.
inline void putValue(ByteOut& out, const Attribute& a, std::size_t i, int c, std::endian order) {
    const std::size_t k = i * std::size_t(a.components) + std::size_t(c);
    if (a.type == AttributeType::Int)
        out.put(std::int32_t(a.ints[k]), order);
    else
        out.put(a.floats[k], order);
}
// Every attribute's values of particle i, in the set's order (a record).
inline void putRecord(ByteOut& out, const ParticleSet& set, std::size_t i, std::endian order) {
    for (const Attribute& a : set.attributes)
        for (int c = 0; c < a.components; ++c) putValue(out, a, i, c, order);
}
// All values of `a`, particle by particle.
inline void putValues(ByteOut& out, const Attribute& a, std::size_t particles, std::endian order) {
    for (std::size_t i = 0; i < particles; ++i)
        for (int c = 0; c < a.components; ++c) putValue(out, a, i, c, order);
}

}  // namespace meniscus::io_write
