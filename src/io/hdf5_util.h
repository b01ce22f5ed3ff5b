// The HDF5 C API as the HDF5 particle readers use it (internal to src/io;
// only compiled with MENISCUS_HAVE_HDF5): handles closed by RAII, one lock
// around every use of the library, HDF5's own error printing silenced and its
// error stack turned into our messages, and datasets read with their declared
// size checked against the bytes the file really holds before anything is
// allocated.
//
// Safety rules for files from elsewhere: only hard links are followed (an
// external link would open another file), and datasets whose raw data lives
// in external files or virtual (VDS) mappings are refused, so reading a file
// never reads another one. Filter plugins are not loaded (gzip, shuffle and
// the other built-in filters work; PySPH uses gzip).
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "io/column_set.h"
#include "meniscus/types.h"

namespace meniscus::io_util::h5 {

// A handle of any HDF5 kind (file, group, dataset, dataspace, type, plist,
// attribute), closed with H5Idec_ref... through the matching close call.
class Handle {
public:
    Handle() = default;
    explicit Handle(hid_t id) : id_(id) {}
    Handle(Handle&& o) noexcept : id_(o.id_) { o.id_ = H5I_INVALID_HID; }
    Handle& operator=(Handle&& o) noexcept;
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    ~Handle();
    hid_t get() const { return id_; }
    bool valid() const { return id_ >= 0; }

private:
    hid_t id_ = H5I_INVALID_HID;
};

// Held for every call into HDF5 (the library is not thread-safe in every
// build, and its error stack and auto-printing are per thread at best).
// Construction silences HDF5's automatic error printing for this thread.
class Lock {
public:
    Lock();
    ~Lock();

private:
    std::unique_lock<std::mutex> lock_;
};

// HDF5's own explanation of the last failure on this thread ("" when its
// error stack is empty), e.g. "file signature not found"; clears the stack.
std::string lastError();

// A file opened read-only, from the disk or from bytes in memory (the core
// driver with a file image), with the size of its bytes.
struct File {
    Handle file;
    std::uint64_t size = 0;
};
// Errors throw ParseFailure (io_util::fail) with a message for `name`.
File openFile(const std::string& path);
File openImage(ByteView data);

// The names of the links in `group`, in name order, following only hard
// links: soft, external and user-defined links are left out.
std::vector<std::string> linkNames(hid_t group);
// True when `name` is a hard link in `group` to an object of that kind.
bool hasGroup(hid_t group, const std::string& name);
bool hasDataset(hid_t group, const std::string& name);
Handle openGroup(hid_t group, const std::string& name, const std::string& where);

// What a one-dimensional numeric dataset holds, without reading it.
struct DatasetInfo {
    bool supported = false;  // 1-D (or scalar), integer or floating point
    std::string why;         // when not: the type or shape, for a message
    bool isInt = false;
    std::uint64_t length = 0;
};
DatasetInfo inspectDataset(hid_t group, const std::string& name);

// Reads a dataset that inspectDataset called supported, as `components`
// values per particle. Throws (fail) naming it and `where` when its declared
// size is more than the file can hold (uncompressed: its storage; compressed:
// 1100 times its storage, past deflate's largest ratio), when its raw data
// lives outside the file, or when HDF5 cannot read it.
Column readColumn(const File& file, hid_t group, const std::string& name, const std::string& where);

// A numeric attribute of an object as double; `fallback` when it is missing
// or not a number.
double numberAttribute(hid_t object, const std::string& attribute, double fallback);

}  // namespace meniscus::io_util::h5

namespace meniscus::io_util {

// The layouts an HDF5 particle file may have (src/io/h5part.cpp,
// src/io/pysph_hdf5.cpp), given an open file. `inner`: the part of a frame
// path after the file ("Step#3", "fluid"; "" for the default). `name`: for
// messages. Errors throw ParseFailure.
bool isH5Part(hid_t file);
bool isPySph(hid_t file);
ParticleSet readH5Part(const h5::File& file, const std::string& inner, const std::string& name);
ParticleSet readPySph(const h5::File& file, const std::string& inner, const std::string& name);
// H5Part steps in numeric order: ("Step#0", 0), ("Step#1", 1), ...
std::vector<std::pair<std::string, long long>> h5partSteps(hid_t file);
// PySPH's particle arrays: name and particle count (0 when it has no x).
std::vector<std::pair<std::string, std::uint64_t>> pysphArrays(hid_t file);

}  // namespace meniscus::io_util
