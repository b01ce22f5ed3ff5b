// Rendering: Renderer (the render() of __init__.py is one frame of a fresh
// one), auto_camera(), settings().
//
// Settings are the library's render options (include/meniscus/options.h)
// under their Python names (--noise-bump: noise_bump): each keyword's value
// is set, typed, through the option table (setRenderOption) and the options
// become RenderSettings through the library's renderSettings, as the CLI's
// do, so names, defaults, checks and settings are the CLI's and a render
// matches its PNG byte for byte. The camera for one frame is the library's
// chooseCamera on the points sampled of it, the radius the same
// resolveRadius.
#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "arrays.h"
#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/options.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "meniscus/surface.h"
#include "module.h"

namespace meniscus::py {

namespace {

// ---------------------------------------------------------------- options

// Options that are not keywords: fluid_attribute names a file's attribute
// (give fluid= the array itself).
bool isSetting(const std::string& optionName) { return optionName != "fluid-attribute"; }

std::string settingNames() {
    std::string s;
    for (const RenderOptionSpec& spec : renderOptionTable())
        if (isSetting(spec.name)) s += (s.empty() ? "" : ", ") + keywordName(spec.name);
    for (const MesherOptionSpec& spec : mesherOptionTable()) s += ", " + keywordName(spec.name);
    return s;
}

bool isBool(pb::handle v) {
    return pb::isinstance<pb::bool_>(v) || pb::isinstance(v, pb::module_::import("numpy").attr("bool_"));
}

// A Python value as an option's typed value: True/False, a whole number, a
// number, a text, three numbers (a tuple, list or array: eye=(1, 2, 3)), or
// a list of texts (material=('water', 'lava'), joined by commas as the option
// says them; geometry=[...], one object each).
OptionValue optionValue(pb::handle v, const std::string& name) {
    if (isBool(v)) return v.cast<bool>();
    if (pb::isinstance<pb::str>(v)) return v.cast<std::string>();
    if (pb::hasattr(v, "__index__")) return std::int64_t(pb::int_(pb::reinterpret_borrow<pb::object>(v)));
    if (pb::hasattr(v, "__float__")) return double(pb::float_(pb::reinterpret_borrow<pb::object>(v)));
    if (pb::isinstance<pb::list>(v) || pb::isinstance<pb::tuple>(v) || pb::isinstance<pb::array>(v)) {
        const pb::list items(pb::isinstance<pb::array>(v) ? v.attr("tolist")() : pb::reinterpret_borrow<pb::object>(v));
        bool texts = items.size() > 0;
        for (pb::handle e : items) texts = texts && pb::isinstance<pb::str>(e);
        if (texts) {  // kept apart: a text option joins them with commas, a list option keeps each
            std::vector<std::string> list;
            for (pb::handle e : items) list.push_back(e.cast<std::string>());
            return list;
        }
        if (items.size() == 3) {
            glm::vec3 out;
            for (int k = 0; k < 3; ++k) {
                if (isBool(items[k]) || !pb::hasattr(items[k], "__float__"))
                    throwValue(name + ": expected three numbers (x, y, z)");
                out[k] = float(double(pb::float_(pb::reinterpret_borrow<pb::object>(items[k]))));
            }
            return out;
        }
        throwValue(name + ": expected three numbers (x, y, z) or a list of names");
    }
    throw pb::type_error(name + ": expected a number, a string, True/False or a list of numbers, got " +
                         std::string(pb::str(v.get_type().attr("__name__"))));
}

// One keyword onto `o`: None puts the option back to its default.
void applySetting(RenderOptions& o, const std::string& name, pb::handle value, const char* where) {
    if (name == "fluid_attribute")
        throw pb::type_error(std::string(where) + ": fluid_attribute names a file's attribute; pass the array "
                                                  "itself, fluid=frame['" + "name']");
    const RenderOptionSpec* spec = findRenderOption(name);
    const MesherOptionSpec* mspec = spec ? nullptr : findMesherOption(name);
    if ((!spec && !mspec) || name.find('-') != std::string::npos)
        throw pb::type_error(std::string(where) + ": unexpected keyword argument '" + name +
                             "' (not a setting); the settings (meniscus.settings() describes them) are: " +
                             settingNames());
    if (value.is_none()) {
        RenderOptions fresh;
        const auto reset = [](const OptionRef& to, const OptionRef& from) {
            std::visit([&](auto* p) { *p = *std::get<decltype(p)>(from); }, to);
        };
        if (spec) reset(spec->field(o), spec->field(fresh));
        else reset(mspec->field(o.mesher), mspec->field(fresh.mesher));
        return;
    }
    const OptionValue v = optionValue(value, name);
    const Status st = spec ? setOption(*spec, o, v) : setOption(*mspec, o.mesher, v);
    if (!st) throwValue(st.error().describe());
}

RenderOptions optionsOf(const pb::dict& kw, const char* where, RenderOptions o = {}) {
    for (auto [k, v] : kw) applySetting(o, k.cast<std::string>(), v, where);
    return o;
}

// ---------------------------------------------------------------- camera

// The camera dict's keys: the camera options, and the clip range (which the
// CLI leaves at its defaults for a given eye, and the auto camera sets).
const char* const kCameraOptions[] = {"eye", "target", "fov", "azimuth", "elevation", "distance"};

struct CameraArg {
    pb::dict options;  // a Python object: made, copied and destroyed only with the GIL held
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
        c.options[pb::str(key)] = v;
    }
    return c;
}

// The camera for one frame (the library's chooseCamera on the points sampled
// as the CLI samples a single file), with the near and far planes given.
Result<Camera> frameCamera(const RenderOptions& o, std::span<const glm::vec3> points, float radius,
                           const CameraArg& extra, std::size_t* outside) {
    std::vector<glm::vec3> samples;
    if (!o.eye) {
        sampleFramePoints(points, samples);
        if (!o.geometry.empty()) {  // framed with the particles, as the CLI frames them
            auto geometry = renderGeometry(o.geometry, o.up, o.cutAway == "on");
            if (!geometry) return geometry.error();
            frameGeometry(geometry->get(), samples, nullptr);
        }
    }
    auto cam = chooseCamera(o, samples, radius, outside);
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
    auto up = upRotation(o.up);
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
    std::string note;
    const auto radius = resolveRadius(o.radius, [&] { return defaultRadiusOf(p, points); }, &note);
    if (!radius) return radius.error();
    f.radius = *radius;
    if (note.rfind("warning: ", 0) == 0) f.warnings.push_back(note.substr(9));  // a fallback's line
    std::size_t outside = 0;
    auto cam = frameCamera(o, points, f.radius, extra, &outside);
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

// background=(rgb, depth): the host's picture of the set as numpy arrays,
// H x W x 3 (or 4, with alpha) linear floats and H x W depths whose meaning
// is the backdrop_depth_kind setting (docs/compositing.md); None: the studio
// (or the backdrop setting's files).
std::shared_ptr<const BackdropImage> backgroundArg(pb::handle background, const RenderOptions& o) {
    if (background.is_none()) return nullptr;
    if (!pb::isinstance<pb::sequence>(background) || pb::isinstance<pb::str>(background) ||
        pb::len(background) != 2)
        throwValue("background: expected (rgb, depth), an H x W x 3 (or 4) array of linear colours and an H x W "
                   "array of depths");
    const auto seq = pb::reinterpret_borrow<pb::sequence>(background);
    using Floats = pb::array_t<float, pb::array::c_style | pb::array::forcecast>;
    const Floats rgb = Floats::ensure(seq[0]), depth = Floats::ensure(seq[1]);
    if (!rgb || rgb.ndim() != 3 || (rgb.shape(2) != 3 && rgb.shape(2) != 4))
        throwValue("background: the colour is an H x W x 3 (or H x W x 4) array of linear floats");
    if (!depth || depth.ndim() != 2 || depth.shape(0) != rgb.shape(0) || depth.shape(1) != rgb.shape(1))
        throwValue("background: the depth is an H x W array, the colour's H and W");
    auto kind = parseBackdropDepth(o.backdropDepthKind);
    if (!kind) throwValue("backdrop_depth_kind " + kind.error().message);
    const long h = long(rgb.shape(0)), w = long(rgb.shape(1));
    if (h > kMaxBackdropSidePx || w > kMaxBackdropSidePx)
        throwValue("background: " + std::to_string(w) + "x" + std::to_string(h) + " pixels, more than " +
                   std::to_string(kMaxBackdropSidePx) + " a side");
    auto made = makeBackdrop(int(w), int(h), std::span<const float>(rgb.data(), std::size_t(rgb.size())),
                             int(rgb.shape(2)), std::span<const float>(depth.data(), std::size_t(depth.size())),
                             *kind);
    if (!made) throwValue("background: " + made.error().message);
    if (auto st = checkBackdropSize(*made, o.width, o.height); !st) throwValue("background: " + st.error().message);
    return std::make_shared<const BackdropImage>(std::move(*made));
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
        base_ = optionsOf(settings, "Renderer()");
        applySetting(base_, "width", pb::int_(width), "Renderer()");
        applySetting(base_, "height", pb::int_(height), "Renderer()");
        if (auto s = renderSettings(base_); !s) throwValue(s.error().describe());  // errors now, not at the first frame
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
                      pb::object studio, pb::object frame, pb::object background) {
        if (name_ != "cpu" && std::this_thread::get_id() != owner_)
            throwRuntime("a GL Renderer is bound to the thread that made it (its GL context is current there); "
                         "make one Renderer per thread");
        const CameraArg cam = cameraArg(camera);
        RenderOptions o = optionsOf(cam.options, "camera", base_);
        if (!radius.is_none()) {
            const float r = radius.cast<float>();
            if (auto st = checkRadius(r); !st) throwValue("radius: " + st.error().message);
            applySetting(o, "radius", radius, "render()");
        }
        const std::optional<Bounds> fixedStudio = studioArg(studio);
        auto parsed = renderSettings(o);
        if (!parsed) throwValue(parsed.error().describe());
        RenderSettings s = std::move(*parsed);
        if (auto backdrop = backgroundArg(background, o)) s.scene.backdrop = std::move(backdrop);
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
                if (!fixedStudio) {  // around the scene's objects too, as the CLI
                    std::vector<glm::vec3> none;
                    frameGeometry(s.geometry.get(), none, &s.scene.studioBounds);
                }
                TriangleMesh mesh;
                if (o.surface == "mesh") {
                    auto made = extractSurface(f.view, mesherParams(o.mesher, s.radiusM, 0));
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
    RenderOptions base_;
    BackendChoice choice_ = BackendChoice::Auto;
    std::optional<Renderer> renderer_;
    std::string name_, note_;
    std::thread::id owner_;
    std::int64_t next_ = 0;
    std::mutex mutex_;  // one frame at a time, the GIL released
};

pb::dict autoCamera(pb::object particles, pb::object radius, int width, int height, const pb::kwargs& settings) {
    RenderOptions o = optionsOf(settings, "auto_camera()");
    applySetting(o, "width", pb::int_(width), "auto_camera()");
    applySetting(o, "height", pb::int_(height), "auto_camera()");
    if (!radius.is_none()) applySetting(o, "radius", radius, "auto_camera()");
    if (auto s = renderSettings(o); !s) throwValue(s.error().describe());
    const Particles p = particlesArg(particles, {}, o.hPerSpacing);
    Frame f;
    Status st = okStatus();
    const CameraArg none;  // made (a Python dict) while the GIL is held
    {
        pb::gil_scoped_release unlocked;
        st = prepareFrame(o, p, none, f);
    }
    if (!st) throwValue(st.error().describe());
    warnAll(f.warnings);
    // In the data's coordinates, as camera= takes them: the up turn undone.
    const UpRotation back = upRotation(o.up)->inverse();
    const glm::vec3 eye = back.apply(f.camera.eye), target = back.apply(f.camera.target);
    pb::dict d;
    d["eye"] = pb::make_tuple(eye.x, eye.y, eye.z);
    d["target"] = pb::make_tuple(target.x, target.y, target.z);
    d["fov"] = f.camera.fovYDegrees;
    d["near"] = f.camera.nearM;
    d["far"] = f.camera.farM;
    return d;
}

pb::dict settingsInfo(const std::string& command) {
    pb::dict d;
    const auto put = [&](const auto& spec) {
        pb::dict e;
        e["option"] = "--" + spec.name;
        e["default"] = spec.flag ? std::string("False") : defaultText(spec);
        e["unit"] = spec.unit;
        e["group"] = optionGroupTitle(spec.group);
        e["help"] = spec.help;
        d[pb::str(keywordName(spec.name))] = e;
    };
    if (command == "render") {
        for (const RenderOptionSpec& spec : renderOptionTable())
            if (isSetting(spec.name)) put(spec);
        for (const MesherOptionSpec& spec : mesherOptionTable()) put(spec);
    } else if (command == "mesh") {  // mesh()'s keywords: `meniscus mesh`'s rows
        put(*findIn(meshOptionTable(), "radius"));
        for (const MesherOptionSpec& spec : mesherOptionTable()) put(spec);
        put(*findRenderOption("h-per-spacing"));
    } else if (command == "simulate") {  // simulate()'s keywords: `meniscus simulate`'s rows
        for (const char* name : kSimulateKeywords) put(*findIn(simulateOptionTable(), name));
    } else {
        throwValue("settings: '" + command + "': expected 'render', 'mesh' or 'simulate'");
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
             pb::arg("frame") = pb::none(), pb::arg("background") = pb::none(),
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
background: (rgb, depth), another renderer's picture of the set made by this
camera at this size: rgb H x W x 3 (or 4, with alpha) linear floats, depth
H x W, whose meaning the backdrop_depth_kind setting gives ('linear' eye
depth, 'ray' distance, 'blender', 'window:NEAR,FAR'). It replaces the studio:
the set hides the liquid where it is nearer, and the liquid refracts it
(docs/compositing.md).

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
    m.def("settings", &settingsInfo, pb::arg("command") = "render",
          R"(The settings render() and Renderer take, by Python name; with command='mesh'
or 'simulate', the keywords mesh() or simulate() take.

Returns {name: {'option': the CLI option, 'default': its default as text
('' when the default is the input's or the scene's own), 'unit': its unit
('' for none), 'group': where --help lists it, 'help': what it does}}. They
are `meniscus render`'s (mesh's, simulate's) options, so a render scene
file's keys and the CLI's documentation apply.)");
}

}  // namespace meniscus::py
