// The isosurface mesher (mesh()) and the simulator (simulate()).
#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "arrays.h"
#include "meniscus/io.h"
#include "meniscus/options.h"
#include "meniscus/sim.h"
#include "meniscus/surface.h"
#include "module.h"

namespace meniscus::py {

namespace {

// ---------------------------------------------------------------- mesh

// The dict's arrays of these names as attributes of `set` (its positions
// set): float arrays Float, integer ones Int, N or N x C; errors name the key.
void attributesFromDict(const pb::dict& d, const std::vector<std::string>& names, ParticleSet& set) {
    const long rows = long(set.size());
    for (const std::string& name : names) {
        if (!d.contains(name.c_str())) {
            std::string have;
            for (const auto& item : d)
                if (item.first.cast<std::string>() != "position") have += (have.empty() ? "" : ", ") + item.first.cast<std::string>();
            throwValue("interpolate: the particles have no '" + name + "' array (they have: " +
                       (have.empty() ? std::string("none") : have) + ")");
        }
        const pb::array a = pb::module_::import("numpy").attr("asarray")(d[name.c_str()]);
        const int components = a.ndim() == 2 ? int(a.shape(1)) : 1;
        if (a.ndim() < 1 || a.ndim() > 2 || a.shape(0) != rows || components < 1)
            throwValue("interpolate: '" + name + "' must have one row per particle (" + std::to_string(rows) + ")");
        Attribute attr{name, AttributeType::Float, components, {}, {}};
        if (a.dtype().kind() == 'i' || a.dtype().kind() == 'u') {
            const auto v = pb::array_t<std::int64_t, pb::array::c_style | pb::array::forcecast>::ensure(a);
            attr.type = AttributeType::Int;
            attr.ints.assign(v.data(), v.data() + v.size());
        } else {
            const FloatArray v = floatArray(a, name, components, rows);
            attr.floats.assign(v.data, v.data + v.rows * std::size_t(components));
        }
        set.attributes.push_back(std::move(attr));
    }
}

pb::tuple mesh(pb::object particles, pb::object radius, const std::string& field, float cubeSize, float iso,
               pb::object support, int block, int threads, bool normals, float hPerSpacing, pb::object interpolate) {
    const Particles p = particlesArg(particles, {}, hPerSpacing);
    // --interpolate's arrays, taken from the dict before the GIL goes.
    ParticleSet carried;
    std::vector<std::string> names;
    if (!interpolate.is_none()) {
        names = interpolate.cast<std::vector<std::string>>();
        if (!pb::isinstance<pb::dict>(particles))
            throwValue("interpolate: the particles must be a dict as read() returns it, holding the arrays named");
        const std::span<const glm::vec3> points(reinterpret_cast<const glm::vec3*>(p.position.data), p.size());
        carried.positions.assign(points.begin(), points.end());
        attributesFromDict(pb::reinterpret_borrow<pb::dict>(particles), names, carried);
    }
    // The mesher's options, set and checked through their table as `meniscus mesh`'s are.
    MesherOptions o;
    const auto set = [&](const char* name, const OptionValue& v) {
        if (auto st = setOption(*findMesherOption(name), o, v); !st) throwValue(st.error().describe());
    };
    set("field", field);
    set("cube-size", double(cubeSize));
    set("iso", double(iso));
    if (!support.is_none()) set("support", double(support.cast<float>()));
    set("block", std::int64_t(block));
    // radius through `meniscus mesh`'s own row (None: the table's unset 0).
    MeshOptions own;
    if (!radius.is_none())
        if (auto st = setOption(*findIn(meshOptionTable(), "radius"), own, double(radius.cast<float>())); !st)
            throwValue(st.error().describe());
    const float given = own.radius;
    if (!radius.is_none())
        if (auto st = checkRadius(given); !st) throwValue("radius: " + st.error().message);
    Result<TriangleMesh> made = makeError("", "");
    {
        pb::gil_scoped_release unlocked;
        const std::span<const glm::vec3> points(reinterpret_cast<const glm::vec3*>(p.position.data), p.size());
        const auto r = resolveRadius(given, [&] { return defaultRadiusOf(p, points); });  // as `meniscus mesh`
        if (!r) {
            made = r.error();
        } else {
            const MeshParams params = mesherParams(o, *r, threads);
            MeshStats stats;
            made = extractSurface(p.view(), params, &stats);
            // The attributes as `meniscus mesh --interpolate` carries them.
            if (made && !names.empty()) {
                const float h = params.field == SurfaceField::Sph ? stats.supportM
                                                                  : defaults::kSphSupportRadii * params.radiusM;
                if (auto st = interpolateAttributes(carried, names, h, *made, threads); !st) made = st.error();
            }
        }
    }
    if (!made) throwValue(pythonWords(made.error().describe()));
    TriangleMesh& m = *made;
    const pb::ssize_t triangles = pb::ssize_t(m.triangleCount());
    const pb::ssize_t count = pb::ssize_t(m.vertexCount());
    pb::array vertices = adoptVec3(std::move(m.positions));
    pb::array faces = adopt(std::move(m.indices), {triangles, 3});
    pb::dict attributes;
    for (Attribute& a : m.attributes) {
        const int c = a.components;
        attributes[a.name.c_str()] =
            c == 1 ? adopt(std::move(a.floats), {count}) : adopt(std::move(a.floats), {count, pb::ssize_t(c)});
    }
    pb::list out;
    out.append(vertices);
    out.append(faces);
    if (normals) out.append(adoptVec3(std::move(m.normals)));
    if (!names.empty()) out.append(attributes);
    return pb::tuple(out);
}

// write_mesh(): the arrays as a TriangleMesh, written as `meniscus mesh` writes it.
void writeMeshArrays(const std::filesystem::path& path, pb::object vertices, pb::object faces, pb::object normals,
                     pb::object attributes) {
    const Result<MeshFormat> format = meshFormatOf(path);
    if (!format) throwValue(format.error().describe());
    TriangleMesh m;
    const FloatArray v = floatArray(vertices, "vertices", 3, -1, true);
    m.positions.assign(reinterpret_cast<const glm::vec3*>(v.data), reinterpret_cast<const glm::vec3*>(v.data) + v.rows);
    const pb::array f = pb::module_::import("numpy").attr("asarray")(faces);
    if (f.ndim() != 2 || f.shape(1) != 3 || (f.dtype().kind() != 'i' && f.dtype().kind() != 'u'))
        throwValue("faces: expected an M x 3 array of vertex indices (integers)");
    const auto idx = pb::array_t<std::int64_t, pb::array::c_style | pb::array::forcecast>::ensure(f);
    m.indices.reserve(std::size_t(idx.size()));
    for (pb::ssize_t k = 0; k < idx.size(); ++k) {
        const std::int64_t i = idx.data()[k];
        if (i < 0 || std::uint64_t(i) >= m.positions.size())
            throwValue("faces: triangle " + std::to_string(k / 3) + " has vertex index " + std::to_string(i) +
                       ", out of range (" + std::to_string(m.positions.size()) + " vertices)");
        m.indices.push_back(std::uint32_t(i));
    }
    if (!normals.is_none()) {
        const FloatArray n = floatArray(normals, "normals", 3, long(v.rows), true);
        m.normals.assign(reinterpret_cast<const glm::vec3*>(n.data), reinterpret_cast<const glm::vec3*>(n.data) + n.rows);
    }
    if (!attributes.is_none()) {
        for (const auto& item : attributes.cast<pb::dict>()) {
            const std::string name = item.first.cast<std::string>();
            const pb::array a = pb::module_::import("numpy").attr("asarray")(item.second);
            const int c = a.ndim() == 2 ? int(a.shape(1)) : 1;
            const FloatArray values = floatArray(a, name, c, long(v.rows), true);
            m.attributes.push_back({name, AttributeType::Float, c,
                                    std::vector<float>(values.data, values.data + values.rows * std::size_t(c)), {}});
        }
    }
    Status st = okStatus();
    {
        pb::gil_scoped_release unlocked;
        st = writeMesh(path, m, *format);
    }
    if (!st) throwOs(st.error().describe());
}

// ---------------------------------------------------------------- simulate

// The frames of a simulation, made as they are asked for: frame k at k / fps
// simulated seconds, from 0 to the duration (as `meniscus simulate` writes them).
class Simulation {
public:
    Simulation(pb::object scene, pb::object duration, pb::object fps, pb::object radius, pb::object solver) {
        Result<sim::Scene> read = makeError("", "");
        if (pb::isinstance<pb::dict>(scene)) {
            const std::string text = pb::module_::import("json").attr("dumps")(scene).cast<std::string>();
            read = sim::parseScene(text, "scene");
        } else {
            const std::filesystem::path path = scene.cast<std::filesystem::path>();
            std::error_code ec;
            if (!std::filesystem::exists(path, ec))
                throwOs(path.string() + ": no such scene file", PyExc_FileNotFoundError);
            read = sim::readScene(path);
        }
        if (!read) throwValue(read.error().describe());
        sim::Scene& sc = *read;
        // The overrides set, typed, through `meniscus simulate`'s table, and applied as it applies them.
        // None is Python's "the scene's": a value given must be one, not the table's unset sentinel.
        SimulateOptions o;
        const auto set = [&](const char* name, pb::object v, const OptionValue& value) {
            if (v.is_none()) return;
            const SimulateOptionSpec& spec = *findIn(simulateOptionTable(), name);
            OptionLimits given = spec.limits;
            given.unset = NAN, given.emptyUnset = false;
            if (auto st = setOptionValue(spec.name, spec.field(o), value, given); !st)
                throwValue(st.error().describe());
        };
        set("duration", duration, duration.is_none() ? 0.0 : duration.cast<double>());
        set("fps", fps, fps.is_none() ? 0.0 : fps.cast<double>());
        set("radius", radius, radius.is_none() ? 0.0 : radius.cast<double>());
        set("solver", solver, solver.is_none() ? std::string() : solver.cast<std::string>());
        if (auto st = applySimulateOptions(o, sc); !st) throwValue(st.error().describe());
        Result<std::unique_ptr<sim::Simulator>> made = makeError("", "");
        {
            pb::gil_scoped_release unlocked;
            made = sim::Simulator::create(sc);
        }
        if (!made) throwValue(made.error().describe());
        sim_ = std::move(*made);
        fps_ = sc.fps;
        frames_ = std::size_t(std::floor(sc.duration * sc.fps + 1e-9)) + 1;
    }

