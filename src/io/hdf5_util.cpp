// The HDF5 C API as the particle readers use it (hdf5_util.h), and the public
// entry points for HDF5 particle files (io.h): parseHdf5, the H5Part step and
// PySPH array listings, reading a file from the disk. Without HDF5 in the
// build (MENISCUS_HAVE_HDF5 unset) each of them says so.
#include <cmath>
#include <algorithm>
#include <cstring>
#include <limits>

#include "io/containers.h"
#include "io/io_util.h"
#include "meniscus/io.h"

#if MENISCUS_HAVE_HDF5
#include "io/hdf5_util.h"

namespace meniscus::io_util::h5 {

namespace {

std::mutex& libraryMutex() {
    static std::mutex m;
    return m;
}

// Datasets may be compressed (PySPH writes gzip level 9); deflate's largest
// ratio is about 1032:1, so more than this many bytes per stored byte is a
// header claiming data that is not there.
constexpr std::uint64_t kMaxCompressionRatio = 1100;
// No single dataset (or chunk) of a particle file needs more; larger claims
// are refused before HDF5 allocates for them.
constexpr std::uint64_t kMaxChunkBytes = std::uint64_t(64) << 20;
constexpr std::uint64_t kMaxLength = std::uint64_t(1) << 40;
constexpr std::size_t kMaxLinks = 1'000'000;

herr_t closeAny(hid_t id) {
    switch (H5Iget_type(id)) {
        case H5I_FILE: return H5Fclose(id);
        case H5I_GROUP: return H5Gclose(id);
        case H5I_DATASET: return H5Dclose(id);
        case H5I_DATASPACE: return H5Sclose(id);
        case H5I_DATATYPE: return H5Tclose(id);
        case H5I_ATTR: return H5Aclose(id);
        case H5I_GENPROP_LST: return H5Pclose(id);
        default: return H5Idec_ref(id);
    }
}

herr_t collectError(unsigned n, const H5E_error2_t* err, void* data) {
    auto* out = static_cast<std::vector<std::string>*>(data);
    if (err && err->desc && *err->desc) out->push_back(err->desc);
    return 0;
}

struct LinkList {
    std::vector<std::string> names;
    bool tooMany = false;
};

herr_t collectLink(hid_t, const char* name, const H5L_info_t* info, void* data) {
    auto* out = static_cast<LinkList*>(data);
    if (out->names.size() >= kMaxLinks) {
        out->tooMany = true;
        return 1;  // stop
    }
    if (info && info->type == H5L_TYPE_HARD) out->names.emplace_back(name);
    return 0;
}

bool isPlainName(const std::string& name) {
    return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
           name.find('\0') == std::string::npos;
}

// The kind of object a hard link `name` in `group` leads to (H5I_BADID when
// none, or not a hard link).
H5I_type_t objectKind(hid_t group, const std::string& name) {
    if (!isPlainName(name) || H5Lexists(group, name.c_str(), H5P_DEFAULT) <= 0) return H5I_BADID;
    H5L_info_t info;
    if (H5Lget_info(group, name.c_str(), &info, H5P_DEFAULT) < 0 || info.type != H5L_TYPE_HARD) return H5I_BADID;
    Handle obj(H5Oopen(group, name.c_str(), H5P_DEFAULT));
    return obj.valid() ? H5Iget_type(obj.get()) : H5I_BADID;
}

std::string withHdf5Reason(std::string message) {
    const std::string why = lastError();
    return why.empty() ? message : message + " (HDF5: " + why + ")";
}

DatasetInfo inspectOpen(hid_t dset) {
    DatasetInfo info;
    Handle space(H5Dget_space(dset));
    Handle type(H5Dget_type(dset));
    if (!space.valid() || !type.valid()) {
        info.why = withHdf5Reason("its shape or type cannot be read");
        return info;
    }
    const H5S_class_t shape = H5Sget_simple_extent_type(space.get());
    if (shape == H5S_NULL) {
        info.length = 0;
    } else if (shape == H5S_SIMPLE && H5Sget_simple_extent_ndims(space.get()) == 1) {
        hsize_t dims[1] = {0};
        if (H5Sget_simple_extent_dims(space.get(), dims, nullptr) != 1) {
            info.why = withHdf5Reason("its shape cannot be read");
            return info;
        }
        info.length = dims[0];
    } else {
        const int n = shape == H5S_SIMPLE ? H5Sget_simple_extent_ndims(space.get()) : 0;
        info.why = shape == H5S_SCALAR ? "it is a single value, not one per particle"
                                       : "it has " + std::to_string(n) + " dimensions, not one value per particle";
        return info;
    }
    const H5T_class_t cls = H5Tget_class(type.get());
    const std::size_t size = H5Tget_size(type.get());
    if (cls == H5T_INTEGER && size >= 1 && size <= 8) {
        info.isInt = true;
    } else if (cls == H5T_FLOAT && size >= 2 && size <= 16) {
        info.isInt = false;
    } else {
        static const char* kNames[] = {"integer", "floating point", "time", "string", "bitfield", "opaque",
                                       "compound", "reference", "enum (or bool)", "variable-length", "array"};
        const char* what = cls >= 0 && cls < H5T_NCLASSES ? kNames[cls] : "unknown";
        info.why = std::string("its type (") + what + ", " + std::to_string(size) +
                   " bytes) is not a number type meniscus reads (integers, float32, float64)";
        return info;
    }
    if (info.length > kMaxLength) {
        info.why = "it declares " + std::to_string(info.length) + " values";
        return info;
    }
    info.supported = true;
    return info;
}

}  // namespace

Handle& Handle::operator=(Handle&& o) noexcept {
    if (this != &o) {
        if (valid()) closeAny(id_);
        id_ = o.id_;
        o.id_ = H5I_INVALID_HID;
    }
    return *this;
}

Handle::~Handle() {
    if (valid()) closeAny(id_);
}

Lock::Lock() : lock_(libraryMutex()) {
    static bool once = false;
    if (!once) {
        // Files from elsewhere must not make HDF5 load shared libraries.
        H5PLset_loading_state(0);
        once = true;
    }
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

Lock::~Lock() {
    H5Eclear2(H5E_DEFAULT);
    // HDF5 keeps freed blocks on its own free lists for reuse; give them
    // back, so reading a long sequence does not hold the largest frame's
    // metadata for good.
    H5garbage_collect();
}

std::string lastError() {
    std::vector<std::string> stack;
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, collectError, &stack);
    H5Eclear2(H5E_DEFAULT);
    // The deepest entry says what was wrong with the bytes; the top one what
    // the call was doing.
    return stack.empty() ? std::string() : stack.back();
}

File openFile(const std::string& path) {
#if H5_VERSION_GE(1, 12, 0)
    const htri_t isHdf5 = H5Fis_accessible(path.c_str(), H5P_DEFAULT);
#else
    const htri_t isHdf5 = H5Fis_hdf5(path.c_str());
#endif
    if (isHdf5 == 0) fail("not an HDF5 file (no HDF5 signature)");
    if (isHdf5 < 0) fail(withHdf5Reason("cannot open as an HDF5 file"));
    File f;
    f.file = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
    if (!f.file.valid()) fail(withHdf5Reason("cannot open as an HDF5 file"));
    hsize_t size = 0;
    if (H5Fget_filesize(f.file.get(), &size) < 0) fail(withHdf5Reason("cannot tell the HDF5 file's size"));
    f.size = size;
    return f;
}

File openImage(ByteView data) {
    if (!hasHdf5Signature(data)) fail("not an HDF5 file (no HDF5 signature)");
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
    // The core driver reads the file from memory; the image is copied, and
    // nothing is written back (no backing store).
    if (!fapl.valid() || H5Pset_fapl_core(fapl.get(), 1 << 16, 0) < 0 ||
        H5Pset_file_image(fapl.get(), const_cast<std::uint8_t*>(data.data()), data.size()) < 0)
        fail(withHdf5Reason("cannot open the HDF5 data in memory"));
    File f;
    f.file = Handle(H5Fopen("meniscus-memory.h5", H5F_ACC_RDONLY, fapl.get()));
    if (!f.file.valid()) fail(withHdf5Reason("cannot open as an HDF5 file"));
    f.size = data.size();
    return f;
}

std::vector<std::string> linkNames(hid_t group) {
    LinkList list;
    hsize_t index = 0;
    if (H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, &index, collectLink, &list) < 0)
        fail(withHdf5Reason("cannot list a group's members"));
    if (list.tooMany) fail("a group has more than " + std::to_string(kMaxLinks) + " members");
    return std::move(list.names);
}

