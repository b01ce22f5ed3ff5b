// Rendering: Renderer (the render() of __init__.py is one frame of a fresh
// one), auto_camera(), settings().
//
// Settings are `meniscus render`'s own options under their Python names
// (--noise-bump: noise_bump): each keyword becomes the option's argument and
// goes through the CLI's parser and settingsFromOptions (apps/meniscus,
// linked as meniscus_app), so names, defaults, checks and the resulting
// RenderSettings are the CLI's and a render matches its PNG byte for byte.
// The camera for one frame is the CLI's own (app::chooseCamera on the points
// fixForSequence samples of a single file), the radius the same
// defaultRadius.
#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "arrays.h"
#include "common.h"  // meniscus_app: RenderOptions, addCameraOptions, settingsFromOptions, upRotation
#include "mesh.h"    // meniscus_app: addSurfaceOptions, mesherParams
#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "meniscus/surface.h"
#include "module.h"

namespace meniscus::py {

namespace {

using app::RenderOptions;

// ---------------------------------------------------------------- options

// The options a keyword may name: `render`'s look, camera and surface
// options. Left out: fluid_attribute (a file's attribute: give fluid= the
// array) and the ones about sequences and outputs, which main.cpp adds.
const char* const kNotSettings[] = {"help", "fluid_attribute"};

// `render`'s options bound to `o` (what main.cpp's render command adds, less
// the sequence and file options).
std::unique_ptr<CLI::App> optionTable(RenderOptions& o) {
    auto cmd = std::make_unique<CLI::App>("meniscus.render settings");
    app::addCameraOptions(cmd.get(), o, true);
    app::addSurfaceOptions(cmd.get(), o);
    return cmd;
}

std::string pythonName(const std::string& option) {  // "--noise-bump" -> "noise_bump"
    std::string n = option.substr(option.rfind("--") == 0 ? 2 : 0);
    std::replace(n.begin(), n.end(), '-', '_');
    return n;
}

struct Setting {
    std::string option;  // "--noise-bump"
    bool flag = false;   // takes no value (--noise)
    std::string help, defaultText;
};

// Python name -> option, built once.
const std::map<std::string, Setting>& settingTable() {
    static const std::map<std::string, Setting> table = [] {
        RenderOptions o;
        auto cmd = optionTable(o);
        std::map<std::string, Setting> t;
        for (const CLI::Option* opt : cmd->get_options()) {
            if (opt->get_lnames().empty()) continue;
            const std::string name = pythonName(opt->get_lnames().front());
            if (std::find(std::begin(kNotSettings), std::end(kNotSettings), name) != std::end(kNotSettings)) continue;
            t[name] = Setting{"--" + opt->get_lnames().front(), opt->get_expected_max() == 0, opt->get_description(),
                              opt->get_default_str()};
        }
        return t;
    }();
    return table;
}

std::string settingNames() {
    std::string s;
    for (const auto& [name, setting] : settingTable()) s += (s.empty() ? "" : ", ") + name;
    return s;
}

// One value as the option's text, as a scene file's value becomes it:
// numbers in the shortest form that reads back as the same double, True/False
// as on/off, a list joined with commas (eye=(1, 2, 3): "1,2,3").
std::string valueText(pb::handle v, const std::string& name, bool inList = false) {
    if (pb::isinstance<pb::bool_>(v) || pb::isinstance(v, pb::module_::import("numpy").attr("bool_")))
        return v.cast<bool>() ? "on" : "off";
    if (pb::isinstance<pb::str>(v)) return v.cast<std::string>();
    if (pb::hasattr(v, "__index__")) return pb::str(pb::int_(pb::reinterpret_borrow<pb::object>(v)));
    if (pb::hasattr(v, "__float__")) return pb::repr(pb::float_(pb::reinterpret_borrow<pb::object>(v)));
    if (!inList && (pb::isinstance<pb::list>(v) || pb::isinstance<pb::tuple>(v) || pb::isinstance<pb::array>(v))) {
        std::string joined;
        for (pb::handle e : pb::iter(pb::isinstance<pb::array>(v) ? v.attr("tolist")() : pb::reinterpret_borrow<pb::object>(v)))
            joined += (joined.empty() ? "" : ",") + valueText(e, name, true);
        return joined;
    }
    throw pb::type_error(name + ": expected a number, a string, True/False or a list of numbers, got " +
                         std::string(pb::str(v.get_type().attr("__name__"))));
}

// Option -> its word on the command line ("--width=320", "--noise"); a
// flag set False is absent.
using Args = std::map<std::string, std::string>;

void addSetting(Args& args, const std::string& name, pb::handle value, const char* where) {
    const auto& table = settingTable();
    const auto it = table.find(name);
    if (name == "fluid_attribute")
        throw pb::type_error(std::string(where) + ": fluid_attribute names a file's attribute; pass the array "
                                                  "itself, fluid=frame['" + "name']");
    if (it == table.end())
        throw pb::type_error(std::string(where) + ": unexpected keyword argument '" + name +
                             "' (not a setting); the settings (meniscus.settings() describes them) are: " +
                             settingNames());
    if (value.is_none()) {
        args.erase(it->second.option);
        return;
    }
    if (it->second.flag) {
        if (!pb::isinstance<pb::bool_>(value) && !pb::isinstance(value, pb::module_::import("numpy").attr("bool_")))
            throwValue(name + ": expected True or False");
        if (value.cast<bool>()) args[it->second.option] = it->second.option;
        else args.erase(it->second.option);
        return;
    }
    // "--name=value": a value starting with '-' (eye=(-1, 2, 3)) stays a value.
    args[it->second.option] = it->second.option + "=" + valueText(value, name);
}

Args argsOf(const pb::dict& kw, const char* where) {
    Args args;
    for (auto [k, v] : kw) addSetting(args, k.cast<std::string>(), v, where);
    return args;
}

RenderOptions parseOptions(const Args& args) {
    RenderOptions o;
    auto cmd = optionTable(o);
    std::vector<std::string> words;
    for (const auto& [option, word] : args) words.push_back(word);
    std::reverse(words.begin(), words.end());  // CLI11 takes them last first
    try {
        cmd->parse(words);
    } catch (const CLI::ParseError& e) {
        throwValue(e.what());
    }
    return o;
}

// ---------------------------------------------------------------- camera

// The camera dict's keys: the camera options, and the clip range (which the
// CLI leaves at its defaults for a given eye, and the auto camera sets).
const char* const kCameraOptions[] = {"eye", "target", "fov", "azimuth", "elevation", "distance"};

struct CameraArg {
    Args args;
    std::optional<float> nearM, farM;
};

CameraArg cameraArg(pb::handle camera) {
    CameraArg c;
    if (camera.is_none()) return c;
    if (!pb::isinstance<pb::dict>(camera))
        throwValue("camera: expected a dict such as {'eye': (x, y, z), 'target': (x, y, z), 'fov': 40} "
                   "(or auto_camera()'s), got " + std::string(pb::str(camera.get_type().attr("__name__"))));
    for (auto [k, v] : pb::reinterpret_borrow<pb::dict>(camera)) {
        const std::string key = pb::str(k);
        if (key == "near" || key == "far") {
            const float f = v.cast<float>();
            (key == "near" ? c.nearM : c.farM) = f;
            continue;
        }
        if (std::find(std::begin(kCameraOptions), std::end(kCameraOptions), key) == std::end(kCameraOptions))
            throwValue("camera: unknown key '" + key + "' (expected eye, target, fov, near, far, or for the automatic "
                       "camera azimuth, elevation, distance)");
        addSetting(c.args, key, v, "camera");
    }
    return c;
}

// The CLI's camera for one frame (app::chooseCamera, the points sampled as
// fixForSequence samples a single file), with the near and far planes given.
Result<Camera> chooseCamera(const RenderOptions& o, std::span<const glm::vec3> points, float radius,
                            const CameraArg& extra, std::size_t* outside) {
    std::vector<glm::vec3> samples;
    if (o.eye.empty()) app::sampleFramePoints(points, samples);
    auto cam = app::chooseCamera(o, samples, radius, outside);
    if (!cam) return makeError("", "camera: " + cam.error().message);
    if (extra.nearM) cam->nearM = *extra.nearM;
    if (extra.farM) cam->farM = *extra.farM;
    if (auto st = validateCamera(*cam); !st) return makeError("", "camera: " + st.error().message);
    return cam;
}

// ---------------------------------------------------------------- one frame

// What a frame needs besides the settings, prepared without the GIL: the
// particles turned by the up axis (a copy only then), radius, camera, studio.
struct Frame {
    ParticleView view;
    std::vector<glm::vec3> turned, turnedVelocity;  // with up != +y
    float radius = 0.0f;
    Camera camera;
    std::vector<std::string> warnings;
};

Status prepareFrame(const RenderOptions& o, const Particles& p, const CameraArg& extra, Frame& f) {
    auto up = app::upRotation(o.up);
    if (!up) return up.error();
    f.view = p.view();
    std::span<const glm::vec3> points(reinterpret_cast<const glm::vec3*>(p.position.data), p.size());
    if (!up->identity) {
        f.turned.reserve(p.size());
        for (const glm::vec3& q : points) f.turned.push_back(up->apply(q));
        f.view.positions = StridedView<glm::vec3>(std::span<const glm::vec3>(f.turned));
        points = f.turned;
        if (f.view.velocity.present()) {
            for (std::size_t i = 0; i < f.view.velocity.count; ++i)
                f.turnedVelocity.push_back(up->apply(f.view.velocity[i]));
            f.view.velocity = StridedView<glm::vec3>(std::span<const glm::vec3>(f.turnedVelocity));
        }
    }
    f.radius = o.radius;
    if (f.radius == 0.0f) {
        const RadiusEstimate est = defaultRadiusOf(p, points);
        f.radius = est.radius;
        if (est.fallback) f.warnings.push_back("radius " + est.describe());
        if (auto st = checkRadius(f.radius); !st)
            return makeError("", "the estimated " + st.error().message + "; pass radius=");
    }
    std::size_t outside = 0;
    auto cam = chooseCamera(o, points, f.radius, extra, &outside);
    if (!cam) return cam.error();
    f.camera = *cam;
    if (outside > 0)
        f.warnings.push_back("auto camera: " + std::to_string(outside) +
                             " sampled particles (the outermost) left outside the frame");
    return okStatus();
}

pb::dict aovDict(Aovs&& a) {
    pb::dict d;
    auto put = [&](const char* key, auto&& image) {
        if (!image.empty()) d[key] = adoptImage(std::move(image));
    };
    put("color", std::move(a.color));
    put("depth", std::move(a.depth));
    put("raw_depth", std::move(a.rawDepth));
    put("normal", std::move(a.normal));
    put("thickness", std::move(a.thickness));
    put("noise", std::move(a.noise));
    put("foam", std::move(a.foam));
    put("whitening", std::move(a.whitening));
    put("spray", std::move(a.spray));
    put("silhouette", std::move(a.silhouette));
    put("fluid", std::move(a.fluid));
    return d;
}

std::optional<Bounds> studioArg(pb::handle studio) {
    if (studio.is_none()) return std::nullopt;
    const FloatArray b = floatArray(studio, "studio", 3, 2);
    Bounds box;
    box.min = {b.data[0], b.data[1], b.data[2]};
    box.max = {b.data[3], b.data[4], b.data[5]};
    if (box.empty()) throwValue("studio: expected ((xmin, ymin, zmin), (xmax, ymax, zmax)) with min <= max");
    return box;
}

// The values the renderer would refuse, as ValueErrors naming the array (the
// renderer's own errors are then about the run itself).
void checkParticleValues(const Particles& p, bool ownRadii) {
    for (std::size_t i = 0; p.fluid.data && i < p.size(); ++i)
        if (p.fluid.data[i] < 0 || p.fluid.data[i] >= kMaxFluids)
            throwValue("fluid[" + std::to_string(i) + "] = " + std::to_string(p.fluid.data[i]) +
                       ": fluid indices are 0 to " + std::to_string(kMaxFluids - 1));
    for (std::size_t i = 0; ownRadii && p.radius.data && i < p.size(); ++i)
        if (auto st = checkRadius(p.radius.data[i]); !st)
            throwValue((p.radiusName.empty() ? std::string("radii") : p.radiusName) + "[" + std::to_string(i) +
                       "]: " + st.error().message);
}

// ---------------------------------------------------------------- Renderer

class PyRenderer {
public:
    PyRenderer(int width, int height, const std::string& backend, const pb::kwargs& settings) {
        base_ = argsOf(settings, "Renderer()");
        addSetting(base_, "width", pb::int_(width), "Renderer()");
        addSetting(base_, "height", pb::int_(height), "Renderer()");
        const RenderOptions o = parseOptions(base_);  // errors now, not at the first frame
        if (auto s = app::settingsFromOptions(o); !s) throwValue(s.error().describe());
        if (!backendFromName(backend, &choice_))
            throwValue("backend '" + backend + "': expected one of " + backendNames());
        Result<Renderer> made = makeError("", "");
        {
            pb::gil_scoped_release unlocked;
            made = Renderer::create(choice_, &note_);
        }
        if (!made) throwRuntime(made.error().describe());
        renderer_.emplace(std::move(*made));
        name_ = renderer_->backendName();
        owner_ = std::this_thread::get_id();
    }

