// Files that hold more than one frame or particle array (internal to src/io):
// H5Part (a whole sequence, one Step#N group per frame), PySPH output (.hdf5
// and .npz: one particle array per body: fluid, boundary, ...) and plain
// .npz files. A frame inside such a file is named by a path into it, HDF5
// style (io.h): run.h5part/Step#3, dam_break_2d_100.hdf5/fluid, out.npz/fluid.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "meniscus/io.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus::io_util {

// The most a particle file may hold to be read into memory whole: as much as
// a .bgeo.gz may inflate to (gzip.cpp); any larger file is refused unread.
inline constexpr std::uint64_t kMaxParticleFileBytes = std::uint64_t(4) << 30;  // 4 GiB
// The most a ParaView collection (.pvd, an index of file names) may hold.
inline constexpr std::uint64_t kMaxPvdFileBytes = std::uint64_t(64) << 20;  // 64 MiB
// How much of a file readFileChecked reads first, for its signature.
inline constexpr std::size_t kHeadBytes = 4096;

// A file read into memory whole, checked from its first bytes: the first
// kHeadBytes (or fewer, in a smaller file) go to `checkHead`, whose error is
// returned before anything more is read, and a file over `maxBytes` is
// refused unread. Errors name the file.
Result<std::vector<std::uint8_t>> readFileChecked(const std::filesystem::path& path, std::uint64_t maxBytes,
                                                  const std::function<Status(ByteView head)>& checkHead);

// The first bytes of a particle file checked against its format: the magic
// of a binary format, XML for .vtu/.vtp, 'ply' on the first line, text (no
// NUL byte) for .csv and .xyz. Auto: known by `head` or refused.
Status checkParticleHead(ByteView head, const std::string& name, ParticleFormat format);

// By extension, any case: .h5part, .h5, .hdf5 (HDF5) and .npz.
bool isHdf5Name(std::string_view fileName);
bool isNpzName(std::string_view fileName);
inline bool isContainerName(std::string_view fileName) { return isHdf5Name(fileName) || isNpzName(fileName); }

// The HDF5 signature ("\x89HDF\r\n\x1a\n") at the start, or at 512, 1024,
// 2048, ... as a user block moves it, within `data`.
bool hasHdf5Signature(ByteView data);

// A path into a container: `file` is an existing regular file with a
// container name and `inner` the rest ("Step#3", "fluid", "particles/fluid").
struct ContainerPath {
    std::filesystem::path file;
    std::string inner;
};
// The split of `path` when a leading part of it is such a file (and `path`
// itself is not a file), else nullopt. Touches the disk.
std::optional<ContainerPath> splitContainerPath(const std::filesystem::path& path);

// An HDF5 particle file read from the disk (H5Part or PySPH by content),
// without reading the whole file into memory; `name` names it in messages.
// src/io/hdf5_util.cpp; without HDF5 an error saying so.
Result<ParticleSet> readHdf5File(const std::filesystem::path& path, const std::string& inner, const std::string& name);

// The particle arrays of a PySPH .hdf5 file (none for H5Part) and of an .npz
// (PySPH's, or the bodies "NAME/x" of a plain one); listParticleArrays (io.h)
// picks by name.
Result<std::vector<ParticleArrayInfo>> listHdf5ParticleArrays(const std::filesystem::path& path);
Result<std::vector<ParticleArrayInfo>> listNpzParticleArrays(const std::filesystem::path& path);

}  // namespace meniscus::io_util
