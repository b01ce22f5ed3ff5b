// PLY particle writer: binary little-endian, one "vertex" element (Turk 1994;
// see ply_format.h) with
//   property float x, y, z
//   per attribute, in the set's order, float or int (int32):
//     velocity                 vx vy vz (what our reader, CloudCompare and
//                              MeshLab's custom-attribute import expect)
//     one component            its name
//     k components             NAME_0 ... NAME_{k-1}
// Our reader (ply.cpp) maps these back to the same attributes: vx vy vz ->
// velocity, density, id, and NAME_0.. -> NAME with k components.
#include <algorithm>
#include <cctype>

#include "io/particle_writers.h"

namespace meniscus::io_write {

namespace {

// The property name of each component of `a`.
std::vector<std::string> propertyNames(const Attribute& a) {
    if (a.name == kAttrVelocity) return {"vx", "vy", "vz"};
    if (a.components == 1) return {a.name};
    std::vector<std::string> names;
    for (int c = 0; c < a.components; ++c) names.push_back(a.name + "_" + std::to_string(c));
    return names;
}

}  // namespace

Status checkPly(const ParticleSet& set, const std::string& file) {
    std::vector<std::string> taken = {"x", "y", "z"};
    for (const Attribute& a : set.attributes) {
        if (std::any_of(a.name.begin(), a.name.end(), [](char c) { return !std::isgraph(static_cast<unsigned char>(c)); }))
            return makeError(file, "attribute '" + a.name.substr(0, 60) +
                                       "': PLY property names cannot hold spaces or control characters");
        for (const std::string& n : propertyNames(a)) {
            if (std::find(taken.begin(), taken.end(), n) != taken.end())
                return makeError(file, "attribute '" + a.name + "' would be written as PLY property '" + n +
                                           "', which another column already is");
            taken.push_back(n);
        }
    }
    return okStatus();
}

void writePly(const ParticleSet& set, ByteOut& out) {
    std::string header = "ply\nformat binary_little_endian 1.0\ncomment particles written by meniscus\n";
    header += "element vertex " + std::to_string(set.size()) + "\n";
    header += "property float x\nproperty float y\nproperty float z\n";
    for (const Attribute& a : set.attributes)
        for (const std::string& n : propertyNames(a))
            header += std::string("property ") + (a.type == AttributeType::Int ? "int " : "float ") + n + "\n";
    header += "end_header\n";
    out.text(header);
    for (std::size_t i = 0; i < set.size(); ++i) {
        const glm::vec3& p = set.positions[i];
        out.le(p.x);
        out.le(p.y);
        out.le(p.z);
        putRecord(out, set, i, std::endian::little);
    }
}

}  // namespace meniscus::io_write
