// Format dispatch and the checks every particle file gets, whatever its format:
// non-finite positions dropped with a counted warning
// (docs/pipeline.md#classification), empty sets rejected.
#include <algorithm>
#include <cctype>
#include <fstream>
#include <limits>
#include <new>

#include "io/containers.h"
#include "io/io_util.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"

namespace meniscus {

namespace {

using io_util::endsWith;
using io_util::lower;

// Content sniffing, for names without a known extension.
ParticleFormat formatFromContent(ByteView data) {
    auto startsWith = [&](std::string_view magic) {
        return data.size() >= magic.size() &&
               std::equal(magic.begin(), magic.end(), data.begin(),
                          [](char m, std::uint8_t b) { return static_cast<std::uint8_t>(m) == b; });
    };
    if (startsWith("\x1f\x8b") || startsWith("Bgeo")) return ParticleFormat::Bgeo;
    if (startsWith("# vtk DataFile")) return ParticleFormat::VtkLegacy;
    if (startsWith("ply")) return ParticleFormat::Ply;
    if (startsWith("<?xml") || startsWith("<VTKFile")) return ParticleFormat::Vtu;
    if (io_util::hasHdf5Signature(data)) return ParticleFormat::Hdf5;
    if (startsWith("PK\x03\x04") || startsWith("PK\x05\x06")) return ParticleFormat::Npz;  // a zip archive
    return ParticleFormat::Auto;
}

// The checks every particle file gets, whatever its format (see io.h).
Result<ParticleSet> finishParticles(Result<ParticleSet> parsed, const std::string& name, bool allowEmpty) {
    if (!parsed) return parsed;
    ParticleSet& set = parsed.value();
    for (const Attribute& a : set.attributes)
        if (a.count() != set.size())
            return makeError(name, "attribute '" + a.name + "' has " + std::to_string(a.count()) +
                                       " values but the file has " + std::to_string(set.size()) + " particles");
    const std::size_t total = set.size();
    const std::size_t dropped = dropNonFinite(set);
    if (dropped > 0)
        set.warnings.push_back(name + ": dropped " + std::to_string(dropped) + " of " + std::to_string(total) +
                               " particles with NaN/Inf positions");
    if (set.size() == 0 && !(allowEmpty && total == 0))
        return makeError(name, total == 0 ? "file contains no particles"
                                          : "all " + std::to_string(total) + " particles have NaN/Inf positions");
    return parsed;
}

}  // namespace

ParticleFormat formatFromName(std::string_view name) {
    const std::string n = lower(name);
    if (endsWith(n, ".bgeo") || endsWith(n, ".bgeo.gz") || endsWith(n, ".geo")) return ParticleFormat::Bgeo;
    if (endsWith(n, ".vtk")) return ParticleFormat::VtkLegacy;
    if (endsWith(n, ".vtu") || endsWith(n, ".vtp")) return ParticleFormat::Vtu;
    if (endsWith(n, ".ply")) return ParticleFormat::Ply;
    if (endsWith(n, ".csv")) return ParticleFormat::Csv;
    if (endsWith(n, ".xyz") || endsWith(n, ".txt")) return ParticleFormat::Xyz;
    if (io_util::isHdf5Name(n)) return ParticleFormat::Hdf5;
    if (io_util::isNpzName(n)) return ParticleFormat::Npz;
    return ParticleFormat::Auto;
}

namespace io_util {

Result<std::vector<std::uint8_t>> readFileChecked(const std::filesystem::path& path, std::uint64_t maxBytes,
                                                  const std::function<Status(ByteView head)>& checkHead) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return makeError(path.string(), "no such file");
    if (std::filesystem::is_directory(path, ec)) return makeError(path.string(), "is a directory, not a file");
    // A device or a pipe has no size to read up to (/dev/zero never ends).
    if (!std::filesystem::is_regular_file(path, ec))
        return makeError(path.string(), "is not a regular file (a device or a pipe); give a file");
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) return makeError(path.string(), "cannot open for reading");
    const std::streamoff end = in.tellg();
    if (end < 0) return makeError(path.string(), "cannot determine file size");
    const std::uint64_t size = std::uint64_t(end);
    in.seekg(0);
    // The first bytes first: a file of the wrong kind is refused from its
    // signature, however large it is.
    std::vector<std::uint8_t> bytes(std::size_t(std::min<std::uint64_t>(size, kHeadBytes)));
    if (!bytes.empty() && !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size())))
        return makeError(path.string(), "read error");
    if (checkHead)
        if (auto ok = checkHead(ByteView(bytes.data(), bytes.size())); !ok) return ok.error();
    if (size > maxBytes)
        return makeError(path.string(), std::to_string(size) + " bytes, more than the limit of " +
                                            std::to_string(maxBytes) + " bytes for this kind of file");
    if (size == bytes.size()) return bytes;
    const std::size_t head = bytes.size();
    try {
        bytes.resize(std::size_t(size));
    } catch (const std::bad_alloc&) {
        return makeError(path.string(), "file too large to read into memory");
    }
    if (!in.read(reinterpret_cast<char*>(bytes.data() + head), std::streamsize(size - head)))
        return makeError(path.string(), "read error");
    return bytes;
}

