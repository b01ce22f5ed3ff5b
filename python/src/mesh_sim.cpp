// The isosurface mesher (mesh()) and the simulator (simulate()).
#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "arrays.h"
#include "meniscus/options.h"
#include "meniscus/sim.h"
#include "meniscus/surface.h"
#include "module.h"

namespace meniscus::py {

namespace {

// ---------------------------------------------------------------- mesh

pb::tuple mesh(pb::object particles, pb::object radius, const std::string& field, float cubeSize, float iso,
               pb::object support, int block, int threads, bool normals, float hPerSpacing) {
    const Particles p = particlesArg(particles, {}, hPerSpacing);
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
        if (!r) made = r.error();
        else made = extractSurface(p.view(), mesherParams(o, *r, threads));
    }
    if (!made) throwValue(made.error().describe());
    TriangleMesh& m = *made;
    const pb::ssize_t triangles = pb::ssize_t(m.triangleCount());
    pb::array vertices = adoptVec3(std::move(m.positions));
    pb::array faces = adopt(std::move(m.indices), {triangles, 3});
    if (!normals) return pb::make_tuple(vertices, faces);
    return pb::make_tuple(vertices, faces, adoptVec3(std::move(m.normals)));
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
          pb::arg("h_per_spacing") = defaults::kHPerSpacing,
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
when normals=False. The GIL is released while it runs. ValueError for a bad
argument or a grid too large for memory.)");

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
