// The render options and sequence set-up shared by render, demo and view (see common.h).
#include "common.h"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

#include <CLI/CLI.hpp>

#include "help_format.h"
#include "meniscus/boundary.h"
#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/geometry.h"
#include "meniscus/sim.h"
#include "scene_file.h"
#include "simulate.h"

namespace fs = std::filesystem;

namespace meniscus::app {

namespace {

// The camera (chooseCamera), radius and studio box for a whole sequence.
// `geometry` is what is framed with the points (the settings' own when null).
Status fixCamera(const RenderJob& o, const std::vector<glm::vec3>& samplePoints, float radius,
                 const Bounds& studio, RenderSettings& settings, const SceneGeometry* geometry = nullptr) {
    Bounds box = studio;
    std::vector<glm::vec3> points = samplePoints;
    frameGeometry(geometry ? geometry : settings.geometry.get(), points, &box);
    auto camera = chooseCamera(o, points, radius);
    if (!camera) return camera.error();
    settings.camera = *camera;
    settings.radiusM = radius;
    settings.scene.studioBounds = box;
    return okStatus();
}

}  // namespace

Result<Camera> chooseCamera(const RenderJob& o, std::span<const glm::vec3> samplePoints, float radius,
                            std::size_t* outsideCount) {
    if (o.cameraPath.empty()) {
        std::size_t outside = 0;
        auto cam = meniscus::chooseCamera(o, samplePoints, radius, &outside);
        if (!cam) return cam;
        if (outsideCount) *outsideCount = outside;
        else if (outside > 0)
            std::cerr << "meniscus: auto camera: " << outside << " of " << samplePoints.size()
                      << " sampled particles (the outermost) left outside the frame\n";
        return cam;
    }
    // The path's first key; runRender moves the camera along the rest.
    if (o.eye || o.target) return makeError("", "--camera-path sets the eye and target: leave out --eye and --target");
    auto keys = cameraPathFromOptions(o);
    if (!keys) return keys.error();
    Camera cam;
    cam.width = o.width;
    cam.height = o.height;
    cam.nearM = defaults::kNearM;
    cam.farM = defaults::kFarM;
    cam.eye = keys->front().eye;
    cam.target = keys->front().target;
    cam.fovYDegrees = keys->front().fovYDegrees;
    if (auto st = validateCamera(cam); !st) return st.error();
    return cam;
}

int fail(const std::string& line) {
    std::cerr << "meniscus: error: " << line << "\n";
    return 1;
}

int failUsage(const std::string& line) {
    std::cerr << "meniscus: error: " << line << "\n";
    return 2;
}

int fail(const Error& error) {
    std::cerr << "meniscus: error: " << error.describe() << "\n";
    return error.usage ? 2 : 1;
}

void printWarnings(const ParticleSet& set) {
    for (const auto& w : set.warnings) std::cerr << "meniscus: warning: " << w << "\n";
}

bool isExr(const std::string& path) { return fs::path(path).extension() == ".exr"; }
bool isPng(const std::string& path) { return fs::path(path).extension() == ".png"; }
bool isMp4(const std::string& path) { return fs::path(path).extension() == ".mp4"; }

CLI::Option* addTableOption(CLI::App* cmd, const std::string& name, OptionGroup group, const std::string& help,
                            const OptionRef& ref, const OptionLimits& limits, bool flag, bool noDefault) {
    // The default shown is the bound value's (a command may set its own, e.g. simulate's --backend cpu).
    const std::string defaultText = noDefault ? std::string() : optionText(ref);
    const std::string option = "--" + name;
    CLI::Option* opt = std::visit(
        [&](auto* p) -> CLI::Option* {
            using T = std::remove_pointer_t<decltype(p)>;
            if constexpr (std::is_same_v<T, bool>) {
                if (flag) return cmd->add_flag(option, *p, help);
                return cmd->add_option(option, *p, help);
            } else if constexpr (std::is_same_v<T, int> || std::is_same_v<T, float> || std::is_same_v<T, double> ||
                                 std::is_same_v<T, std::uint64_t> || std::is_same_v<T, std::string>) {
                return cmd->add_option(option, *p, help);
            } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
                // A list: the option repeated, one value each time, taken
                // whole (CLI11 would otherwise split a value in brackets at its
                // commas, and inline JSON such as [{"box": ...}, ...] is one).
                return cmd->add_option(option, *p, help)->allow_extra_args(false);
            } else if constexpr (std::is_same_v<T, std::vector<float>>) {
                // Its count of numbers, "a,b,c" or "a b c"; too few or too many is bad usage.
                return cmd->add_option(option, *p, help)->delimiter(',')->expected(int(limits.count));
            } else {
                // Three numbers "x,y,z", checked as the library checks them.
                return cmd->add_option_function<std::string>(
                              option,
                              [p, name, limits](const std::string& text) {
                                  const auto v = parseVec3(text);
                                  if (!v) throw CLI::ValidationError("--" + name + " " + text +
                                                                     ": expected three numbers x,y,z");
                                  T value{*v};
                                  if (auto st = checkOptionValue(name, OptionRef(&value), limits); !st)
                                      throw CLI::ValidationError(st.error().message);
                                  *p = *v;
                              },
                              help)
                    ->type_name("X,Y,Z");
            }
        },
        ref);
    opt->group(optionGroupTitle(group));
    if (!limits.choices.empty()) {
        std::string list;
        for (const std::string& c : limits.choices) list += (list.empty() ? "" : ",") + c;
        opt->type_name("TEXT:{" + list + "}");
        // A value not among the choices is bad usage (exit 2), said as the library says it.
        opt->check(CLI::Validator(
            [name, limits](std::string& text) -> std::string {
                std::string value = text;
                const Status st = checkOptionValue(name, OptionRef(&value), limits);
                return st ? std::string() : st.error().message.substr(name.size() + 3);  // less "--NAME "
            },
            ""));
    }
    if (!defaultText.empty() && !flag) opt->default_str(defaultText);
    // Numbers (each of a list's) in range as the library checks them.
    std::visit(
        [&](auto* p) {
            using T = std::remove_pointer_t<decltype(p)>;
            if constexpr (std::is_same_v<T, int> || std::is_same_v<T, float> || std::is_same_v<T, double> ||
                          std::is_same_v<T, std::uint64_t> || std::is_same_v<T, std::vector<float>>) {
                if (limits.positive) {
                    opt->check(CLI::PositiveNumber);
                    if (std::isfinite(limits.max)) opt->check(CLI::Range(0.0, limits.max));
                }
                else if (limits.min == 0.0 && std::isinf(limits.max)) opt->check(CLI::NonNegativeNumber);
                else if (!std::isnan(limits.min) && !std::isnan(limits.max)) {
                    if constexpr (std::is_same_v<T, int>) opt->check(CLI::Range(int(limits.min), int(limits.max)));
                    else if constexpr (std::is_same_v<T, std::uint64_t>)
                        opt->check(CLI::Range(std::uint64_t(limits.min), std::uint64_t(limits.max)));
                    else opt->check(CLI::Range(limits.min, limits.max));
                }
            }
        },
        ref);
    return opt;
}