Status checkParticleHead(ByteView head, const std::string& name, ParticleFormat format) {
    if (format == ParticleFormat::Auto) format = formatFromName(name);
    if (format == ParticleFormat::Auto) format = formatFromContent(head);
    auto startsWith = [&](ByteView data, std::string_view magic) {
        return data.size() >= magic.size() &&
               std::equal(magic.begin(), magic.end(), data.begin(),
                          [](char m, std::uint8_t b) { return static_cast<std::uint8_t>(m) == b; });
    };
    // Text after a UTF-8 byte order mark and blanks (XML, PLY).
    ByteView text = head;
    if (startsWith(text, "\xEF\xBB\xBF")) text = text.subspan(3);
    while (!text.empty() && (text[0] == ' ' || text[0] == '\t' || text[0] == '\r' || text[0] == '\n'))
        text = text.subspan(1);
    if (head.empty()) return okStatus();  // the parser says "file is empty"
    switch (format) {
        case ParticleFormat::Bgeo:
            if (startsWith(head, "\x1f\x8b") || startsWith(head, "Bgeo") || startsWith(head, "\x7fNSJ") ||
                (head.size() < 4 && std::equal(head.begin(), head.end(), "Bgeo")))
                return okStatus();
            return makeError(name, "not a BGEO file (bad magic: expected 'Bgeo' or gzip data)");
        case ParticleFormat::VtkLegacy: {
            static constexpr std::string_view magic = "# vtk DataFile";
            const std::size_t n = std::min(head.size(), magic.size());
            if (std::equal(head.begin(), head.begin() + std::ptrdiff_t(n), magic.begin())) return okStatus();
            return makeError(name, "bad magic: not a legacy VTK file (expected '# vtk DataFile Version' on line 1)");
        }
        case ParticleFormat::Vtu:
            if (!text.empty() && text[0] == '<') return okStatus();
            return makeError(name, "not a VTKFile (not VTK XML: the file does not start with '<')");
        case ParticleFormat::Ply: {
            while (!text.empty() && (text[0] == ' ' || text[0] == '\t')) text = text.subspan(1);
            if (startsWith(text, "ply") &&
                (text.size() == 3 || text[3] == ' ' || text[3] == '\t' || text[3] == '\r' || text[3] == '\n'))
                return okStatus();
            return makeError(name, "not a PLY file: the first line is not 'ply'");
        }
        case ParticleFormat::Csv:
        case ParticleFormat::Xyz:
            for (std::size_t i = 0; i < head.size(); ++i)
                if (head[i] == 0)
                    return makeError(name, "not a text file (a NUL byte at offset " + std::to_string(i) + ")");
            return okStatus();
        case ParticleFormat::Hdf5:
            // The signature may follow a user block (at 512, 1024, 2048, ...
            // bytes, past the first bytes read here): the HDF5 reader checks it.
            return okStatus();
        case ParticleFormat::Npz:
            if (startsWith(head, "PK\x03\x04") || startsWith(head, "PK\x05\x06")) return okStatus();
            return makeError(name, "not a readable .npz (zip) archive (bad magic: expected 'PK')");
        case ParticleFormat::Auto: break;
    }
    return makeError(name, "unknown particle file format (expected .bgeo, .vtk, .vtu, .vtp, .ply, .csv, .xyz, "
                           ".h5part, .h5, .hdf5 or .npz)");
}

}  // namespace io_util

