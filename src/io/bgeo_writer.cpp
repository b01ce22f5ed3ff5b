// Houdini classic BGEO v5 writer, laid out as partio writes it (wdas/partio,
// src/lib/io/BHCLASSIC.cpp, writeBHCLASSIC) and so as SPlisHSPlasH's partio
// export is: big-endian,
//   int32 magic 'Bgeo', char 'V', int32 version 5, nPoints, nPrims 0,
//   nPointGroups 0, nPrimGroups 0, nPointAttrib, nVertexAttrib 0,
//   nPrimAttrib 0, nAttrib 0;
//   per point attribute: uint16 name length, name, uint16 size, int32 type
//     (0 float, 1 int, 5 vector: a Float attribute of 3 components), size x
//     int32 default 0;
//   per point: P as 4 float32 (x, y, z, w = 1), then each attribute's values;
//   no primitives, no detail attributes, then the bytes 00 ff.
// Plain for .bgeo, gzip-compressed for .bgeo.gz, as partio's write() decides
// from the name (SPlisHSPlasH forces compression, so its .bgeo files are gzip
// data; partio, Houdini and our reader read either).
#include <bit>
#include <limits>

#include "io/particle_writers.h"

namespace meniscus::io_write {

namespace {
enum HoudiniType : std::int32_t { kFloat = 0, kInt = 1, kVector = 5 };

HoudiniType houdiniType(const Attribute& a) {
    if (a.type == AttributeType::Int) return kInt;
    return a.components == 3 ? kVector : kFloat;
}
}  // namespace

Status checkBgeo(const ParticleSet& set, const std::string& file) {
    if (set.size() > std::size_t(std::numeric_limits<std::int32_t>::max()))
        return makeError(file, "BGEO holds at most 2^31 - 1 points; the set has " + std::to_string(set.size()));
    for (const Attribute& a : set.attributes) {
        if (a.name == "P" || a.name == "position")
            return makeError(file, "attribute '" + a.name + "' would clash with the position, which BGEO stores as P");
        if (a.name.size() > std::numeric_limits<std::uint16_t>::max() || a.components > 0xffff)
            return makeError(file, "attribute '" + a.name.substr(0, 60) +
                                       "': BGEO names and component counts are at most 65535");
    }
    return okStatus();
}

void writeBgeo(const ParticleSet& set, ByteOut& out) {
    out.text("Bgeo");
    out.u8('V');
    const std::int32_t counts[] = {5, std::int32_t(set.size()), 0, 0, 0, std::int32_t(set.attributes.size()), 0, 0, 0};
    for (std::int32_t c : counts) out.be(c);
    for (const Attribute& a : set.attributes) {
        out.be(std::uint16_t(a.name.size()));
        out.text(a.name);
        out.be(std::uint16_t(a.components));
        out.be(std::int32_t(houdiniType(a)));
        for (int c = 0; c < a.components; ++c) out.be(std::int32_t(0));
    }
    for (std::size_t i = 0; i < set.size(); ++i) {
        const glm::vec3& p = set.positions[i];
        out.be(p.x);
        out.be(p.y);
        out.be(p.z);
        out.be(1.0f);  // w
        putRecord(out, set, i, std::endian::big);
    }
    out.u8(0x00);
    out.u8(0xff);
}

}  // namespace meniscus::io_write
