// H5Part particle files (.h5part, .h5): one HDF5 file holding a whole
// sequence. Layout (Bethel et al., "H5Part: A Portable High Performance
// Parallel Data Interface for Particle Simulations", PAC 2005; the H5Part
// and H5hut file format): the root holds one group per time step, named
// "Step#" and the step number (H5PartSetStep; writers may zero-pad it,
// "Step#000012"), each holding one 1-D dataset per particle quantity, all of
// one length: x, y, z and whatever else the code writes (id, vx, vy, vz, px,
// py, pz, rho, h, ...), as float32/float64/int32/int64. Attributes of the file
// and the steps (TimeStep, time) are not needed for rendering.
//
// A frame is one step: `run.h5part/Step#3` (io.h). Datasets are matched by
// the shared alias table (column_set.h); one that is not a 1-D number array
// (a string, a compound) is skipped with a warning; a dataset whose length
// differs from the positions' is an error, as H5Part gives every dataset of a
// step one value per particle.
#if MENISCUS_HAVE_HDF5

#include <algorithm>
#include <charconv>

#include "io/attribute_names.h"
#include "io/hdf5_util.h"
#include "io/io_util.h"

namespace meniscus::io_util {

namespace {

constexpr std::string_view kStepPrefix = "Step#";

// The step number of a root member's name, or -1 when it is no step.
long long stepNumber(std::string_view name) {
    if (name.substr(0, kStepPrefix.size()) != kStepPrefix) return -1;
    const std::string_view digits = name.substr(kStepPrefix.size());
    if (digits.empty() || digits.size() > 18 ||
        !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return -1;
    long long n = 0;
    std::from_chars(digits.data(), digits.data() + digits.size(), n);
    return n;
}

std::string stepRange(const std::vector<std::pair<std::string, long long>>& steps) {
    if (steps.size() == 1) return "1 step, " + steps.front().first;
    return std::to_string(steps.size()) + " steps, " + steps.front().first + " .. " + steps.back().first;
}

}  // namespace

std::vector<std::pair<std::string, long long>> h5partSteps(hid_t file) {
    std::vector<std::pair<std::string, long long>> steps;
    for (std::string& n : h5::linkNames(file))
        if (const long long k = stepNumber(n); k >= 0) steps.emplace_back(std::move(n), k);
    // Numeric order (name order would put Step#10 before Step#2); the same
    // number twice (Step#1, Step#01): by name.
    std::sort(steps.begin(), steps.end(), [](const auto& a, const auto& b) {
        return a.second != b.second ? a.second < b.second : a.first < b.first;
    });
    return steps;
}

bool isH5Part(hid_t file) {
    for (const std::string& n : h5::linkNames(file))
        if (stepNumber(n) >= 0) return true;
    return false;
}

ParticleSet readH5Part(const h5::File& file, const std::string& inner, const std::string& name) {
    const auto steps = h5partSteps(file.file.get());
    if (steps.empty())
        fail("H5Part file has no steps (groups Step#0, Step#1, ...); its top level has: " +
             listNames(h5::linkNames(file.file.get())));
    std::vector<std::string> warnings;
    std::string step;
    if (inner.empty()) {
        step = steps.front().first;
        if (steps.size() > 1)
            warnings.push_back(name + ": H5Part file holds " + stepRange(steps) + "; read " + step +
                               " (name one as " + name + "/" + steps.back().first +
                               ", or give the file as a sequence)");
    } else {
        const auto it = std::find_if(steps.begin(), steps.end(), [&](const auto& s) { return s.first == inner; });
        if (it == steps.end()) fail("H5Part file has no step " + quoteShort(inner) + " (it has " + stepRange(steps) + ")");
        step = inner;
    }
    const std::string where = step + ": ";
    h5::Handle group = h5::openGroup(file.file.get(), step, "");

    // The datasets this step holds that can be read, and their length.
    std::vector<std::string> names, readable;
    for (std::string& n : h5::linkNames(group.get())) {
        if (!h5::hasDataset(group.get(), n)) continue;  // a subgroup: not H5Part data
        names.push_back(n);
        const h5::DatasetInfo info = h5::inspectDataset(group.get(), n);
        if (info.supported) readable.push_back(n);
        else warnings.push_back(name + ": dataset " + quoteShort(n) + " skipped: " + info.why);
    }
    const ColumnRoles roles = findColumnRoles(readable);
    if (!roles.hasPosition()) {
        std::string missing;
        for (int c = 0; c < 3; ++c) {
            bool found = false;
            for (const std::string& n : readable) found = found || componentIn(positionColumns(), n) == c;
            if (!found) missing += std::string(missing.empty() ? "" : ", ") + "xyz"[c];
        }
        fail(where + "no position dataset" + (missing.size() > 1 ? "s " : " ") + missing +
             " (an H5Part step holds x, y, z); it has: " + listNames(names));
    }
    const std::string& lengthOf = readable[std::size_t(roles.position[0])];
    const std::uint64_t count = h5::inspectDataset(group.get(), lengthOf).length;

    std::vector<Column> columns;
    for (const std::string& n : readable) {
        const std::uint64_t length = h5::inspectDataset(group.get(), n).length;
        if (length != count)
            fail(where + "dataset " + quoteShort(n) + " has " + std::to_string(length) + " values but " +
                 quoteShort(lengthOf) + " has " + std::to_string(count) +
                 " (every dataset of a step holds one value per particle)");
        columns.push_back(h5::readColumn(file, group.get(), n, where));
    }
    ParticleSet set = particlesFromColumns(std::move(columns), std::size_t(count), where + "no positions");
    set.warnings = std::move(warnings);
    return set;
}

}  // namespace meniscus::io_util

#endif  // MENISCUS_HAVE_HDF5