Result<std::vector<std::uint8_t>> readFileBytes(const std::filesystem::path& path) {
    return io_util::readFileChecked(path, std::numeric_limits<std::uint64_t>::max(), nullptr);
}

Result<ParticleSet> parseParticles(ByteView data, const std::string& name, ParticleFormat format, bool allowEmpty) {
    if (format == ParticleFormat::Auto) format = formatFromName(name);
    if (format == ParticleFormat::Auto) format = formatFromContent(data);
    if (data.empty()) return makeError(name, "file is empty");

    Result<ParticleSet> parsed = [&]() -> Result<ParticleSet> {
        switch (format) {
            case ParticleFormat::Bgeo: return parseBgeo(data, name);
            case ParticleFormat::VtkLegacy: return parseVtkLegacy(data, name);
            case ParticleFormat::Vtu: return parseVtu(data, name);
            case ParticleFormat::Ply: return parsePly(data, name);
            case ParticleFormat::Csv: return parseCsv(data, name);
            case ParticleFormat::Xyz: return parseXyz(data, name);
            case ParticleFormat::Hdf5: return parseHdf5(data, name);
            case ParticleFormat::Npz: return parseNpz(data, name);
            case ParticleFormat::Auto: break;
        }
        return makeError(name, "unknown particle file format (expected .bgeo, .vtk, .vtu, .vtp, .ply, .csv, .xyz, "
                               ".h5part, .h5, .hdf5 or .npz)");
    }();
    return finishParticles(std::move(parsed), name, allowEmpty);
}

Result<ParticleSet> readParticles(const std::filesystem::path& path, ParticleFormat format, bool allowEmpty) {
    const std::string name = path.string();
    // A frame inside a container: run.h5part/Step#3, out_100.hdf5/fluid, out.npz/fluid.
    if (const auto inside = io_util::splitContainerPath(path)) {
        if (io_util::isNpzName(inside->file.filename().string())) {
            auto bytes = io_util::readFileChecked(inside->file, io_util::kMaxParticleFileBytes, [&](ByteView head) {
                return io_util::checkParticleHead(head, inside->file.string(), ParticleFormat::Npz);
            });
            if (!bytes) return bytes.error();
            return finishParticles(parseNpz(bytes.value(), name, inside->inner), name, allowEmpty);
        }
        return finishParticles(io_util::readHdf5File(inside->file, inside->inner, name), name, allowEmpty);
    }
    // HDF5 files are opened where they are: an H5Part file may hold a long
    // sequence, of which one step is read.
    if ((format == ParticleFormat::Auto ? formatFromName(name) : format) == ParticleFormat::Hdf5) {
        std::error_code ec;
        if (std::filesystem::is_regular_file(path, ec))
            return finishParticles(io_util::readHdf5File(path, "", name), name, allowEmpty);
    }
    auto bytes = io_util::readFileChecked(path, io_util::kMaxParticleFileBytes,
                                          [&](ByteView head) { return io_util::checkParticleHead(head, name, format); });
    if (!bytes) return bytes.error();
    return parseParticles(bytes.value(), path.string(), format, allowEmpty);
}

}  // namespace meniscus
