// One particle set from whole named arrays, for the formats that store one
// array per quantity rather than rows: H5Part steps, PySPH particle arrays
// (.hdf5 and .npz) and plain numpy .npz files. The names are matched through
// the shared alias table (attribute_names.h): x y z -> positions, u v w (or
// vx vy vz, ...) -> "velocity", rho/density -> "density", id/idp (integer
// arrays only) -> "id"; every other array is kept under its own name (h, m,
// p, gid, ...), Int when the file stores integers, else Float.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "meniscus/types.h"

namespace meniscus::io_util {

struct Column {
    std::string name;
    bool isInt = false;
    int components = 1;              // values per particle
    std::vector<double> floats;      // when !isInt; float64 kept until the set is built
    std::vector<std::int64_t> ints;  // when isInt
    std::size_t values() const { return isInt ? ints.size() : floats.size(); }
};

// The particle set of `count` particles from `columns` (each must hold
// count x components values; the caller checks that and names the file).
// Positions come from three one-component columns (x y z and the table's
// other spellings) or, failing that, one three-component column named
// position, positions, pos, points or P. Without either this throws
// ParseFailure (io_util::fail) with `noPositions`. float64 values become
// float (rounded to nearest).
ParticleSet particlesFromColumns(std::vector<Column> columns, std::size_t count, const std::string& noPositions);

// "'a', 'b', 'c'" of the names, at most `max` of them ("..." after).
std::string listNames(const std::vector<std::string>& names, std::size_t max = 12);
// "a, b, c": the texts as they are.
std::string joinNames(const std::vector<std::string>& texts);

}  // namespace meniscus::io_util
