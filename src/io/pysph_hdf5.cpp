// PySPH's HDF5 output (.hdf5): what pysph.solver.utils.dump writes by
// default (pysph/solver/output.py, HDFOutput._dump), one file per output step
// (dam_break_2d_100.hdf5):
//   /solver_data                  attributes t, dt, count
//   /particles/<array>/constants  one dataset per constant of the array
//   /particles/<array>/arrays/<prop>
//                                 one 1-D dataset per property (x, y, z, u, v,
//                                 w, rho, h, m, p, gid, pid, tag, ...), gzip
//                                 level 9, with attributes name, type,
//                                 default, stride and stored; a property the
//                                 run did not output (stored = False) is an
//                                 empty dataset.
// `<array>` is each particle array of the run: "fluid", "boundary", "solid",
// ... A frame is one array (io.h): `out.hdf5/fluid` (or
// `out.hdf5/particles/fluid`); without a name, the array called "fluid",
// else the first (by name) that has particles.
//
// A property with stride k (k values per particle) becomes an attribute of k
// components. A 2-D run often does not store z (nor w): an unstored position
// (or velocity component, when another one is stored) is the property's
// `default` attribute (0) for every particle. Names go
// through the shared alias table (column_set.h): u v w -> velocity, rho ->
// density; h, the smoothing length, is kept as "h", which
// addRadiusFromSmoothingLength (particles.h) turns into radii.
#if MENISCUS_HAVE_HDF5

#include <algorithm>
#include <array>
#include <cmath>

#include "io/hdf5_util.h"
#include "io/io_util.h"