    pb::object render(pb::object particles, pb::object radius, pb::object camera, bool aovs, pb::object velocity,
                      pb::object density, pb::object id, pb::object fluid, pb::object color, pb::object radii,
                      pb::object studio, pb::object frame) {
        if (name_ != "cpu" && std::this_thread::get_id() != owner_)
            throwRuntime("a GL Renderer is bound to the thread that made it (its GL context is current there); "
                         "make one Renderer per thread");
        Args args = base_;
        const CameraArg cam = cameraArg(camera);
        for (const auto& [option, word] : cam.args) args[option] = word;
        if (!radius.is_none()) {
            const float r = radius.cast<float>();
            if (auto st = checkRadius(r); !st) throwValue("radius: " + st.error().message);
            addSetting(args, "radius", radius, "render()");
        }
        const std::optional<Bounds> fixedStudio = studioArg(studio);
        const RenderOptions o = parseOptions(args);
        auto parsed = app::settingsFromOptions(o);
        if (!parsed) throwValue(parsed.error().describe());
        RenderSettings s = std::move(*parsed);
        const Particles p = particlesArg(particles, {pb::reinterpret_borrow<pb::object>(velocity),
                                                     pb::reinterpret_borrow<pb::object>(density),
                                                     pb::reinterpret_borrow<pb::object>(id),
                                                     pb::reinterpret_borrow<pb::object>(fluid),
                                                     pb::reinterpret_borrow<pb::object>(color),
                                                     pb::reinterpret_borrow<pb::object>(radii)},
                                       o.hPerSpacing);
        s.colorOnly = !aovs;  // as the CLI for a PNG
        const std::int64_t index = frame.is_none() ? next_ : frame.cast<std::int64_t>();
        next_ = index + 1;
        s.frameIndex = index;

        checkParticleValues(p, s.particleRadii);

        Frame f;
        Result<Aovs> out = makeError("", "");
        bool argumentError = true;  // until the frame is set up: radius, camera, mesh parameters
        {
            pb::gil_scoped_release unlocked;
            std::lock_guard<std::mutex> lock(mutex_);
            const Status st = prepareFrame(o, p, cam, f);
            if (!st) {
                out = st.error();
            } else {
                s.camera = f.camera;
                s.radiusM = f.radius;
                // As the CLI: the studio around this frame's particles (all of them, spray too).
                const glm::vec3* points =
                    f.turned.empty() ? reinterpret_cast<const glm::vec3*>(p.position.data) : f.turned.data();
                s.scene.studioBounds =
                    fixedStudio ? *fixedStudio : computeBounds(std::span<const glm::vec3>(points, p.size()));
                TriangleMesh mesh;
                if (o.surface == "mesh") {
                    auto made = extractSurface(f.view, app::mesherParams(o.mesher, s.radiusM, 0));
                    if (!made) out = made.error();
                    else mesh = std::move(*made), s.mesh = &mesh;
                }
                if (o.surface != "mesh" || s.mesh) {
                    argumentError = false;
                    out = renderer_->render(f.view, s);
                }
                s.mesh = nullptr;
            }
        }
        if (s.whitening.enabled && !f.view.velocity.present())
            f.warnings.push_back("the particles have no velocity: whiten leaves the colour as it is");
        warnAll(f.warnings);
        if (!out) {
            if (argumentError) throwValue(out.error().describe());
            throwRuntime(out.error().describe());
        }
        pb::array image = adoptImage(encodeSrgb8(out->color));
        if (!aovs) return image;
        return pb::make_tuple(image, aovDict(std::move(*out)));
    }

