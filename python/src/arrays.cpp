// numpy arrays in and out, errors as exceptions (arrays.h).
#include "arrays.h"

#include <cctype>
#include <cmath>
#include <span>
#include <stdexcept>
#include <cstring>
#include <utility>

#include "meniscus/particles.h"

namespace meniscus::py {

void throwValue(const std::string& message) { throw pb::value_error(pythonWords(message)); }

void throwOs(const std::string& message, PyObject* type) {
    PyErr_SetString(type, message.c_str());
    throw pb::error_already_set();
}

void throwRuntime(const std::string& message) { throw std::runtime_error(pythonWords(message)); }

std::string pythonWords(std::string message) {
    // "--fill-holes" -> "fill_holes": the option's keyword in Python.
    std::string out;
    for (std::size_t i = 0; i < message.size();) {
        const bool option = message.compare(i, 2, "--") == 0 && i + 2 < message.size() &&
                            std::islower(static_cast<unsigned char>(message[i + 2])) &&
                            (i == 0 || !std::isalnum(static_cast<unsigned char>(message[i - 1])));
        if (!option) {
            out += message[i++];
            continue;
        }
        i += 2;
        while (i < message.size() && (std::isalnum(static_cast<unsigned char>(message[i])) || message[i] == '-'))
            out += message[i] == '-' ? '_' : message[i], ++i;
    }
    return out;
}

namespace {

pb::array asNumpy(pb::handle obj, const std::string& name) {
    if (pb::isinstance<pb::array>(obj)) return pb::reinterpret_borrow<pb::array>(obj);
    try {
        return pb::module_::import("numpy").attr("asarray")(obj);
    } catch (pb::error_already_set&) {
        throwValue(name + ": expected a numpy array, got " + std::string(pb::str(obj.get_type().attr("__name__"))));
    }
}

std::string shapeText(const pb::array& a) {
    std::string s = "(";
    for (pb::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

std::string dtypeText(const pb::array& a) { return pb::str(a.dtype()); }

bool nativeOrder(const pb::array& a) { return a.dtype().attr("isnative").cast<bool>(); }

// C-contiguous and aligned, so a row is one glm::vec3 where it lies.
void checkLayout(const pb::array& a, const std::string& name) {
    constexpr int kAligned = 0x0100;  // NPY_ARRAY_ALIGNED
    if (!(a.flags() & pb::array::c_style))
        throwValue(name + ": the array is not C-contiguous (a slice or a transpose); pass "
                          "numpy.ascontiguousarray(" + name + ")");
    if (!(a.flags() & kAligned)) throwValue(name + ": the array's data is not aligned; pass a copy (" + name + ".copy())");
}

}  // namespace

FloatArray floatArray(pb::handle obj, const std::string& name, int components, long rows, bool allowEmpty) {
    pb::array a = asNumpy(obj, name);
    const std::string want =
        components == 1 ? "(N,)" : "(N, " + std::to_string(components) + ")";
    const bool shapeOk = components == 1 ? (a.ndim() == 1 || (a.ndim() == 2 && a.shape(1) == 1))
                                         : (a.ndim() == 2 && a.shape(1) == components);
    if (!shapeOk) throwValue(name + ": expected shape " + want + ", got " + shapeText(a));
    const pb::dtype dt = a.dtype();
    if (dt.kind() != 'f' || (dt.itemsize() != 4 && dt.itemsize() != 8))
        throwValue(name + ": expected float32 or float64 values, got " + dtypeText(a));
    checkLayout(a, name);
    const std::size_t n = std::size_t(a.shape(0));
    if (rows >= 0 && n != std::size_t(rows))
        throwValue(name + ": " + std::to_string(n) + " rows for " + std::to_string(rows) + " particles");
    if (rows < 0 && n == 0 && !allowEmpty) throwValue(name + ": no particles (0 rows)");
    // float32 in native order is used where it lies; anything else converted once.
    if (dt.itemsize() != 4 || !nativeOrder(a)) a = a.attr("astype")("float32");
    FloatArray out;
    out.keep = a;
    out.data = static_cast<const float*>(a.data());
    out.rows = n;
    out.components = components;
    return out;
}

IntArray intArray(pb::handle obj, const std::string& name, long rows) {
    pb::array a = asNumpy(obj, name);
    if (!(a.ndim() == 1 || (a.ndim() == 2 && a.shape(1) == 1)))
        throwValue(name + ": expected shape (N,), got " + shapeText(a));
    const pb::dtype dt = a.dtype();
    if (dt.kind() != 'i' && dt.kind() != 'u') throwValue(name + ": expected integers, got " + dtypeText(a));
    checkLayout(a, name);
    if (a.shape(0) != rows)
        throwValue(name + ": " + std::to_string(a.shape(0)) + " values for " + std::to_string(rows) + " particles");
    if (dt.kind() != 'i' || dt.itemsize() != 8 || !nativeOrder(a)) a = a.attr("astype")("int64");
    IntArray out;
    out.keep = a;
    out.data = static_cast<const std::int64_t*>(a.data());
    out.rows = std::size_t(rows);
    return out;
}

FloatArray positionArray(pb::handle obj, const std::string& name) {
    FloatArray p = floatArray(obj, name, 3);
    const float* v = p.data;
    for (std::size_t i = 0; i < p.rows * 3; ++i)
        if (!std::isfinite(v[i])) {
            const std::size_t row = i / 3;
            throwValue(name + "[" + std::to_string(row) + "] = (" + std::to_string(v[3 * row]) + ", " +
                       std::to_string(v[3 * row + 1]) + ", " + std::to_string(v[3 * row + 2]) +
                       ") is not finite; drop such rows first, e.g. p[numpy.isfinite(p).all(axis=1)]");
        }
    const std::span<const glm::vec3> points(reinterpret_cast<const glm::vec3*>(v), p.rows);
    if (auto st = checkCoordinates(points, name); !st) throwValue(st.error().describe());
    return p;
}

ParticleView Particles::view() const {
    ParticleView v;
    const std::size_t n = position.rows;
    v.positions = StridedView<glm::vec3>(position.data, n);
    if (velocity.data) v.velocity = StridedView<glm::vec3>(velocity.data, n);
    if (density.data) v.density = StridedView<float>(density.data, n);
    if (color.data) v.color = StridedView<glm::vec3>(color.data, n);
    if (radius.data) v.radius = StridedView<float>(radius.data, n);
    if (id.data) v.id = StridedView<std::int64_t>(id.data, n);
    if (fluid.data) v.fluid = StridedView<std::int64_t>(fluid.data, n);
    return v;
}

Particles particlesArg(pb::handle obj, const ParticleKeywords& extra, float hPerSpacing) {
    Particles p;
    const long n = [&] {
        if (!pb::isinstance<pb::dict>(obj)) {
            p.position = positionArray(obj);
            return long(p.position.rows);
        }
        // A frame as read() gives it: the attributes ParticleView::of would
        // take from the file (their canonical name, type and shape); others
        // are left out, as the CLI leaves them out.
        const pb::dict d = pb::reinterpret_borrow<pb::dict>(obj);
        if (!d.contains("position")) throwValue("the particle dict has no 'position' array (read() gives one)");
        p.position = positionArray(d["position"], "position");
        const long rows = long(p.position.rows);
        auto floats = [&](const char* key, int components, FloatArray& out) {
            if (!d.contains(key)) return false;
            try {
                out = floatArray(d[key], key, components, rows);
                return true;
            } catch (pb::value_error&) {
                return false;
            }
        };
        auto ints = [&](const char* key, IntArray& out) {
            if (!d.contains(key)) return;
            try {
                const pb::array a = asNumpy(d[key], key);
                if (a.dtype().kind() != 'i' && a.dtype().kind() != 'u') return;  // e.g. an id stored as floats
                out = intArray(a, key, rows);
            } catch (pb::value_error&) {
            }
        };
        floats("velocity", 3, p.velocity);
        floats("density", 1, p.density);
        floats("color", 3, p.color);
        for (std::string_view name : kAttrRadiusNames)
            if (!p.radius.data && floats(std::string(name).c_str(), 1, p.radius)) p.radiusName = std::string(name);
        FloatArray h;
        for (std::string_view name : kAttrSmoothingLengthNames) {
            if (p.radius.data || !floats(std::string(name).c_str(), 1, h)) continue;
            if (!(hPerSpacing > 0.0f) || !std::isfinite(hPerSpacing))
                throwValue("h_per_spacing: expected a positive number, got " + std::to_string(hPerSpacing));
            // The same floats as addRadiusFromSmoothingLength computes for a file.
            const float toRadius = 1.0f / (2.0f * hPerSpacing);
            std::vector<float> radii(h.rows);
            for (std::size_t i = 0; i < h.rows; ++i) radii[i] = h.data[i] * toRadius;
            p.radius.keep = adopt(std::move(radii), {pb::ssize_t(h.rows)});
            p.radius.data = static_cast<const float*>(p.radius.keep.data());
            p.radius.rows = h.rows;
            p.radius.components = 1;
            p.radiusName = std::string(kAttrRadiusNames[0]);
            p.smoothingLength = std::string(name);
        }
        ints("id", p.id);
        ints("fluid", p.fluid);
        return rows;
    }();
    if (!extra.velocity.is_none()) p.velocity = floatArray(extra.velocity, "velocity", 3, n);
    if (!extra.density.is_none()) p.density = floatArray(extra.density, "density", 1, n);
    if (!extra.color.is_none()) p.color = floatArray(extra.color, "color", 3, n);
    if (!extra.radii.is_none()) p.radius = floatArray(extra.radii, "radii", 1, n), p.radiusName.clear();
    if (!extra.id.is_none()) p.id = intArray(extra.id, "id", n);
    if (!extra.fluid.is_none()) p.fluid = intArray(extra.fluid, "fluid", n);
    return p;
}

pb::array_t<float> adoptVec3(std::vector<glm::vec3>&& values) {
    const pb::ssize_t n = pb::ssize_t(values.size());
    auto* owned = new std::vector<glm::vec3>(std::move(values));
    pb::capsule free(owned, [](void* p) { delete static_cast<std::vector<glm::vec3>*>(p); });
    return pb::array_t<float>({n, pb::ssize_t(3)}, reinterpret_cast<const float*>(owned->data()), free);
}

namespace {
template <class T, class S>
pb::array_t<S> adoptPixels(Image<T>&& image, int channels) {
    const pb::ssize_t h = image.height, w = image.width;
    auto* owned = new std::vector<T>(std::move(image.pixels));
    pb::capsule free(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    const S* data = reinterpret_cast<const S*>(owned->data());
    if (channels == 1) return pb::array_t<S>({h, w}, data, free);
    return pb::array_t<S>({h, w, pb::ssize_t(channels)}, data, free);
}
}  // namespace

pb::array_t<float> adoptImage(Image<float>&& image) { return adoptPixels<float, float>(std::move(image), 1); }
pb::array_t<float> adoptImage(Image<glm::vec3>&& image) { return adoptPixels<glm::vec3, float>(std::move(image), 3); }
pb::array_t<float> adoptImage(Image<glm::vec4>&& image) { return adoptPixels<glm::vec4, float>(std::move(image), 4); }
pb::array_t<std::uint8_t> adoptImage(Image<glm::u8vec4>&& image) {
    return adoptPixels<glm::u8vec4, std::uint8_t>(std::move(image), 4);
}

pb::dict particleDict(ParticleSet&& set) {
    pb::dict d;
    const pb::ssize_t n = pb::ssize_t(set.size());
    d["position"] = adoptVec3(std::move(set.positions));
    for (Attribute& a : set.attributes) {
        std::vector<pb::ssize_t> shape{n};
        if (a.components != 1) shape.push_back(a.components);
        // Attributes whose value count does not fit are left out (readers never make them).
        if (a.count() != std::size_t(n) || a.components < 1) continue;
        if (a.type == AttributeType::Float) d[pb::str(a.name)] = adopt(std::move(a.floats), shape);
        else d[pb::str(a.name)] = adopt(std::move(a.ints), shape);
    }
    return d;
}

void warnAll(const std::vector<std::string>& warnings) {
    if (warnings.empty()) return;
    // meniscus._warn points the warning at the user's line, past render()'s own frame.
    const pb::object warn = pb::module_::import("meniscus").attr("_warn");
    for (const std::string& w : warnings) warn("meniscus: " + w);
}

}  // namespace meniscus::py
