// Files that hold more than one frame or particle array (internal to src/io):
// H5Part (a whole sequence, one Step#N group per frame), PySPH output (.hdf5
// and .npz: one particle array per body: fluid, boundary, ...) and plain
// .npz files. A frame inside such a file is named by a path into it, HDF5
// style (io.h): run.h5part/Step#3, dam_break_2d_100.hdf5/fluid, out.npz/fluid.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "meniscus/io.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus::io_util {

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
