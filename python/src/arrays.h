// numpy arrays in and out, and the library's errors as Python exceptions: what
// every area of the module (read, render, mesh, simulate) shares.
//
// In: float32 or float64 (integers for ids), C-contiguous, the shape the
// argument needs; anything else is a ValueError naming the argument. A
// float32 (int64) array is used where it lies, without a copy; float64 (other
// integer types) is converted once. Out: arrays that own the library's
// vectors (moved, not copied).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "meniscus/params.h"
#include "meniscus/particle_view.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus::py {

namespace pb = pybind11;

// ---- errors. ValueError: a bad argument; OSError: a file could not be read
// or written (missing, unreadable, not a valid file of its format);
// RuntimeError: the pipeline failed while running (e.g. no GL context).
[[noreturn]] void throwValue(const std::string& message);
[[noreturn]] void throwOs(const std::string& message, PyObject* type = PyExc_OSError);
[[noreturn]] void throwRuntime(const std::string& message);
// A CLI-worded message ("--fill-holes: ...") in Python's words ("fill_holes: ...").
std::string pythonWords(std::string message);

// ---- arrays in

// An N x C float32 array (C = 1: shape (N,) or (N, 1)), viewed in place or
// converted once from float64. `keep` holds the memory the view points into.
struct FloatArray {
    pb::array keep;
    const float* data = nullptr;
    std::size_t rows = 0;
    int components = 0;
};
struct IntArray {
    pb::array keep;
    const std::int64_t* data = nullptr;
    std::size_t rows = 0;
};

// `obj` (an ndarray, or anything numpy.asarray takes) as N x `components`
// floats; `rows` = the N it must have, or -1 for any (then at least one row
// unless allowEmpty). Errors name `name`.
FloatArray floatArray(pb::handle obj, const std::string& name, int components, long rows = -1,
                      bool allowEmpty = false);
// Integers, one per row (ids, fluid indices), as int64.
IntArray intArray(pb::handle obj, const std::string& name, long rows);

// Positions: N x 3, N >= 1, every coordinate finite and within
// kMaxCoordinateM (a NaN is a ValueError naming its row: the readers drop such
// particles from files, but an array's rows are the caller's to choose).
FloatArray positionArray(pb::handle obj, const std::string& name = "positions");

// The particles of a render, a mesh or a radius estimate: an N x 3 array, or
// a dict as read() returns it ("position", and the attributes the renderer
// reads: velocity, density, id, fluid, color, radius (or pscale,
// particle_radius)); keyword arrays given to the call override the dict's.
struct Particles {
    FloatArray position, velocity, density, color, radius;
    IntArray id, fluid;
    std::string radiusName;  // the dict key the radii came from ("" = none or the keyword)
    std::string smoothingLength;  // the dict key they were derived from, if so
    ParticleView view() const;
    std::size_t size() const { return position.rows; }
};
struct ParticleKeywords {
    pb::object velocity = pb::none(), density = pb::none(), id = pb::none(), fluid = pb::none(),
               color = pb::none(), radii = pb::none();
};
// A dict with a smoothing length ("h", ...) and no radius gets radii
// h / (2 hPerSpacing), as the CLI gives a file's (addRadiusFromSmoothingLength).
Particles particlesArg(pb::handle obj, const ParticleKeywords& extra = {},
                       float hPerSpacing = defaults::kHPerSpacing);

// ---- arrays out: the vector moved into a capsule the array owns.
template <class T>
pb::array_t<T> adopt(std::vector<T>&& values, std::vector<pb::ssize_t> shape) {
    auto* owned = new std::vector<T>(std::move(values));
    pb::capsule free(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return pb::array_t<T>(shape, owned->data(), free);
}
// glm vectors as N x 3 (or N x 4) float32 arrays.
pb::array_t<float> adoptVec3(std::vector<glm::vec3>&& values);
pb::array_t<float> adoptImage(Image<float>&& image);
pb::array_t<float> adoptImage(Image<glm::vec3>&& image);
pb::array_t<float> adoptImage(Image<glm::vec4>&& image);
pb::array_t<std::uint8_t> adoptImage(Image<glm::u8vec4>&& image);

// A particle set as read() returns it: {"position": N x 3, name: N or N x C, ...}.
pb::dict particleDict(ParticleSet&& set);

// Warnings (dropped particles, ...) through Python's warnings module.
void warnAll(const std::vector<std::string>& warnings);

}  // namespace meniscus::py