void addTableOptions(CLI::App* cmd, meniscus::RenderOptions& o,
                     const std::function<bool(const RenderOptionSpec&)>& keep) {
    for (const RenderOptionSpec& s : renderOptionTable())
        if (keep(s)) addRow(cmd, s, s.field(o));
}

void addJobTableOptions(CLI::App* cmd, JobOptions& o, const std::vector<std::string>& names) {
    for (const std::string& name : names) {
        const JobOptionSpec& s = *findJobOption(name);
        addRow(cmd, s, s.field(o));
    }
}

void addMesherTableOptions(CLI::App* cmd, MesherOptions& o) { addRows(cmd, mesherOptionTable(), o); }

void addSmoothingLengthOption(CLI::App* cmd, float& hPerSpacing) {
    const RenderOptionSpec& s = *findRenderOption("h-per-spacing");
    addRow(cmd, s, &hPerSpacing);
}

namespace {
// The ray cast's options follow the mesher's under --surface (addSurfaceOptions).
bool surfaceOption(const RenderOptionSpec& s) { return s.name == "surface" || s.name.rfind("raycast-", 0) == 0; }
}  // namespace

void addCameraOptions(CLI::App* cmd, RenderJob& o, bool radiusOption) {
    addTableOptions(cmd, o, [&](const RenderOptionSpec& s) {
        return !surfaceOption(s) && (radiusOption || (s.name != "radius" && s.name != "h-per-spacing"));
    });
}

void addSurfaceOptions(CLI::App* cmd, RenderJob& o) {
    addTableOptions(cmd, o, [](const RenderOptionSpec& s) { return s.name == "surface"; });
    addMesherTableOptions(cmd, o.mesher);
    addTableOptions(cmd, o, [](const RenderOptionSpec& s) { return s.name.rfind("raycast-", 0) == 0; });
}

