// Scene files (docs/scenes.md): JSON text in, a checked sim::Scene out.
// Every key must be one the reader knows (a typo is an error, with a guess at
// what was meant), every number is checked for type, range and float range,
// and every error names the file, the field path (`fluid[1].box.max`) and the
// problem. Missing fields keep the defaults of sim.h / params.h.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "meniscus/io.h"
#include "meniscus/json_text.h"
#include "meniscus/sim.h"

namespace meniscus::sim {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr int kSceneVersion = 1;
// A scene's size and nesting: json_limits::kSimulationScene (json_text.h),
// checked before the text is read into memory or parsed.
constexpr int kMaxDepth = json_limits::kSimulationScene.maxDepth;
constexpr int kMaxInt = 1 << 30;

// Thrown inside the reader for a bad field, caught in parseScene: the field
// path and what is wrong with it.
struct SceneFailure {
    std::string path;
    std::string message;
};
[[noreturn]] void fail(std::string path, std::string message) {
    throw SceneFailure{std::move(path), std::move(message)};
}

// A key as an error shows it: a very long one (only ever a mistake) cut short.
std::string shown(std::string_view key) {
    return key.size() <= 64 ? std::string(key) : std::string(key.substr(0, 61)) + "...";
}
std::string child(const std::string& path, std::string_view key) {
    return path.empty() ? shown(key) : path + "." + shown(key);
}
std::string element(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

// "a string (\"0.02\")", "an array", ...: what a value is, for "expected X, got Y".
std::string got(const json& v) {
    std::string text = v.is_string() ? v.dump() : std::string();
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    const std::string type = v.type_name();
    const std::string article = (type == "array" || type == "object") ? "an " : "a ";
    if (v.is_null()) return "null";
    return article + type + (text.empty() ? "" : " (" + text + ")");
}

// Edits (insert, delete, replace, swap two neighbours) from a to b, for "did
// you mean" (optimal string alignment distance).
std::size_t editDistance(std::string_view a, std::string_view b) {
    const std::size_t w = b.size() + 1;
    std::vector<std::size_t> d((a.size() + 1) * w);
    for (std::size_t i = 0; i <= a.size(); ++i) d[i * w] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) d[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i)
        for (std::size_t j = 1; j <= b.size(); ++j) {
            std::size_t best = std::min({d[(i - 1) * w + j] + 1, d[i * w + j - 1] + 1,
                                         d[(i - 1) * w + j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                best = std::min(best, d[(i - 2) * w + j - 2] + 1);
            d[i * w + j] = best;
        }
    return d.back();
}

std::string joined(const std::vector<std::string>& words) {
    std::string out;
    for (const auto& w : words) out += (out.empty() ? "" : ", ") + w;
    return out;
}

// The closest of `known` to `key` when it is close enough to be a typo.
std::string guess(const std::string& key, const std::vector<std::string>& known) {
    if (key.size() > 64) return {};  // no key is that long, and the distance costs |key| x |k|
    std::string best;  // up to one edit in three letters: "raduis", "domian", not "max" for "min"
    std::size_t bestDistance = std::max<std::size_t>(1, key.size() / 3) + 1;
    for (const auto& k : known) {
        const std::size_t d = editDistance(key, k);
        if (d < bestDistance) bestDistance = d, best = k;
    }
    return best;
}

// One JSON object being read. Each get() names a key the object may have;
// finish() rejects any other key, listing the known ones, so a misspelt key
// is an error instead of a silently ignored default.
class Fields {
public:
    Fields(const json& value, std::string path, std::string what)
        : object_(value), path_(std::move(path)), what_(std::move(what)) {
        if (!value.is_object())
            fail(path_, "expected an object {...} (" + what_ + "), got " + got(value));
    }

    const json* get(const char* key) {
        known_.emplace_back(key);
        const auto it = object_.find(key);
        return it == object_.end() ? nullptr : &*it;
    }
    const json& need(const char* key, const std::string& hint) {
        const json* v = get(key);
        if (v) return *v;
        std::string typo;  // "domian" for "domain": say so, not only that "domain" is missing
        for (auto it = object_.begin(); it != object_.end() && typo.empty(); ++it)
            if (!knows(it.key()) && !guess(it.key(), {key}).empty()) typo = " (is \"" + shown(it.key()) + "\" a misspelling of it?)";
        fail(path(key), "missing" + typo + "; " + what_ + " needs it (" + hint + ")");
    }
    std::string path(std::string_view key) const { return child(path_, key); }
    bool knows(const std::string& key) const {
        return std::find(known_.begin(), known_.end(), key) != known_.end();
    }

    // `nested`, `nestedName`: a sub-object whose keys are often written one
    // level too high (params' keys at the top of the scene).
    void finish(const Fields* nested = nullptr, const char* nestedName = nullptr) const {
        for (auto it = object_.begin(); it != object_.end(); ++it) {
            const std::string& key = it.key();
            if (knows(key)) continue;
            std::string message = "unknown key";
            if (nested && nested->knows(key)) {
                message += " (it belongs inside \"" + std::string(nestedName) + "\")";
            } else if (const std::string g = guess(key, known_); !g.empty()) {
                message += " (did you mean \"" + g + "\"?)";
            }
            fail(path(key), message + "; " + what_ + " has the keys: " + joined(known_));
        }
    }

private:
    const json& object_;
    std::string path_;
    std::string what_;
    std::vector<std::string> known_;
};

// ---- values -----------------------------------------------------------------

double number(const json& v, const std::string& path) {
    if (!v.is_number()) fail(path, "expected a number, got " + got(v));
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(path, "is not a finite number");
    return d;
}

float toFloat(double d, const std::string& path) {
    if (std::fabs(d) > double(FLT_MAX)) fail(path, num(d) + " is out of range for a 32-bit float");
    if (d != 0.0 && std::fabs(d) < double(FLT_MIN)) fail(path, num(d) + " is too small for a 32-bit float");
    return float(d);
}

enum class Bound { Any, Positive, NonNegative };

double bounded(double v, Bound bound, const std::string& path) {
    if (bound == Bound::Positive && !(v > 0.0)) fail(path, "must be > 0, got " + num(v));
    if (bound == Bound::NonNegative && !(v >= 0.0)) fail(path, "must be >= 0, got " + num(v));
    return v;
}

float floatValue(const json& v, const std::string& path, Bound bound = Bound::Any) {
    return float(bounded(toFloat(number(v, path), path), bound, path));
}

void readFloat(Fields& f, const char* key, float& out, Bound bound = Bound::Any) {
    if (const json* v = f.get(key)) out = floatValue(*v, f.path(key), bound);
}

void readDouble(Fields& f, const char* key, double& out, Bound bound) {
    if (const json* v = f.get(key)) out = bounded(number(*v, f.path(key)), bound, f.path(key));
}

int intValue(const json& v, const std::string& path, int lo, int hi) {
    const double d = number(v, path);
    if (d != std::floor(d)) fail(path, "expected a whole number, got " + num(d));
    if (d < lo || d > hi) fail(path, "must be from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got " + num(d));
    return int(d);
}

void readInt(Fields& f, const char* key, int& out, int lo, int hi) {
    if (const json* v = f.get(key)) out = intValue(*v, f.path(key), lo, hi);
}

std::string stringValue(const json& v, const std::string& path) {
    if (!v.is_string()) fail(path, "expected a string, got " + got(v));
    return v.get<std::string>();
}

void readString(Fields& f, const char* key, std::string& out) {
    if (const json* v = f.get(key)) out = stringValue(*v, f.path(key));
}

const char* const kAxis[3] = {"x", "y", "z"};

// [x, y, z]; `nonZero`: a direction, which must have a length.
glm::vec3 vec3Value(const json& v, const std::string& path, bool nonZero = false) {
    if (!v.is_array() || v.size() != 3)
        fail(path, "expected an array of 3 numbers [x, y, z], got " +
                       (v.is_array() ? "an array of " + std::to_string(v.size()) : got(v)));
    glm::vec3 out;
    for (int i = 0; i < 3; ++i) out[i] = floatValue(v[std::size_t(i)], element(path, std::size_t(i)));
    if (nonZero && !(glm::dot(out, out) > 0.0f)) fail(path, "must not be [0, 0, 0] (it is a direction)");
    return out;
}

void readVec3(Fields& f, const char* key, glm::vec3& out, bool nonZero = false) {
    if (const json* v = f.get(key)) out = vec3Value(*v, f.path(key), nonZero);
}

// {"min": [x,y,z], "max": [x,y,z]}, min <= max on every axis; `solid`: strictly
// (a domain or a fluid block needs a volume).
Box boxValue(const json& v, const std::string& path, bool solid) {
    Fields f(v, path, "a box {\"min\": [x, y, z], \"max\": [x, y, z]}");
    Box box;
    box.min = vec3Value(f.need("min", "the lower corner [x, y, z], metres"), f.path("min"));
    box.max = vec3Value(f.need("max", "the upper corner [x, y, z], metres"), f.path("max"));
    f.finish();
    for (int i = 0; i < 3; ++i) {
        const std::string a = kAxis[i];
        if (box.max[i] < box.min[i] || (solid && box.max[i] == box.min[i]))
            fail(f.path("max"), "max." + a + " = " + num(box.max[i]) + " must be " + (solid ? "above" : "at least") +
                                    " min." + a + " = " + num(box.min[i]));
    }
    return box;
}

// `inner` lies in the domain; `what` names the offending corner in the message.
void checkInside(const Box& inner, const Box& domain, const std::string& path, const std::string& what) {
    for (int i = 0; i < 3; ++i) {
        const std::string a = kAxis[i];
        if (inner.min[i] < domain.min[i])
            fail(path, what + " reaches " + a + " = " + num(inner.min[i]) + ", below the domain's min." + a + " = " +
                           num(domain.min[i]) + " (it must lie inside the domain)");
        if (inner.max[i] > domain.max[i])
            fail(path, what + " reaches " + a + " = " + num(inner.max[i]) + ", above the domain's max." + a + " = " +
                           num(domain.max[i]) + " (it must lie inside the domain)");
    }
}

Box requireBox(Fields& f, const char* key, const std::string& hint, bool solid) {
    return boxValue(f.need(key, hint), f.path(key), solid);
}

// The elements of an optional array field, each read by `read(value, path)`.
template <class T, class Read>
std::vector<T> readArray(Fields& f, const char* key, Read&& read) {
    std::vector<T> out;
    const json* v = f.get(key);
    if (!v) return out;
    if (!v->is_array()) fail(f.path(key), "expected an array [...], got " + got(*v));
    for (std::size_t i = 0; i < v->size(); ++i) out.push_back(read((*v)[i], element(f.path(key), i)));
    return out;
}

// ---- the parts of a scene ---------------------------------------------------

SimParams readParams(Fields& f) {
    SimParams p;
    if (const json* v = f.get("solver")) {
        const std::string name = stringValue(*v, f.path("solver"));
        if (!solverFromName(name, &p.solver))
            fail(f.path("solver"), "unknown solver \"" + shown(name) + "\"; the solvers are dfsph, sph, ballistic, pbf");
    }
    readFloat(f, "radius", p.radius, Bound::Positive);
    readFloat(f, "rest_density", p.restDensity, Bound::Positive);
    readFloat(f, "particle_volume", p.particleVolume, Bound::NonNegative);
    readVec3(f, "gravity", p.gravity);
    readFloat(f, "viscosity", p.viscosity, Bound::NonNegative);
    readFloat(f, "surface_tension", p.surfaceTension, Bound::NonNegative);
    readFloat(f, "stiffness", p.stiffness, Bound::Positive);
    readFloat(f, "cfl", p.cfl, Bound::Positive);
    readFloat(f, "min_dt", p.minDt, Bound::Positive);
    readFloat(f, "max_dt", p.maxDt, Bound::Positive);
    readFloat(f, "density_tolerance", p.densityTolerance, Bound::Positive);
    readFloat(f, "divergence_tolerance", p.divergenceTolerance, Bound::Positive);
    readInt(f, "max_iterations", p.maxIterations, 1, kMaxInt);
    readFloat(f, "lifetime", p.lifetime, Bound::NonNegative);
    readInt(f, "resort_every", p.resortEvery, 1, kMaxInt);
    f.finish();
    if (p.maxDt < p.minDt)
        fail(f.path("max_dt"), num(p.maxDt) + " s is below min_dt = " + num(p.minDt) + " s");
    // Fractions of rho0 (0.0005 = 0.05 %): 1 or more is a percentage written as a fraction's place.
    if (p.densityTolerance >= 1.0f)
        fail(f.path("density_tolerance"), "is a fraction of the rest density (0.0005 = 0.05 %) and must be below 1, got " +
                                              num(p.densityTolerance));
    if (p.divergenceTolerance >= 1.0f)
        fail(f.path("divergence_tolerance"),
             "is a fraction of the rest density per second (0.001 = 0.1 %/s) and must be below 1, got " +
                 num(p.divergenceTolerance));
    return p;
}

FluidBlock readFluid(const json& v, const std::string& path, const Box& domain) {
    Fields f(v, path, "a fluid block");
    FluidBlock block;
    std::string shape = "box";
    readString(f, "shape", shape);
    if (shape == "box") {
        block.box = requireBox(f, "box", "the block's extent {\"min\": [x, y, z], \"max\": [x, y, z]}, metres", true);
    } else if (shape == "sphere") {
        block.shape = FluidBlock::Shape::Sphere;
        block.center = vec3Value(f.need("center", "the ball's centre [x, y, z], metres"), f.path("center"));
        block.radius = floatValue(f.need("radius", "the ball's radius, metres"), f.path("radius"), Bound::Positive);
        block.box = Box{block.center - glm::vec3(block.radius), block.center + glm::vec3(block.radius)};
    } else {
        fail(f.path("shape"), "unknown shape \"" + shown(shape) + "\"; the shapes are box, sphere");
    }
    readVec3(f, "velocity", block.velocity);
    f.finish();
    if (block.shape == FluidBlock::Shape::Box) checkInside(block.box, domain, f.path("box"), "the block");
    else checkInside(block.box, domain, f.path("radius"), "the ball");
    return block;
}

bool meshExtension(const fs::path& p) {
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".obj" || ext == ".ply";
}

// Only the keys of the collider's kind are allowed: a "radius" on a box is an
// error, not ignored.
Collider readCollider(const json& v, const std::string& path, const fs::path& folder) {
    Fields probe(v, path, "a collider");
    const json& kindValue = probe.need("kind", "box, sphere, plane or mesh");
    const std::string kind = stringValue(kindValue, probe.path("kind"));
    Collider c;
    Fields f(v, path, "a " + shown(kind) + " collider");
    f.get("kind");
    if (kind == "box") {
        c.kind = Collider::Kind::Box;
        c.box = requireBox(f, "box", "the solid box {\"min\": [x, y, z], \"max\": [x, y, z]}, metres", false);
    } else if (kind == "sphere") {
        c.kind = Collider::Kind::Sphere;
        c.center = vec3Value(f.need("center", "the centre [x, y, z], metres"), f.path("center"));
        c.radius = floatValue(f.need("radius", "metres"), f.path("radius"), Bound::Positive);
    } else if (kind == "plane") {
        c.kind = Collider::Kind::Plane;
        c.point = vec3Value(f.need("point", "a point on the plane [x, y, z], metres"), f.path("point"));
        c.normal = vec3Value(f.need("normal", "toward the fluid's side [x, y, z]"), f.path("normal"), true);
    } else if (kind == "mesh") {
        c.kind = Collider::Kind::Mesh;
        const std::string file = stringValue(f.need("mesh", "a closed OBJ or PLY file"), f.path("mesh"));
        if (file.empty()) fail(f.path("mesh"), "is empty; it names a closed OBJ or PLY file");
        const fs::path mesh(file);
        if (!meshExtension(mesh)) fail(f.path("mesh"), "\"" + shown(file) + "\" is not an OBJ or PLY file (.obj, .ply)");
        c.mesh = mesh.is_absolute() ? mesh : (folder / mesh).lexically_normal();
        readVec3(f, "scale", c.scale);
        for (int i = 0; i < 3; ++i)
            if (!(c.scale[i] > 0.0f))
                fail(element(f.path("scale"), std::size_t(i)), "must be > 0, got " + num(c.scale[i]));
        readVec3(f, "translate", c.translate);
    } else {
        fail(probe.path("kind"), "unknown collider kind \"" + shown(kind) + "\"; the kinds are box, sphere, plane, mesh");
    }
    // How it is drawn: checked by the renderer's geometry reader, which names this key.
    if (const json* m = f.get("material")) {
        if (!m->is_object()) fail(f.path("material"), "expected an object, e.g. {\"glass\": true}");
        c.material = m->dump();
    }
    f.finish();
    return c;
}

Emitter readEmitter(const json& v, const std::string& path, const Box& domain) {
    Fields f(v, path, "an emitter");
    Emitter e;
    e.position = vec3Value(f.need("position", "the nozzle's centre [x, y, z], metres"), f.path("position"));
    readVec3(f, "direction", e.direction, true);
    readFloat(f, "radius", e.radius, Bound::NonNegative);
    readFloat(f, "speed", e.speed, Bound::Positive);
    readFloat(f, "rate", e.rate, Bound::NonNegative);
    readFloat(f, "start", e.start, Bound::NonNegative);
    readFloat(f, "end", e.end, Bound::NonNegative);
    f.finish();
    checkInside(Box{e.position, e.position}, domain, f.path("position"), "the nozzle");
    if (e.end < e.start) fail(f.path("end"), num(e.end) + " s is before start = " + num(e.start) + " s");
    return e;
}

Drain readDrain(const json& v, const std::string& path, const Box& domain) {
    Fields f(v, path, "a drain");
    Drain d;
    d.box = requireBox(f, "box", "the region that removes particles {\"min\": [x, y, z], \"max\": [x, y, z]}", false);
    f.finish();
    for (int i = 0; i < 3; ++i)
        if (d.box.max[i] < domain.min[i] || d.box.min[i] > domain.max[i])
            fail(f.path("box"), std::string("lies outside the domain along ") + kAxis[i] + ", so it would drain nothing");
    return d;
}

Scene sceneFromJson(const json& root, const std::string& name) {
    Fields top(root, "", "a scene");
    Scene scene;
    scene.file = name;
    scene.name = fs::path(name).stem().string();
    const fs::path folder = fs::path(name).parent_path();

    int version = kSceneVersion;
    readInt(top, "version", version, 0, kMaxInt);
    if (version != kSceneVersion)
        fail(top.path("version"), "is " + std::to_string(version) + "; this reader knows version " +
                                      std::to_string(kSceneVersion));
    readString(top, "name", scene.name);
    std::string description;
    readString(top, "description", description);
    readDouble(top, "duration", scene.duration, Bound::NonNegative);
    if (!(scene.duration <= kMaxDuration))
        fail(top.path("duration"), "must be at most " + num(kMaxDuration) + " s, got " + num(scene.duration));
    readDouble(top, "fps", scene.fps, Bound::Positive);
    if (!(scene.fps <= kMaxFps)) fail(top.path("fps"), "must be at most " + num(kMaxFps) + ", got " + num(scene.fps));

    const json noParams = json::object();
    const json* paramsValue = top.get("params");
    Fields params(paramsValue ? *paramsValue : noParams, top.path("params"), "params");
    scene.params = readParams(params);

    scene.domain = requireBox(top, "domain", "the tank {\"min\": [x, y, z], \"max\": [x, y, z]}, metres", true);
    const Box& domain = scene.domain;
    scene.fluid = readArray<FluidBlock>(top, "fluid", [&](const json& v, const std::string& p) { return readFluid(v, p, domain); });
    scene.colliders = readArray<Collider>(top, "colliders", [&](const json& v, const std::string& p) { return readCollider(v, p, folder); });
    scene.emitters = readArray<Emitter>(top, "emitters", [&](const json& v, const std::string& p) { return readEmitter(v, p, domain); });
    scene.drains = readArray<Drain>(top, "drains", [&](const json& v, const std::string& p) { return readDrain(v, p, domain); });
    top.finish(&params, "params");
    if (scene.fluid.empty() && scene.emitters.empty())
        fail("fluid", "the scene has no fluid block and no emitter, so it would hold no particles");
    return scene;
}

// ---- JSON text --------------------------------------------------------------

// Where the parser is (`fluid[1].box`), for the errors it finds itself:
// repeated keys (which nlohmann::json would silently resolve to the last)
// and nesting deeper than any scene needs.
class KeyTracker {
public:
    bool operator()(int depth, json::parse_event_t event, json& parsed) {
        using E = json::parse_event_t;
        if (depth > kMaxDepth) fail(path(), "nested deeper than " + std::to_string(kMaxDepth) + " levels");
        switch (event) {
            case E::object_start: frames_.emplace_back().isArray = false; break;
            case E::array_start: frames_.emplace_back().isArray = true; break;
            case E::key: {
                Frame& top = frames_.back();
                top.key = parsed.get<std::string>();
                if (!top.keys.insert(top.key).second)
                    fail(path(), "repeated key (the second one would silently win); write each key once");
                break;
            }
            case E::object_end:
            case E::array_end:
                frames_.pop_back();
                [[fallthrough]];
            case E::value:
                if (!frames_.empty() && frames_.back().isArray) ++frames_.back().index;
                break;
        }
        return true;
    }

private:
    struct Frame {
        bool isArray = false;
        std::size_t index = 0;
        std::string key;
        std::set<std::string> keys;
    };
    std::string path() const {
        std::string out;
        for (const Frame& f : frames_) out = f.isArray ? element(out, f.index) : child(out, f.key);
        return out;
    }
    std::vector<Frame> frames_;
};

// nlohmann's message without its "[json.exception.parse_error.101] " tag;
// "parse error at line 3, column 19: ..." keeps its position.
std::string parserMessage(std::string what) {
    if (const std::size_t tag = what.find("] "); what.rfind("[json.exception.", 0) == 0 && tag != std::string::npos)
        what.erase(0, tag + 2);
    if (what.rfind("parse error", 0) == 0) what.replace(0, 11, "JSON error");
    return what;
}

}  // namespace

Result<Scene> parseScene(std::string_view text, const std::string& name) {
    if (auto fits = checkJsonText(text, name, json_limits::kSimulationScene); !fits) return fits.error();
    try {
        json root;
        try {
            root = json::parse(text.begin(), text.end(), KeyTracker{});
        } catch (const json::parse_error& e) {
            return makeError(name, parserMessage(e.what()));
        } catch (const json::exception& e) {
            return makeError(name, "JSON error: " + parserMessage(e.what()));
        }
        return sceneFromJson(root, name);
    } catch (const SceneFailure& f) {
        // A field's value (or a key) is wrong: the settings' error, not the data's.
        return makeUsageError(name, f.path.empty() ? f.message : f.path + ": " + f.message);
    } catch (const std::bad_alloc&) {
        return makeError(name, "out of memory while reading the scene");
    } catch (const std::exception& e) {
        return makeError(name, std::string("cannot read the scene: ") + e.what());
    }
}

Result<Scene> readScene(const std::filesystem::path& path) {
    const std::string name = path.string();
    auto text = readJsonText(path, json_limits::kSimulationScene);
    if (!text) return text.error();
    auto scene = parseScene(*text, name);
    if (!scene) return scene;
    std::error_code ec;
    // Mesh paths are resolved against the scene's folder; say now, naming the
    // field, if one is not there, rather than when the simulator starts.
    const auto& colliders = scene.value().colliders;
    for (std::size_t i = 0; i < colliders.size(); ++i) {
        if (colliders[i].kind != Collider::Kind::Mesh) continue;
        if (!fs::is_regular_file(colliders[i].mesh, ec))
            return makeUsageError(name, element("colliders", i) + ".mesh: no such file " + colliders[i].mesh.string());
    }
    return scene;
}

}  // namespace meniscus::sim
