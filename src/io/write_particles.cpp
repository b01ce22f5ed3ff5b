// writeParticles(): the format from the name, the checks every format needs,
// then the format's writer (particle_writers.h) through a temporary file that
// is renamed into place only when complete (atomic_file.h).
#include <cmath>
#include <limits>

#include "io/atomic_file.h"
#include "io/io_util.h"
#include "io/particle_writers.h"
#include "meniscus/io.h"

namespace meniscus {

namespace {

using io_util::endsWith;
using io_util::lower;

// gzip level of .bgeo.gz output. On the r = 0.01 dam break (117,649
// particles: id, density, velocity) level 1 writes in ~190 ms what level 6
// writes in ~300 ms, 0.4 % larger; float data compresses poorly (3.49 MB
// against 4.24 MB plain), and plain .bgeo takes ~17 ms.
constexpr int kBgeoGzipLevel = 1;

std::string what(const Attribute& a) {
    return std::string(a.type == AttributeType::Int ? "Int" : "Float") + " x " + std::to_string(a.components);
}

// What every format needs of a set.
Status checkSet(const ParticleSet& set, const std::string& file) {
    const std::size_t n = set.size();
    for (std::size_t k = 0; k < set.attributes.size(); ++k) {
        const Attribute& a = set.attributes[k];
        if (a.name.empty()) return makeError(file, "attribute " + std::to_string(k + 1) + " has no name");
        for (std::size_t j = 0; j < k; ++j)
            if (set.attributes[j].name == a.name) return makeError(file, "two attributes are named '" + a.name + "'");
        if (a.components < 1)
            return makeError(file, "attribute '" + a.name + "' has " + std::to_string(a.components) + " components");
        const std::size_t values = a.type == AttributeType::Int ? a.ints.size() : a.floats.size();
        if (values != n * std::size_t(a.components))
            return makeError(file, "attribute '" + a.name + "' has " + std::to_string(values) + " values, but " +
                                       std::to_string(n) + " particles of " + std::to_string(a.components) +
                                       " components need " + std::to_string(n * std::size_t(a.components)));
        // The canonical attributes (types.h) are read back by name with these types.
        const bool canonical = (a.name == kAttrId && (a.type != AttributeType::Int || a.components != 1)) ||
                               (a.name == kAttrVelocity && (a.type != AttributeType::Float || a.components != 3)) ||
                               (a.name == kAttrDensity && (a.type != AttributeType::Float || a.components != 1));
        if (canonical)
            return makeError(file, "attribute '" + a.name + "' is " + what(a) + "; '" + a.name + "' must be " +
                                       (a.name == kAttrId ? "Int x 1" : a.name == kAttrVelocity ? "Float x 3" : "Float x 1"));
        if (a.type == AttributeType::Int)
            for (std::size_t i = 0; i < a.ints.size(); ++i)
                if (a.ints[i] < std::numeric_limits<std::int32_t>::min() ||
                    a.ints[i] > std::numeric_limits<std::int32_t>::max())
                    return makeError(file, "attribute '" + a.name + "' of particle " +
                                               std::to_string(i / std::size_t(a.components)) + " is " +
                                               std::to_string(a.ints[i]) + ", beyond the 32-bit integers files store");
    }
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3& p = set.positions[i];
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
            return makeError(file, "particle " + std::to_string(i) + " has a non-finite position (" +
                                       std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) +
                                       "); nothing written");
    }
    return okStatus();
}

}  // namespace

Result<ParticleFormat> writableFormatOf(const std::filesystem::path& path, ParticleFormat format) {
    const std::string file = path.string();
    const std::string name = lower(path.filename().string());
    if (format == ParticleFormat::Auto) {
        if (endsWith(name, ".geo"))
            return makeError(file, "ASCII Houdini .geo is not written; name the file .bgeo (or .bgeo.gz)");
        format = formatFromName(name);
    }
    if (format != ParticleFormat::Bgeo && format != ParticleFormat::VtkLegacy && format != ParticleFormat::Vtu &&
        format != ParticleFormat::Ply)  // CSV, XYZ and the read-only HDF5 and .npz
        return makeError(file, "cannot write particles in this format: name the file .bgeo, .bgeo.gz, .vtk, .vtu, "
                               ".vtp or .ply");
    return format;
}

Status writeParticles(const std::filesystem::path& path, const ParticleSet& set, ParticleFormat format) {
    const std::string file = path.string();
    const std::string name = lower(path.filename().string());
    auto writable = writableFormatOf(path, format);
    if (!writable) return writable.error();
    format = *writable;
    if (Status st = checkSet(set, file); !st) return st;
    Status fits = okStatus();
    if (format == ParticleFormat::Bgeo) fits = io_write::checkBgeo(set, file);
    if (format == ParticleFormat::VtkLegacy) fits = io_write::checkVtkLegacy(set, file);
    if (format == ParticleFormat::Ply) fits = io_write::checkPly(set, file);
    if (!fits) return fits;

    return writeAtomically(path, [&](const std::filesystem::path& tmp) -> Status {
        // gzip for .bgeo.gz only, as partio decides (SPlisHSPlasH forces it for .bgeo too).
        io_write::ByteOut out(tmp, endsWith(name, ".gz") ? kBgeoGzipLevel : 0);
        switch (format) {
            case ParticleFormat::Bgeo: io_write::writeBgeo(set, out); break;
            case ParticleFormat::VtkLegacy: io_write::writeVtkLegacy(set, out); break;
            case ParticleFormat::Vtu: io_write::writeVtu(set, out, endsWith(name, ".vtp")); break;
            case ParticleFormat::Ply: io_write::writePly(set, out); break;
            default: break;  // refused above
        }
        out.finish();
        return okStatus();
    });
}

}  // namespace meniscus