bool hasGroup(hid_t group, const std::string& name) { return objectKind(group, name) == H5I_GROUP; }
bool hasDataset(hid_t group, const std::string& name) { return objectKind(group, name) == H5I_DATASET; }

Handle openGroup(hid_t group, const std::string& name, const std::string& where) {
    if (!hasGroup(group, name)) fail(where + "no group " + quoteShort(name));
    Handle g(H5Gopen2(group, name.c_str(), H5P_DEFAULT));
    if (!g.valid()) fail(withHdf5Reason(where + "cannot open group " + quoteShort(name)));
    return g;
}

DatasetInfo inspectDataset(hid_t group, const std::string& name) {
    Handle dset(H5Dopen2(group, name.c_str(), H5P_DEFAULT));
    if (!dset.valid()) {
        DatasetInfo info;
        info.why = withHdf5Reason("it cannot be opened");
        return info;
    }
    return inspectOpen(dset.get());
}

Column readColumn(const File& file, hid_t group, const std::string& name, const std::string& where) {
    const std::string what = where + "dataset " + quoteShort(name);
    Handle dset(H5Dopen2(group, name.c_str(), H5P_DEFAULT));
    if (!dset.valid()) fail(withHdf5Reason("cannot open " + what));
    const DatasetInfo info = inspectOpen(dset.get());
    if (!info.supported) fail(what + ": " + info.why);
    Handle type(H5Dget_type(dset.get()));
    Handle dcpl(H5Dget_create_plist(dset.get()));
    if (!type.valid() || !dcpl.valid()) fail(withHdf5Reason("cannot read how " + what + " is stored"));
    // Raw data in other files (external storage, virtual datasets) is never read.
    if (H5Pget_external_count(dcpl.get()) != 0) fail(what + " keeps its values in external files, which are not read");
    const H5D_layout_t layout = H5Pget_layout(dcpl.get());
    if (layout == H5D_VIRTUAL) fail(what + " is a virtual dataset (values from other files), which is not read");
    if (layout < 0) fail(withHdf5Reason("cannot read how " + what + " is stored"));

    const std::uint64_t bytes = info.length * H5Tget_size(type.get());
    const std::uint64_t storage = H5Dget_storage_size(dset.get());
    const int filters = H5Pget_nfilters(dcpl.get());
    auto tooBig = [&](const std::string& detail) {
        fail(what + " declares " + std::to_string(info.length) + " values (" + std::to_string(bytes) +
             " bytes) but " + detail + "; the file is damaged or truncated");
    };
    if (storage > file.size) tooBig("claims " + std::to_string(storage) + " bytes of storage in a file of " +
                                    std::to_string(file.size));
    if (layout == H5D_COMPACT) {
        if (bytes > 65536) tooBig("is stored compact, which holds at most 64 KiB");
    } else if (bytes > 0) {
        const std::uint64_t limit = filters > 0 ? storage * kMaxCompressionRatio + 65536 : storage;
        if (bytes > limit) tooBig("the file holds " + std::to_string(storage) + " bytes of it");
        if (layout == H5D_CONTIGUOUS) {
            const haddr_t offset = H5Dget_offset(dset.get());
            if (offset == HADDR_UNDEF || offset > file.size || bytes > file.size - offset)
                tooBig("its bytes are not inside the file");
        }
        if (layout == H5D_CHUNKED) {
            hsize_t chunk[1] = {0};
            if (H5Pget_chunk(dcpl.get(), 1, chunk) != 1) fail(withHdf5Reason("cannot read the chunks of " + what));
            const std::uint64_t chunkBytes = chunk[0] * H5Tget_size(type.get());
            if (chunk[0] > kMaxLength || (chunkBytes > kMaxChunkBytes && chunkBytes > bytes))
                fail(what + " has chunks of " + std::to_string(chunk[0]) + " values, more than it holds");
        }
    }

    Column c;
    c.name = name;
    c.isInt = info.isInt;
    herr_t status = 0;
    if (c.isInt) {
        c.ints.resize(std::size_t(info.length));
        if (info.length > 0)
            status = H5Dread(dset.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.ints.data());
    } else {
        c.floats.resize(std::size_t(info.length));
        if (info.length > 0)
            status = H5Dread(dset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.floats.data());
    }
    if (status < 0) fail(withHdf5Reason("cannot read " + what));
    return c;
}

