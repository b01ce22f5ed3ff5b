// The `meniscus` command line: argument parsing and messages only; the work is
// done by the library. Errors: one line on stderr naming the file and the
// problem, exit code 1 (2 for bad usage).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "demo_data.h"
#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/params.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "progress.h"

namespace fs = std::filesystem;
using namespace meniscus;

namespace {

int fail(const std::string& line) {
    std::cerr << "meniscus: error: " << line << "\n";
    return 1;
}

void printWarnings(const ParticleSet& set) {
    for (const auto& w : set.warnings) std::cerr << "meniscus: warning: " << w << "\n";
}

std::optional<glm::vec3> parseVec3(const std::string& text) {
    std::istringstream in(text);
    glm::vec3 v;
    char c1 = 0, c2 = 0;
    if (!(in >> v.x >> c1 >> v.y >> c2 >> v.z) || c1 != ',' || c2 != ',') return std::nullopt;
    in >> std::ws;
    if (!in.eof()) return std::nullopt;
    return v;
}

const char* typeName(const Attribute& a) {
    if (a.type == AttributeType::Int) return "int";
    return a.components == 3 ? "vector" : "float";
}

// ------------------------------------------------------------------ info

struct InfoOptions {
    std::string input;
    bool json = false;
};

int runInfo(const InfoOptions& o) {
    auto frames = expandSequence(o.input);
    if (!frames) return fail(frames.error().describe());
    auto set = readParticles(frames->front());
    if (!set) return fail(set.error().describe());
    printWarnings(*set);

    const Bounds b = computeBounds(set->positions);
    const RadiusEstimate radius = estimateRadius(set->positions);
    const auto density = attributeStats(*set, kAttrDensity);

    if (o.json) {
        nlohmann::json j;
        j["file"] = frames->front().string();
        if (frames->size() > 1) j["frames"] = frames->size();
        j["count"] = set->size();
        j["bounds_min"] = {b.min.x, b.min.y, b.min.z};
        j["bounds_max"] = {b.max.x, b.max.y, b.max.z};
        j["attributes"] = nlohmann::json::array();
        for (const auto& a : set->attributes)
            j["attributes"].push_back({{"name", a.name}, {"type", typeName(a)}, {"components", a.components}});
        j["radius_estimate"] = radius.radius;
        if (density) j["density"] = {{"min", density->min}, {"median", density->median}, {"max", density->max}};
        j["warnings"] = set->warnings;
        std::cout << j.dump() << "\n";
        return 0;
    }
    std::printf("file        %s\n", frames->front().string().c_str());
    if (frames->size() > 1) std::printf("frames      %zu (first shown)\n", frames->size());
    std::printf("particles   %zu\n", set->size());
    std::printf("bounds      (%.5g, %.5g, %.5g) .. (%.5g, %.5g, %.5g) m\n", b.min.x, b.min.y, b.min.z, b.max.x,
                b.max.y, b.max.z);
    std::printf("attributes ");
    for (const auto& a : set->attributes) std::printf(" %s(%s%s)", a.name.c_str(), typeName(a),
                                                      a.components > 1 && a.components != 3 ? "[]" : "");
    std::printf("%s\n", set->attributes.empty() ? " none" : "");
    std::printf("radius      %.5g m (half the median nearest-neighbour distance%s)\n", radius.radius,
                radius.fallback ? "; too few particles, fallback used" : "");
    if (density)
        std::printf("density     min %.2f  median %.2f  max %.2f\n", density->min, density->median, density->max);
    return 0;
}

// ------------------------------------------------------------------ render

struct RenderOptions {
    std::string input;
    std::string output;
    int width = defaults::kWidth;
    int height = defaults::kHeight;
    std::string eye, target, up = "0,1,0";
    float fov = defaults::kFovYDegrees;
    float radius = 0.0f;  // 0 = estimate
    std::string view = "final";
    std::string filter = "narrow-range";
    int iterations = -1;  // -1 = the filter's default
    bool separable = false;
    std::string material = "water";
    std::string background = "studio";
    std::string backend = "auto";
};

// The pipeline settings named by the options (camera and radius come later).
Result<RenderSettings> settingsFromOptions(const RenderOptions& o) {
    RenderSettings s;
    if (!viewFromName(o.view, &s.view)) return makeError("", "--view " + o.view + ": expected one of " + viewNames());
    if (!filterFromName(o.filter, &s.filter))
        return makeError("", "--filter " + o.filter + ": expected one of " + filterNames());
    if (o.iterations >= 0) setFilterIterations(s.filter, o.iterations);
    if (o.separable) {
        auto* nr = std::get_if<NarrowRangeParams>(&s.filter);
        if (!nr) return makeError("", "--separable applies to --filter narrow-range only");
        nr->separable = true;
    }
    if (!materialPreset(o.material, &s.shading.material))
        return makeError("", "--material " + o.material + ": expected one of " + materialPresetNames());
    if (o.background != "studio" && o.background != "none")
        return makeError("", "--background " + o.background + ": expected studio or none");
    s.scene.background = o.background == "studio";
    return s;
}

bool isExr(const std::string& path) { return fs::path(path).extension() == ".exr"; }
bool isPng(const std::string& path) { return fs::path(path).extension() == ".png"; }

// The camera for a whole sequence: the user's, or auto-framed on the particles
// of a few frames (first, last, three between).
Result<Camera> chooseCamera(const RenderOptions& o, const std::vector<glm::vec3>& samplePoints, float radius) {
    Camera cam;
    cam.width = o.width;
    cam.height = o.height;
    cam.fovYDegrees = o.fov;
    cam.nearM = defaults::kNearM;
    cam.farM = defaults::kFarM;
    if (o.eye.empty() != o.target.empty()) return makeError("", "give both --eye and --target, or neither");
    if (!o.eye.empty()) {
        auto eye = parseVec3(o.eye), target = parseVec3(o.target), up = parseVec3(o.up);
        if (!eye || !target || !up) return makeError("", "--eye, --target and --up take three numbers: x,y,z");
        cam.eye = *eye;
        cam.target = *target;
        cam.up = *up;
    } else {
        cam = autoFrameCamera(samplePoints, radius, cam);
    }
    if (auto st = validateCamera(cam); !st) return st.error();
    return cam;
}

Status writeOutput(const std::string& path, const Aovs& aovs, bool withAlpha) {
    if (isExr(path)) return writeExrAovs(path, aovs);
    return writePng(path, aovs.color, withAlpha);
}

int runRender(const RenderOptions& o, const ParticleSet* embedded) {
    if (!isPng(o.output) && !isExr(o.output))
        return fail(o.output + ": output must end in .png or .exr");
    auto parsed = settingsFromOptions(o);
    if (!parsed) return fail(parsed.error().describe());
    RenderSettings settings = std::move(*parsed);
    if (!(o.radius >= 0.0f)) return fail("--radius must be a positive number of metres");

    std::vector<fs::path> frames;
    if (!embedded) {
        auto list = expandSequence(o.input);
        if (!list) return fail(list.error().describe());
        frames = std::move(*list);
    }
    const std::size_t count = embedded ? 1 : frames.size();
    const bool pattern = o.output.find('%') != std::string::npos;
    if (count > 1 && !pattern)
        return fail(o.output + ": " + std::to_string(count) +
                    " input frames need an output pattern with a frame number, e.g. out_%04d.png");

    auto load = [&](std::size_t i) -> Result<ParticleSet> {
        if (embedded) return *embedded;
        return readParticles(frames[i]);
    };

    // Radius and camera are fixed once per sequence, so the animation does not flicker.
    auto first = load(0);
    if (!first) return fail(first.error().describe());
    float radius = o.radius;
    if (radius == 0.0f) {
        const RadiusEstimate est = estimateRadius(first->positions);
        radius = est.radius;
        if (est.fallback)
            std::cerr << "meniscus: warning: too few particles to estimate the radius; using " << radius
                      << " m (set --radius)\n";
    }
    std::vector<glm::vec3> samplePoints;
    auto addSample = [&](const std::vector<glm::vec3>& p) {
        const std::size_t stride = std::max<std::size_t>(1, p.size() / 20000);
        for (std::size_t i = 0; i < p.size(); i += stride) samplePoints.push_back(p[i]);
    };
    if (o.eye.empty()) {
        addSample(first->positions);
        for (std::size_t k = 1; count > 1 && k <= 4; ++k) {
            auto s = load(k * (count - 1) / 4);
            if (!s) return fail(s.error().describe());
            addSample(s->positions);
        }
    }
    auto camera = chooseCamera(o, samplePoints, radius);
    if (!camera) return fail(camera.error().describe());

    settings.camera = *camera;
    settings.radiusM = radius;
    settings.colorOnly = !isExr(o.output);  // a PNG needs only the colour AOV
    // The studio is built around the first frame and stays put for the sequence.
    settings.scene.studioBounds = computeBounds(first->positions);

    BackendChoice choice = BackendChoice::Auto;
    if (!backendFromName(o.backend, &choice)) return fail("--backend " + o.backend + ": expected one of " + backendNames());
    std::string note;
    auto made = Renderer::create(choice, &note);
    if (!made) return fail(made.error().describe());
    if (!note.empty()) std::cerr << "meniscus: " << note << "\n";
    Renderer renderer = std::move(*made);
    ProgressBar progress(count, "rendering");
    for (std::size_t i = 0; i < count; ++i) {
        auto set = i == 0 ? std::move(first) : load(i);
        if (!set) return fail(set.error().describe());
        printWarnings(*set);
        auto aovs = renderer.render(set->positions, settings);
        if (!aovs) return fail(aovs.error().describe());

        std::string out = o.output;
        if (pattern) {
            const long number = embedded ? 0 : frameNumberFromName(frames[i].filename().string());
            auto name = formatFramePattern(o.output, number >= 0 ? number : long(i));
            if (!name) return fail(name.error().describe());
            out = *name;
        }
        if (auto st = writeOutput(out, *aovs, !settings.scene.background); !st) return fail(st.error().describe());
        progress.update(i + 1);
        if (count == 1) std::cerr << "meniscus: wrote " << out << "\n";
    }
    if (count > 1) std::cerr << "meniscus: wrote " << count << " frames to " << o.output << "\n";
    return 0;
}

void addCameraOptions(CLI::App* cmd, RenderOptions& o) {
    cmd->add_option("--width", o.width, "Image width in pixels")->capture_default_str()->check(CLI::Range(1, 16384));
    cmd->add_option("--height", o.height, "Image height in pixels")->capture_default_str()->check(CLI::Range(1, 16384));
    cmd->add_option("--eye", o.eye, "Camera position x,y,z in metres (default: automatic three-quarter view)");
    cmd->add_option("--target", o.target, "Point the camera looks at, x,y,z in metres");
    cmd->add_option("--up", o.up, "Camera up direction x,y,z")->capture_default_str();
    cmd->add_option("--fov", o.fov, "Vertical field of view in degrees")->capture_default_str();
    cmd->add_option("--radius", o.radius,
                    "Particle radius in metres (default: half the median nearest-neighbour distance)");
    cmd->add_option("--view", o.view,
                    "What the image shows: final (shaded liquid), depth (smoothed eye depth), raw-depth (before "
                    "smoothing), normals, thickness")
        ->capture_default_str();
    cmd->add_option("--filter", o.filter, "Depth smoothing: " + filterNames())->capture_default_str();
    cmd->add_option("--iterations", o.iterations,
                    "Smoothing iterations (default: the filter's own, e.g. 3 for narrow-range, 40 for curvature-flow)")
        ->check(CLI::Range(0, 10000));
    cmd->add_flag("--separable", o.separable, "narrow-range: the faster separable 1-D approximation");
    cmd->add_option("--material", o.material, "Fluid look: " + materialPresetNames())->capture_default_str();
    cmd->add_option("--background", o.background,
                    "studio (checker floor, two walls, sky) or none (transparent PNG background)")
        ->capture_default_str();
    cmd->add_option("--backend", o.backend,
                    "Where the stages run: cpu, gl (OpenGL 4.3 through headless EGL) or auto (gl when a context "
                    "can be created, else cpu with a one-line note)")
        ->capture_default_str();
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "meniscus: turns particle fluid simulation output (SPlisHSPlasH, DualSPHysics, ...) into liquid images.\n"
        "Reads BGEO, legacy VTK, VTU/VTP, PLY, CSV and XYZ files, single frames or numbered sequences.\n\n"
        "Examples:\n"
        "  meniscus demo                                   render the bundled dam-break frame to demo.png\n"
        "  meniscus info frame_21.bgeo                     particle count, bounds, attributes, radius\n"
        "  meniscus render frame_21.bgeo -o f21.png        one frame, automatic camera and radius\n"
        "  meniscus render frame_21.bgeo -o f21.exr --filter curvature-flow   every AOV as float EXR channels\n"
        "  meniscus render frame_21.bgeo -o n.png --view normals              look at one stage of the pipeline\n"
        "  meniscus render 'ParticleData_Fluid_*.bgeo' -o out_%04d.png   a whole sequence"};
    app.require_subcommand(1);
    int threads = 0;
    app.add_option("--threads", threads, "Worker threads (default: all cores)")->check(CLI::NonNegativeNumber);