void addBackendOption(CLI::App* cmd, RenderJob& o) { addJobTableOptions(cmd, o, {"backend"}); }

Result<RenderSettings> settingsFromOptions(const RenderJob& o) {
    if (!o.moreFluids.empty() && o.surface == "mesh")
        return makeError("", "--fluid-attribute, --fluid: several fluids are drawn by the screen-space surface, not "
                             "--surface mesh");
    return renderSettings(o, !o.diffuse.empty());
}

Result<Renderer> makeRenderer(const RenderJob& o) {
    BackendChoice choice = BackendChoice::Auto;
    if (!backendFromName(o.backend, &choice))
        return makeError("", "--backend " + o.backend + ": expected one of " + backendNames());
    std::string note;
    auto made = Renderer::create(choice, &note);
    if (made && !note.empty()) std::cerr << "meniscus: " << note << "\n";
    return made;
}

Status writeImage(const std::string& path, const Aovs& aovs, bool withAlpha) {
    if (isExr(path)) return writeExrAovs(path, aovs);
    return writePng(path, aovs.color, withAlpha);
}

Status useFluidAttribute(ParticleSet& set, const std::string& name) {
    const Attribute* a = set.find(name);
    if (!a) {
        std::string have;
        for (const Attribute& b : set.attributes) have += (have.empty() ? "" : ", ") + b.name;
        return makeError("", "--fluid-attribute " + name + ": no such attribute (the file has: " +
                                 (have.empty() ? std::string("none") : have) + ")");
    }
    if (a->components != 1 || a->count() != set.size())
        return makeError("", "--fluid-attribute " + name + ": expected one value per particle, it has " +
                                 std::to_string(a->components) + " components");
    Attribute fluid;
    fluid.name = std::string(kAttrFluid);
    fluid.type = AttributeType::Int;
    if (a->type == AttributeType::Int) {
        fluid.ints = a->ints;
    } else {
        fluid.ints.reserve(a->floats.size());
        for (std::size_t i = 0; i < a->floats.size(); ++i) {
            const float v = a->floats[i];
            if (!(std::fabs(v) < 1e9f) || v != std::floor(v))
                return makeError("", "--fluid-attribute " + name + ": particle " + std::to_string(i) + " has " +
                                         std::to_string(v) + ", not a whole number");
            fluid.ints.push_back(std::int64_t(v));
        }
    }
    if (name == kAttrFluid) return okStatus();
    if (Attribute* old = set.find(kAttrFluid)) *old = std::move(fluid);
    else set.attributes.push_back(std::move(fluid));
    return okStatus();
}

void addFluidInputOption(CLI::App* cmd, RenderJob& o) { addJobTableOptions(cmd, o, {"fluid", "select"}); }

void addSelectOption(CLI::App* cmd, std::string& select) {
    const JobOptionSpec& s = *findJobOption("select");
    addRow(cmd, s, &select);
}

Status Frames::setSelection(const std::string& text) {
    auto parsed = parseSelection(text);
    if (!parsed) return parsed.error();
    selection = std::move(*parsed);
    return okStatus();
}

void appendFluid(ParticleSet& set, const ParticleSet& more, int fluid) {
    constexpr std::int64_t kIdOffset = std::int64_t(1) << 40;
    if (!set.find(kAttrFluid)) {
        Attribute index;
        index.name = std::string(kAttrFluid);
        index.type = AttributeType::Int;
        index.ints.assign(set.size(), 0);
        set.attributes.push_back(std::move(index));
    }
    set.positions.insert(set.positions.end(), more.positions.begin(), more.positions.end());
    std::vector<Attribute> kept;
    for (Attribute& a : set.attributes) {
        if (a.name == kAttrFluid) {
            a.ints.resize(set.size(), std::int64_t(fluid));
            kept.push_back(std::move(a));
            continue;
        }
        const Attribute* b = more.find(a.name);
        if (!b || b->type != a.type || b->components != a.components || b->count() != more.size()) {
            set.warnings.push_back("attribute '" + a.name + "' is not in every fluid's file alike: left out");
            continue;
        }
        a.floats.insert(a.floats.end(), b->floats.begin(), b->floats.end());
        for (std::int64_t v : b->ints) a.ints.push_back(a.name == kAttrId ? v + std::int64_t(fluid) * kIdOffset : v);
        kept.push_back(std::move(a));
    }
    for (const Attribute& b : more.attributes)
        if (b.name != kAttrFluid &&
            std::none_of(set.attributes.begin(), set.attributes.end(), [&](const Attribute& a) { return a.name == b.name; }))
            set.warnings.push_back("attribute '" + b.name + "' is not in every fluid's file alike: left out");
    set.attributes = std::move(kept);
}