double numberAttribute(hid_t object, const std::string& attribute, double fallback) {
    if (H5Aexists(object, attribute.c_str()) <= 0) return fallback;
    Handle attr(H5Aopen(object, attribute.c_str(), H5P_DEFAULT));
    if (!attr.valid()) return fallback;
    Handle space(H5Aget_space(attr.get()));
    Handle type(H5Aget_type(attr.get()));
    if (!space.valid() || !type.valid() || H5Sget_simple_extent_npoints(space.get()) != 1) return fallback;
    const H5T_class_t cls = H5Tget_class(type.get());
    if (cls != H5T_INTEGER && cls != H5T_FLOAT) return fallback;
    double v = fallback;
    if (H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &v) < 0) return fallback;
    return v;
}

}  // namespace meniscus::io_util::h5

namespace meniscus {

namespace {

using namespace io_util;

// H5Part or PySPH, by what the file holds.
ParticleSet readLayout(const h5::File& file, const std::string& inner, const std::string& name) {
    if (isPySph(file.file.get())) return readPySph(file, inner, name);
    if (isH5Part(file.file.get())) return readH5Part(file, inner, name);
    fail("HDF5 file holds neither H5Part steps (groups Step#0, Step#1, ...) nor PySPH output (a group "
         "'particles'); its top level has: " +
         listNames(h5::linkNames(file.file.get())));
}

}  // namespace

bool particleFormatAvailable(ParticleFormat format) {
#if !MENISCUS_HAVE_LIBZIP
    if (format == ParticleFormat::Npz) return false;
#endif
    return true;
}

Result<ParticleSet> parseHdf5(ByteView data, const std::string& name, const std::string& inner) {
    return guardParse(name, "HDF5", [&]() -> Result<ParticleSet> {
        h5::Lock lock;
        const h5::File file = h5::openImage(data);
        return readLayout(file, inner, name);
    });
}

Result<ParticleSet> io_util::readHdf5File(const std::filesystem::path& path, const std::string& inner,
                                          const std::string& name) {
    return guardParse(name, "HDF5", [&]() -> Result<ParticleSet> {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec)) fail("no such file");
        if (std::filesystem::file_size(path, ec) == 0 && !ec) fail("file is empty");
        h5::Lock lock;
        const h5::File file = h5::openFile(path.string());
        return readLayout(file, inner, name);
    });
}