    InfoOptions info;
    auto* infoCmd = app.add_subcommand("info", "Describe a particle file or sequence");
    infoCmd->add_option("input", info.input, "Particle file, directory, or pattern (frame_%04d.ply, data_*.bgeo)")
        ->required();
    infoCmd->add_flag("--json", info.json, "Print one JSON object (count, bounds_min, bounds_max, attributes, radius_estimate)");

    RenderOptions render;
    auto* renderCmd = app.add_subcommand("render", "Render a particle file or sequence to PNG or EXR");
    renderCmd->add_option("input", render.input, "Particle file, directory, or pattern (frame_%04d.ply, data_*.bgeo)")
        ->required();
    renderCmd->add_option("-o,--output", render.output,
                          "Output .png (8-bit sRGB) or .exr (float AOVs); for a sequence a pattern like out_%04d.png")
        ->required();
    addCameraOptions(renderCmd, render);

    RenderOptions demo;
    demo.output = "demo.png";
    demo.radius = kDemoRadiusM;
    auto* demoCmd = app.add_subcommand(
        "demo", "Render the bundled SPlisHSPlasH dam-break frame (no input needed; --radius defaults to 0.025 m, the simulation's own)");
    demoCmd->add_option("-o,--output", demo.output, "Output .png or .exr")->capture_default_str();
    addCameraOptions(demoCmd, demo);

    CLI11_PARSE(app, argc, argv);

    std::unique_ptr<tbb::global_control> threadLimit;
    if (threads > 0)
        threadLimit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);

    if (*infoCmd) return runInfo(info);
    if (*renderCmd) return runRender(render, nullptr);
    if (*demoCmd) {
        auto set = parseParticles(demoFrameBytes(), kDemoFrameName);
        if (!set) return fail(set.error().describe());
        return runRender(demo, &set.value());
    }
    return 2;
}