    const std::string& backend() const { return name_; }
    const std::string& note() const { return note_; }

private:
    Args base_;
    BackendChoice choice_ = BackendChoice::Auto;
    std::optional<Renderer> renderer_;
    std::string name_, note_;
    std::thread::id owner_;
    std::int64_t next_ = 0;
    std::mutex mutex_;  // one frame at a time, the GIL released
};

pb::dict autoCamera(pb::object particles, pb::object radius, int width, int height, const pb::kwargs& settings) {
    Args args = argsOf(settings, "auto_camera()");
    addSetting(args, "width", pb::int_(width), "auto_camera()");
    addSetting(args, "height", pb::int_(height), "auto_camera()");
    if (!radius.is_none()) addSetting(args, "radius", radius, "auto_camera()");
    const RenderOptions o = parseOptions(args);
    if (auto s = app::settingsFromOptions(o); !s) throwValue(s.error().describe());
    const Particles p = particlesArg(particles, {}, o.hPerSpacing);
    Frame f;
    Status st = okStatus();
    {
        pb::gil_scoped_release unlocked;
        st = prepareFrame(o, p, CameraArg{}, f);
    }
    if (!st) throwValue(st.error().describe());
    warnAll(f.warnings);
    // In the data's coordinates, as camera= takes them: the up turn undone.
    app::UpRotation back = *app::upRotation(o.up);
    back.s = -back.s;
    const glm::vec3 eye = back.apply(f.camera.eye), target = back.apply(f.camera.target);
    pb::dict d;
    d["eye"] = pb::make_tuple(eye.x, eye.y, eye.z);
    d["target"] = pb::make_tuple(target.x, target.y, target.z);
    d["fov"] = f.camera.fovYDegrees;
    d["near"] = f.camera.nearM;
    d["far"] = f.camera.farM;
    return d;
}

pb::dict settingsInfo() {
    pb::dict d;
    for (const auto& [name, s] : settingTable()) {
        pb::dict e;
        e["option"] = s.option;
        e["default"] = s.flag ? std::string("False") : s.defaultText;
        e["help"] = s.help;
        d[pb::str(name)] = e;
    }
    return d;
}

}  // namespace

void bindRender(pb::module_& m) {
    pb::class_<PyRenderer>(m, "Renderer", R"(Renders frames, keeping its state between them.

Renderer(width=1280, height=720, backend='auto', **settings)

backend: 'cpu', 'gl' (OpenGL 4.3 through a headless EGL context) or 'auto'
(GL on a GPU, else the CPU, also over a software GL such as llvmpipe).
settings: `meniscus render`'s options under their Python names (--noise-bump
is noise_bump; flags such as noise take True/False; vectors a tuple;
meniscus.settings() lists them with their defaults). An unknown name is a
TypeError, a bad value a ValueError, a GL backend that cannot start a
RuntimeError.

What it keeps: the backend (a GL renderer keeps its context, buffers and
shaders, and must be used from the thread that made it), the studio layer
while camera and studio stay the same, and the velocities of the last frame
for the surface noise's turbulence.)")
        .def(pb::init<int, int, const std::string&, const pb::kwargs&>(), pb::arg("width") = defaults::kWidth,
             pb::arg("height") = defaults::kHeight, pb::arg("backend") = "auto")
        .def("render", &PyRenderer::render, pb::arg("particles"), pb::kw_only(), pb::arg("radius") = pb::none(),
             pb::arg("camera") = pb::none(), pb::arg("aovs") = false, pb::arg("velocity") = pb::none(),
             pb::arg("density") = pb::none(), pb::arg("id") = pb::none(), pb::arg("fluid") = pb::none(),
             pb::arg("color") = pb::none(), pb::arg("radii") = pb::none(), pb::arg("studio") = pb::none(),
             pb::arg("frame") = pb::none(),
             R"(Render one frame; returns the 8-bit sRGB image, H x W x 4 uint8 (row 0 at the top).

particles: N x 3 positions (float32 is used in place; float64 is converted
once), or a dict as read() returns it, whose velocity, density, id, fluid,
color and radius arrays are used as `meniscus render` uses a file's.
radius: metres; None estimates it as the CLI does (estimate_radius()).
camera: None for the CLI's automatic three-quarter view (the settings
azimuth, elevation, distance tune it), or a dict with 'eye' and 'target'
(x, y, z in the data's coordinates) and optionally 'fov' (degrees), 'near',
'far' (metres), e.g. auto_camera()'s, to keep one camera over a sequence.
aovs: also return a dict of float32 images: color (linear RGBA), depth,
raw_depth (eye depth, inf where no liquid), normal (view space), thickness
(metres), and noise, foam, whitening, spray, silhouette, fluid when on.
velocity (N x 3), density (N), id (N, integers), fluid (N, the fluid index
0-3), color (N x 3 linear RGB), radii (N, each particle's radius): per-particle
arrays, overriding the dict's.
studio: ((xmin, ymin, zmin), (xmax, ymax, zmax)), the box the studio is built
around (default: this frame's particles); fix it to keep it still over a
sequence.
frame: the frame's index in its sequence, for the noise's turbulence; None
counts 0, 1, 2, ... over this renderer's calls.

The GIL is released while the frame renders. Positions must be finite (a
NaN is a ValueError naming its row).)")
        .def_property_readonly("backend", &PyRenderer::backend,
                               "The backend in use: 'cpu', or 'gl (<the GL renderer's name>)'.")
        .def_property_readonly("note", &PyRenderer::note,
                               "Why backend='auto' took the CPU (empty when it did not fall back).");
    m.def("auto_camera", &autoCamera, pb::arg("particles"), pb::kw_only(), pb::arg("radius") = pb::none(),
          pb::arg("width") = defaults::kWidth, pb::arg("height") = defaults::kHeight,
          R"(The camera render() chooses for these particles when none is given.

Returns {'eye': (x, y, z), 'target': (x, y, z), 'fov': degrees, 'near': m,
'far': m} in the data's coordinates; pass it as camera= to keep one camera
over a sequence (the CLI frames a sequence once). settings: the same keywords
as render() (azimuth, elevation, distance, fov, up, ... matter here).)");
    m.def("settings", &settingsInfo,
          R"(The settings render() and Renderer take, by Python name.

Returns {name: {'option': the CLI option, 'default': its default as text,
'help': what it does}}. They are `meniscus render`'s options, so a render
scene file's keys and the CLI's documentation apply.)");
}

}  // namespace meniscus::py