    pb::dict next() {
        if (next_ >= frames_) throw pb::stop_iteration();
        const double t = double(next_) / fps_;
        Status st = okStatus();
        ParticleSet set;
        {
            pb::gil_scoped_release unlocked;
            std::lock_guard<std::mutex> lock(mutex_);
            st = sim_->advanceTo(t);
            if (st) set = sim_->particles();
        }
        if (!st) throwRuntime(st.error().describe());
        ++next_;
        pb::dict d = particleDict(std::move(set));
        d["time"] = t;
        return d;
    }

    std::size_t size() const { return frames_; }
    float radius() const { return sim_->scene().params.radius; }
    std::size_t particles() const { return sim_->size(); }
    Bounds domain() const {
        Bounds b;
        b.min = sim_->scene().domain.min;
        b.max = sim_->scene().domain.max;
        return b;
    }

private:
    std::unique_ptr<sim::Simulator> sim_;
    double fps_ = 1.0;
    std::size_t frames_ = 0, next_ = 0;
    std::mutex mutex_;
};

}  // namespace

void bindMeshSim(pb::module_& m) {
    m.def("mesh", &mesh, pb::arg("particles"), pb::kw_only(), pb::arg("radius") = pb::none(),
          pb::arg("field") = MesherOptions{}.field, pb::arg("cube_size") = MesherOptions{}.cubeSize,
          pb::arg("iso") = MesherOptions{}.iso, pb::arg("support") = pb::none(),
          pb::arg("block") = MesherOptions{}.block, pb::arg("threads") = 0, pb::arg("normals") = true,
          pb::arg("h_per_spacing") = defaults::kHPerSpacing, pb::arg("interpolate") = pb::none(),
          R"(The liquid's surface as a closed triangle mesh (as `meniscus mesh` writes it).

particles: N x 3 positions or a dict as read() returns it.
radius: metres; None estimates it as the CLI does (estimate_radius()).
field: 'sph' (the SPH density, cubic spline of support 4 r) or 'thesis'.
cube_size: the marching cubes' edge in radii; iso: the level as a fraction of
the field inside fluid at rest; support: the field's support in radii (None:
the field's own); block: block edge in cubes; threads: 0 = all cores (the
mesh is the same for any count); h_per_spacing: a dict with a smoothing length
("h", "hsml", ...) and no radius has radii h / (2 h_per_spacing), as the CLI
gives a file's.
Returns (vertices N x 3 float32, faces M x 3 uint32 counter-clockwise from
outside, normals N x 3 float32 pointing out of the liquid); without normals
when normals=False. interpolate: names of the dict's arrays (velocity,
density, fluid, any other) to carry onto the vertices as `meniscus mesh
--interpolate` does (the SPH kernel normalised by its sum; docs/meshes.md);
a dict of them (N or N x C float32 per vertex) is then appended to the tuple.
The GIL is released while it runs. ValueError for a bad argument or a grid
too large for memory.)");
    m.def("write_mesh", &writeMeshArrays, pb::arg("path"), pb::arg("vertices"), pb::arg("faces"),
          pb::arg("normals") = pb::none(), pb::arg("attributes") = pb::none(),
          R"(Write a triangle mesh as `meniscus mesh` does, the format from the name.

.ply (binary; attributes as float properties), .obj, .vtp or .vtk (VTK
PolyData for ParaView; normals and attributes as point data). vertices: N x 3;
faces: M x 3 vertex indices; normals: N x 3 or None; attributes: a dict of
N or N x C arrays, or None. Written to a temporary name and renamed.
ValueError for a bad argument (an index out of range, a wrong shape, an
unknown extension); OSError when it cannot be written.)");

    pb::class_<Simulation>(m, "Simulation", R"(The frames of a simulation, made one by one as it is iterated.

Made by simulate(); len() is the number of frames; each item is a dict of
arrays as read() returns ("position", "id", "velocity", "density",
"pressure") plus "time" (seconds).)")
        .def("__iter__", [](Simulation& s) -> Simulation& { return s; })
        .def("__next__", &Simulation::next)
        .def("__len__", &Simulation::size)
        .def_property_readonly("radius", &Simulation::radius, "The particle radius, metres.")
        .def_property_readonly("particles", &Simulation::particles, "Particles now.")
        .def_property_readonly(
            "domain",
            [](const Simulation& s) {
                const Bounds b = s.domain();
                return pb::make_tuple(pb::make_tuple(b.min.x, b.min.y, b.min.z), pb::make_tuple(b.max.x, b.max.y, b.max.z));
            },
            "The tank, ((xmin, ymin, zmin), (xmax, ymax, zmax)), metres: pass it as render()'s studio=.");
    m.def(
        "simulate",
        [](pb::object scene, pb::object duration, pb::object fps, pb::object radius, pb::object solver) {
            return std::make_unique<Simulation>(scene, duration, fps, radius, solver);
        },
        pb::arg("scene"), pb::kw_only(), pb::arg("duration") = pb::none(), pb::arg("fps") = pb::none(),
        pb::arg("radius") = pb::none(), pb::arg("solver") = pb::none(),
        R"(Run the built-in SPH simulator (as `meniscus simulate` does); returns an iterator of frames.

scene: a scene file's path (docs/scenes.md; scenes/*.json) or the same as a
dict. duration (s), fps (frames per simulated second), radius (m), solver
('dfsph', 'sph', 'pbf', 'ballistic'): override the scene's.
Frame k is the state at k / fps seconds, from 0 to the duration; each is a
dict of arrays ("position", "id", "velocity", "density", "pressure") plus
"time". The simulation advances as the frames are taken, with the GIL
released. FileNotFoundError for a missing scene file, ValueError for a bad
scene, RuntimeError when a step fails.)");
}

}  // namespace meniscus::py
