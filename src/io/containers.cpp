// Paths into container files (containers.h, io.h): run.h5part/Step#3,
// out_100.hdf5/fluid, out.npz/fluid.
#include "io/containers.h"

#include <algorithm>
#include <cstring>

#include "io/io_util.h"
#include "meniscus/io.h"

namespace meniscus {

namespace fs = std::filesystem;

namespace io_util {

namespace {
// An inner path has at most this many parts (particles/fluid is two).
constexpr int kMaxInnerParts = 4;
}  // namespace

bool isHdf5Name(std::string_view fileName) {
    const std::string n = lower(fileName);
    return endsWith(n, ".h5part") || endsWith(n, ".h5") || endsWith(n, ".hdf5");
}

bool isNpzName(std::string_view fileName) { return endsWith(lower(fileName), ".npz"); }

bool hasHdf5Signature(ByteView data) {
    // HDF5 File Format Specification, "Format Signature": at 0, 512, 1024,
    // 2048, ... (after a user block).
    static constexpr std::uint8_t kSignature[] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
    for (std::size_t at = 0; at + sizeof kSignature <= data.size(); at = at == 0 ? 512 : at * 2)
        if (std::memcmp(data.data() + at, kSignature, sizeof kSignature) == 0) return true;
    return false;
}

std::optional<ContainerPath> splitContainerPath(const fs::path& path) {
    std::error_code ec;
    if (fs::is_regular_file(path, ec)) return std::nullopt;
    fs::path file = path;
    std::vector<std::string> rest;
    while (file.has_filename() && int(rest.size()) < kMaxInnerParts) {
        rest.push_back(file.filename().string());
        file = file.parent_path();
        if (file.empty()) break;
        if (isContainerName(file.filename().string()) && fs::is_regular_file(file, ec)) {
            std::string inner;
            for (auto it = rest.rbegin(); it != rest.rend(); ++it) inner += (inner.empty() ? "" : "/") + *it;
            return ContainerPath{file, inner};
        }
    }
    return std::nullopt;
}

}  // namespace io_util

Result<std::vector<ParticleArrayInfo>> listParticleArrays(const fs::path& path) {
    const std::string name = path.filename().string();
    if (io_util::isNpzName(name)) return io_util::listNpzParticleArrays(path);
    if (io_util::isHdf5Name(name)) return io_util::listHdf5ParticleArrays(path);
    return makeError(path.string(), "not a PySPH .hdf5 or .npz file (by its name)");
}

long frameNumberOf(const fs::path& framePath) {
    // Lexically: the first part of the path (not the last) named like a
    // container is the file; what follows is inside it.
    std::vector<std::string> parts;
    for (const fs::path& part : framePath) parts.push_back(part.string());
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
        if (!io_util::isContainerName(parts[i])) continue;
        const std::string& inner = parts.back();
        if (inner.rfind("Step#", 0) == 0) return frameNumberFromName(inner);  // an H5Part step
        return frameNumberFromName(parts[i]);                                 // a particle array: the file's number
    }
    return frameNumberFromName(framePath.filename().string());
}

}  // namespace meniscus