namespace {

// `read` of the open H5Part file at `path`, its errors naming the file.
template <class T, class F>
Result<T> withH5PartFile(const std::filesystem::path& path, F&& read) {
    const std::string name = path.string();
    try {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec)) return makeError(name, "no such file");
        h5::Lock lock;
        const h5::File file = h5::openFile(name);
        return read(file.file.get());
    } catch (const io_util::ParseFailure& f) {
        return makeError(name, f.message);
    } catch (const std::exception& e) {
        return makeError(name, std::string("cannot read HDF5 data: ") + e.what());
    }
}

}  // namespace

Result<std::vector<std::string>> listH5PartSteps(const std::filesystem::path& path) {
    return withH5PartFile<std::vector<std::string>>(path, [](hid_t file) {
        std::vector<std::string> steps;
        for (auto& s : h5partSteps(file)) steps.push_back(std::move(s.first));
        return steps;
    });
}

Result<std::vector<double>> h5partStepTimes(const std::filesystem::path& path) {
    return withH5PartFile<std::vector<double>>(path, [](hid_t file) {
        std::vector<double> times;
        for (const auto& step : h5partSteps(file)) {
            h5::Handle group = h5::openGroup(file, step.first, "");
            // ParaView's H5Part reader reads "TimeValue"; other writers say "time" or "Time".
            double t = NAN;
            for (const char* key : {"TimeValue", "time", "Time"})
                if (std::isnan(t)) t = h5::numberAttribute(group.get(), key, NAN);
            if (std::isnan(t)) return std::vector<double>{};  // one step without a time: none
            times.push_back(t);
        }
        return times;
    });
}

Result<std::vector<ParticleArrayInfo>> io_util::listHdf5ParticleArrays(const std::filesystem::path& path) {
    const std::string name = path.string();
    try {
        h5::Lock lock;
        const h5::File file = h5::openFile(name);
        std::vector<ParticleArrayInfo> out;
        if (!isPySph(file.file.get())) return out;
        for (auto& [array, count] : pysphArrays(file.file.get())) out.push_back({array, std::size_t(count)});
        return out;
    } catch (const io_util::ParseFailure& f) {
        return makeError(name, f.message);
    } catch (const std::exception& e) {
        return makeError(name, std::string("cannot read HDF5 data: ") + e.what());
    }
}

}  // namespace meniscus

#else  // !MENISCUS_HAVE_HDF5

namespace meniscus {

namespace {
const char* const kNoHdf5 =
    "built without HDF5 support, so H5Part and PySPH .hdf5 files cannot be read (install libhdf5-dev and rebuild)";
}

bool particleFormatAvailable(ParticleFormat format) {
    if (format == ParticleFormat::Hdf5) return false;
#if !MENISCUS_HAVE_LIBZIP
    if (format == ParticleFormat::Npz) return false;
#endif
    return true;
}

Result<ParticleSet> parseHdf5(ByteView, const std::string& name, const std::string&) {
    return makeError(name, kNoHdf5);
}

Result<ParticleSet> io_util::readHdf5File(const std::filesystem::path&, const std::string&, const std::string& name) {
    return makeError(name, kNoHdf5);
}

Result<std::vector<std::string>> listH5PartSteps(const std::filesystem::path& path) {
    return makeError(path.string(), kNoHdf5);
}

Result<std::vector<double>> h5partStepTimes(const std::filesystem::path& path) {
    return makeError(path.string(), kNoHdf5);
}

Result<std::vector<ParticleArrayInfo>> io_util::listHdf5ParticleArrays(const std::filesystem::path& path) {
    return makeError(path.string(), kNoHdf5);
}

}  // namespace meniscus

#endif  // MENISCUS_HAVE_HDF5