namespace meniscus::io_util {

namespace {

constexpr const char* kPositionNames[] = {"x", "y", "z"};
constexpr std::array<const char*, 3> kTriples[] = {{"x", "y", "z"}, {"u", "v", "w"}};
constexpr int kMaxStride = 64;

// The particle count of an array: the length of its stored x (0 when none).
std::uint64_t arrayCount(hid_t particles, const std::string& array) {
    if (!h5::hasGroup(particles, array)) return 0;
    h5::Handle group(H5Gopen2(particles, array.c_str(), H5P_DEFAULT));
    if (!group.valid() || !h5::hasGroup(group.get(), "arrays")) return 0;
    h5::Handle arrays(H5Gopen2(group.get(), "arrays", H5P_DEFAULT));
    if (!arrays.valid()) return 0;
    std::uint64_t count = 0;
    for (const char* p : kPositionNames)
        if (h5::hasDataset(arrays.get(), p)) count = std::max(count, h5::inspectDataset(arrays.get(), p).length);
    return count;
}

}  // namespace

bool isPySph(hid_t file) { return h5::hasGroup(file, "particles"); }

std::vector<std::pair<std::string, std::uint64_t>> pysphArrays(hid_t file) {
    std::vector<std::pair<std::string, std::uint64_t>> out;
    h5::Handle particles(H5Gopen2(file, "particles", H5P_DEFAULT));
    if (!particles.valid()) return out;
    for (std::string& n : h5::linkNames(particles.get()))
        if (h5::hasGroup(particles.get(), n)) out.emplace_back(n, arrayCount(particles.get(), n));
    return out;
}

ParticleSet readPySph(const h5::File& file, const std::string& innerPath, const std::string& name) {
    h5::Handle particles = h5::openGroup(file.file.get(), "particles", "PySPH file: ");
    const auto arrays = pysphArrays(file.file.get());
    std::vector<std::string> arrayNames;
    for (const auto& a : arrays) arrayNames.push_back(a.first);
    if (arrays.empty()) fail("PySPH file has no particle arrays (its group 'particles' is empty)");

    std::vector<std::string> warnings;
    std::string chosen;
    std::string inner = innerPath;
    if (inner.rfind("particles/", 0) == 0) inner = inner.substr(10);
    if (!inner.empty()) {
        if (std::find(arrayNames.begin(), arrayNames.end(), inner) == arrayNames.end())
            fail("PySPH file has no particle array " + quoteShort(inner) + " (it has " + listNames(arrayNames) + ")");
        chosen = inner;
    } else if (std::find(arrayNames.begin(), arrayNames.end(), "fluid") != arrayNames.end()) {
        chosen = "fluid";
    } else {
        std::vector<std::string> withParticles;
        for (const auto& [n, count] : arrays)
            if (count > 0) withParticles.push_back(quoteShort(n) + " (" + std::to_string(count) + ")");
        const auto first = std::find_if(arrays.begin(), arrays.end(), [](const auto& a) { return a.second > 0; });
        chosen = first != arrays.end() ? first->first : arrays.front().first;
        if (withParticles.size() > 1)
            warnings.push_back(name + ": PySPH particle arrays " + joinNames(withParticles) + " and none named 'fluid': read " +
                               quoteShort(chosen) + " (name another as " + name + "/NAME)");
    }
    const std::string where = "particle array " + quoteShort(chosen) + ": ";
    h5::Handle array = h5::openGroup(particles.get(), chosen, "PySPH file: ");
    h5::Handle props = h5::openGroup(array.get(), "arrays", where);

    // The particle count: the longest of x, y, z (an unstored one is empty).
    std::vector<std::string> names;
    for (std::string& n : h5::linkNames(props.get()))
        if (h5::hasDataset(props.get(), n)) names.push_back(std::move(n));
    std::uint64_t count = 0;
    bool anyPosition = false;
    for (const char* p : kPositionNames)
        if (std::find(names.begin(), names.end(), p) != names.end()) {
            anyPosition = true;
            count = std::max(count, h5::inspectDataset(props.get(), p).length);
        }
    if (!anyPosition) fail(where + "no property x, y or z; it has: " + listNames(names));

    std::vector<Column> columns;
    for (const std::string& n : names) {
        const h5::DatasetInfo info = h5::inspectDataset(props.get(), n);
        const bool isPosition = n == "x" || n == "y" || n == "z";
        if (!info.supported) {
            if (isPosition) fail(where + "property " + quoteShort(n) + ": " + info.why);
            warnings.push_back(name + ": property " + quoteShort(n) + " skipped: " + info.why);
            continue;
        }
        if (info.length == 0 && count > 0) continue;  // not stored (stored = False)
        h5::Handle dset(H5Dopen2(props.get(), n.c_str(), H5P_DEFAULT));
        const double strideValue = dset.valid() ? h5::numberAttribute(dset.get(), "stride", 1.0) : 1.0;
        if (!(strideValue >= 1.0 && strideValue <= kMaxStride && std::floor(strideValue) == strideValue))
            fail(where + "property " + quoteShort(n) + " has a stride of " + std::to_string(strideValue));
        const int stride = isPosition ? 1 : int(strideValue);
        if (info.length != count * std::uint64_t(stride))
            fail(where + "property " + quoteShort(n) + " has " + std::to_string(info.length) + " values for " +
                 std::to_string(count) + " particles" + (stride > 1 ? " of stride " + std::to_string(stride) : "") +
                 " (x, y, z have " + std::to_string(count) + ")");
        Column c = h5::readColumn(file, props.get(), n, where);
        c.components = stride;
        columns.push_back(std::move(c));
    }
    // A position or velocity component PySPH did not store (z and w of a 2-D
    // run) is its default value, so the triple is whole.
    for (const auto& triple : kTriples) {
        const auto stored = [&](const char* p) {
            return std::any_of(columns.begin(), columns.end(), [&](const Column& c) { return c.name == p; });
        };
        if (std::string_view(triple[0]) != "x" && !std::any_of(triple.begin(), triple.end(), stored)) continue;
        for (const char* p : triple) {
            if (stored(p)) continue;
            double fallback = 0.0;
            if (h5::hasDataset(props.get(), p)) {
                h5::Handle dset(H5Dopen2(props.get(), p, H5P_DEFAULT));
                if (dset.valid()) fallback = h5::numberAttribute(dset.get(), "default", 0.0);
            }
            Column c;
            c.name = p;
            c.floats.assign(std::size_t(count), fallback);
            columns.push_back(std::move(c));
        }
    }
    ParticleSet set = particlesFromColumns(std::move(columns), std::size_t(count), where + "no positions");
    set.warnings = std::move(warnings);
    return set;
}

}  // namespace meniscus::io_util

#endif  // MENISCUS_HAVE_HDF5