Status Frames::addFluids(const RenderJob& o) {
    if (auto st = setSelection(o.select); !st) return st;
    fluidAttribute = o.fluidAttribute;
    if (o.moreFluids.empty()) return okStatus();
    if (!o.fluidAttribute.empty()) return makeError("", "--fluid and --fluid-attribute: give one or the other");
    if (embedded) return makeError("", "--fluid needs an input (the demo frame is one fluid)");
    if (o.moreFluids.size() + 1 > std::size_t(kMaxFluids))
        return makeError("", std::to_string(o.moreFluids.size() + 1) + " fluids (the input and " +
                                 std::to_string(o.moreFluids.size()) + " --fluid): at most " +
                                 std::to_string(kMaxFluids));
    for (const std::string& spec : o.moreFluids) {
        auto list = expandSequence(spec);
        if (!list) return list.error();
        if (list->size() != files.size())
            return makeError(spec, "--fluid: " + std::to_string(list->size()) + " frame(s), the input has " +
                                       std::to_string(files.size()));
        moreFluids.push_back(std::move(*list));
    }
    return okStatus();
}

void applyUp(const UpRotation& up, ParticleSet& set) {
    if (up.identity) return;
    for (glm::vec3& p : set.positions) p = up.apply(p);
    Attribute* v = set.find(kAttrVelocity);
    if (v && v->type == AttributeType::Float && v->components == 3)
        for (std::size_t k = 0; k + 2 < v->floats.size(); k += 3) {
            const glm::vec3 t = up.apply(glm::vec3(v->floats[k], v->floats[k + 1], v->floats[k + 2]));
            v->floats[k] = t.x, v->floats[k + 1] = t.y, v->floats[k + 2] = t.z;
        }
}

Result<ParticleSet> Frames::load(std::size_t i, std::string* smoothingLength) const {
    auto set = embedded ? Result<ParticleSet>(*embedded) : readParticles(files[source(i)]);
    // --select first: its positions and velocities are the file's, before --up.
    if (set)
        if (auto st = applySelection(*set, selection, name(i)); !st) return st.error();
    if (set) applyUp(up, *set);
    if (set) {
        auto h = addRadiusFromSmoothingLength(*set, hPerSpacing);
        if (!h) return h.error();
        if (smoothingLength) *smoothingLength = *h;
    }
    if (set && !fluidAttribute.empty())
        if (auto st = useFluidAttribute(*set, fluidAttribute); !st)
            return makeError(name(i), st.error().message);
    for (std::size_t k = 0; set && k < moreFluids.size(); ++k) {
        auto more = readParticles(moreFluids[k][source(i)]);
        if (!more) return more.error();
        if (auto st = applySelection(*more, selection, moreFluids[k][source(i)].string()); !st) return st.error();
        applyUp(up, *more);
        if (auto h = addRadiusFromSmoothingLength(*more, hPerSpacing); !h) return h.error();
        set->warnings.insert(set->warnings.end(), more->warnings.begin(), more->warnings.end());
        appendFluid(*set, *more, int(k) + 1);
    }
    return set;
}

Status Frames::checkOutput(const std::string& output, const char* example) const {
    if (count() > 1 && output.find('%') == std::string::npos)
        return makeError(output, std::to_string(count()) + " input frames need an output pattern with a frame number, e.g. " +
                                     example);
    return okStatus();
}

long Frames::outputNumber(std::size_t i) const {
    if (renumber || repeat) return long(i);
    const long number = embedded ? 0 : frameNumberOf(files[i]);  // run.h5part/Step#12 -> 12
    return number >= 0 ? number : long(i);
}

Result<std::string> Frames::outputName(const std::string& output, std::size_t i) const {
    if (output.find('%') == std::string::npos) return output;
    return formatFramePattern(output, outputNumber(i));
}

void printSmoothingLengthNote(const std::string& attribute, float hPerSpacing) {
    std::fprintf(stderr, "meniscus: radii from the smoothing length '%s': r = %s / (2 x %g) (--h-per-spacing)\n",
                 attribute.c_str(), attribute.c_str(), double(hPerSpacing));
}

Result<Frames> openFrames(const std::string& input, const ParticleSet* embedded, float hPerSpacing) {
    Frames frames;
    frames.embedded = embedded;
    frames.hPerSpacing = hPerSpacing;
    if (!embedded) {
        auto list = expandSequence(input);
        if (!list) return list.error();
        frames.files = std::move(*list);
    }
    return frames;
}

Result<ParticleSet> Frames::loadChecked(std::size_t i, std::string* smoothingLength) const {
    auto set = load(i, smoothingLength);
    if (!set) return set.error();
    if (auto st = checkCoordinates(set->positions, name(i)); !st) return st.error();
    return set;
}

std::string Frames::name(std::size_t i) const {
    if (!simulation.empty()) return simulation + " (frame " + std::to_string(i) + ")";
    return embedded ? std::string("the demo frame") : files[source(i)].string();
}

Result<ParticleSet> fixForSequence(const RenderJob& o, const Frames& frames, RenderSettings& settings,
                                   std::size_t* firstIndex) {
    // With --on-error skip the first frame that loads sets the radius and the
    // studio, and the camera samples only frames that load.
    const bool skip = o.onError == "skip";
    std::string smoothingLength;
    std::size_t f = 0;
    auto first = frames.loadChecked(0, &smoothingLength);
    while (!first && skip && f + 1 < frames.count()) first = frames.loadChecked(++f, &smoothingLength);
    if (!first) return first.error();
    if (firstIndex) *firstIndex = f;
    const std::string firstName = frames.name(f);
    // DualSPHysics' boundary particles (--boundary-particles): the radius and
    // the framing are the liquid's, the first frame's walls framed as geometry.
    ParticleSet liquid = *first;
    auto walls = prepareBoundary(liquid, o, settings.geometry, firstName);
    if (!walls) return walls.error();
    std::string note;
    // (A frame of boundary particles alone, such as DualSPHysics' PartBound, has
    // no liquid to estimate from: its own particles' radius, never drawn.)
    const auto resolved =
        resolveRadius(o.radius, [&] { return defaultRadius(liquid.size() > 0 ? liquid : *first); }, &note);
    if (!note.empty()) {
        std::cerr << "meniscus: " << note << "\n";
        if (!smoothingLength.empty()) printSmoothingLengthNote(smoothingLength, frames.hPerSpacing);
    }
    if (!resolved) return makeError(firstName, resolved.error().message);
    const float radius = *resolved;
    std::vector<glm::vec3> samplePoints;
    const auto addSample = [&](const std::vector<glm::vec3>& p) { sampleFramePoints(p, samplePoints); };
    const std::size_t count = frames.repeat ? 1 : frames.count();  // a repeated file: nothing more to sample
    if (!o.eye && o.cameraPath.empty()) {
        addSample(liquid.positions);
        const std::size_t last = defaults::kSequenceFramingFrames - 1;
        for (std::size_t k = 1; count > 1 && k <= last; ++k) {
            const std::size_t i = k * (count - 1) / last;
            if (i <= f) continue;
            auto s = frames.loadChecked(i);
            if (!s && skip) continue;
            if (!s) return s.error();
            if (o.boundaryParticles != "liquid") {  // the liquid's particles only
                auto taken = takeBoundaryParticles(*s, frames.name(i));
                if (!taken) return taken.error();
            }
            addSample(s->positions);
        }
    }
    // The studio is built around the first frame and stays put for the sequence.
    if (auto st = fixCamera(o, samplePoints, radius, computeBounds(liquid.positions), settings, walls->get()); !st)
        return st.error();
    return first;
}

Result<std::vector<CameraKey>> cameraPathFromOptions(const RenderJob& o) {
    if (o.cameraPath.empty()) return std::vector<CameraKey>{};
    auto keys = readCameraPath(o.cameraPath, o.fov);
    if (!keys) return keys.error();
    auto up = meniscus::upRotation(o.up);
    if (!up) return up.error();
    for (CameraKey& k : *keys) {
        k.eye = up->apply(k.eye);
        k.target = up->apply(k.target);
    }
    return keys;
}

Status fixForScene(const RenderJob& o, const sim::Scene& scene, RenderSettings& settings) {
    auto world = simulationGeometry(scene);
    if (!world) return world.error();
    addGeometry(settings, std::move(*world), o.cutAway == "on");
    return fixForBox(o, domainBounds(scene), scene.params.radius, settings);
}

Status fixForBox(const RenderJob& o, const Bounds& box, float radiusM, RenderSettings& settings) {
    std::vector<glm::vec3> corners;
    for (int c = 0; c < 8; ++c)
        corners.push_back({c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y,
                           c & 4 ? box.max.z : box.min.z});
    return fixCamera(o, corners, radiusM, box, settings);
}

}  // namespace meniscus::app
