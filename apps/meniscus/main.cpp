// The `meniscus` command line: argument parsing and messages only; the work is
// done by the library. Errors: one line on stderr naming the file and the
// problem; exit code 1 for the data or the run, 2 for the command line or a scene
// file's values (Error::usage), 130/143 interrupted (docs/usage.md#errors).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "common.h"
#include "help_format.h"
#include "meniscus/io.h"
#include "meniscus/memory_budget.h"
#include "meniscus/params.h"
#include "meniscus/particles.h"
#include "compare.h"
#include "convert.h"
#include "meniscus/renderer.h"
#include "meniscus/surface.h"
#include "mesh.h"
#include "simulate.h"
#include "whitewater.h"
#include "progress.h"
#include "render.h"
#include "scene_file.h"
#include "render_command.h"
#include "view.h"

using namespace meniscus;
using namespace meniscus::app;

namespace {

// The words of the command line with a render scene file's settings put in
// its place (the file's groups the command line does not give again), or the
// words as they are when `render` has no scene file.
//
// `view` takes the same files (checked as `render`'s): the settings it has no
// option for (output, fps, ...) are left out.
Result<std::vector<std::string>> withSceneFile(const std::vector<std::string>& words, CLI::App& render,
                                               CLI::App& sub, RenderJob& job) {
    const auto r = std::find(words.begin(), words.end(), sub.get_name());
    if (r == words.end()) return words;
    // The input word: a .json that is not the value of an option (--simulate s.json, --camera-path p.json).
    auto scene = words.end();
    for (auto w = r + 1; w != words.end() && scene == words.end(); ++w) {
        const CLI::Option* before = sub.get_option_no_throw(*(w - 1));
        if (isJsonFile(*w) && !(w - 1 != r && before && before->get_expected_max() > 0)) scene = w;
    }
    if (scene == words.end()) return words;
    auto parsed = sceneFileArgs(*scene, render);
    if (!parsed) return parsed.error();
    job.sceneFile = *scene;
    job.sceneKeys = parsed->keyOfOption;
    // The table's settings typed onto the options now; the command line's own, parsed after, win.
    if (auto st = applyTypedSettings(*parsed, job, job, *scene,
                                     [&](const std::string& option) { return sub.get_option_no_throw("--" + option); });
        !st)
        return st.error();
    std::vector<std::string> given;  // options on the command line (-o as --output)
    for (auto w = r + 1; w != words.end(); ++w)
        if (w->size() > 1 && (*w)[0] == '-') given.push_back(*w == "-o" ? "--output" : w->substr(0, w->find('=')));
    std::vector<std::string> out(words.begin(), r + 1);
    for (const auto& group : parsed->groups) {
        const bool option = group.front().rfind("--", 0) == 0;
        if (option && !sub.get_option_no_throw(group.front())) continue;
        if (std::find(given.begin(), given.end(), group.front()) == given.end()) out.insert(out.end(), group.begin(), group.end());
    }
    for (auto w = r + 1; w != words.end(); ++w)
        if (w != scene) out.push_back(*w);
    return out;
}

// `meniscus --version`: the version and what this build can do.
std::string versionLine() {
    std::string line = std::string("meniscus ") + MENISCUS_VERSION + " (backends: cpu";
#ifdef MENISCUS_HAVE_GL
    line += ", gl";
#endif
    line += "; viewer: ";
#ifdef MENISCUS_HAVE_GLFW
    line += "yes";
#else
    line += "no";
#endif
    line += "; movies: ";
#ifdef MENISCUS_HAVE_FFMPEG
    line += "yes";
#else
    line += "no";
#endif
    return line + ")";
}

// The first option before the subcommand's name that is not the program's own
// (--threads, --help, --version), or "" when there is none.
std::string optionBeforeSubcommand(int argc, char** argv, CLI::App& app) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--threads") {
            ++i;
            continue;
        }
        if (a.rfind("--threads=", 0) == 0 || a == "--help" || a == "-h" || a == "--version") continue;
        if (a.empty() || a[0] != '-') return "";  // the subcommand (or a stray word CLI11 reports)
        for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
            if (sub->get_option_no_throw(a.substr(0, a.find('='))) != nullptr) return a.substr(0, a.find('='));
        return "";  // unknown anywhere: CLI11's own error
    }
    return "";
}

const char* typeName(const Attribute& a) {
    if (a.type == AttributeType::Int) return "int";
    return a.components == 3 ? "vector" : "float";
}

// ------------------------------------------------------------------ info

const char* radiusMethodName(RadiusMethod m) {
    switch (m) {
        case RadiusMethod::FileAttribute: return "file-attribute";
        case RadiusMethod::BulkDensity: return "bulk-density";
        case RadiusMethod::NearestNeighbour: return "nearest-neighbour";
        case RadiusMethod::Fallback: return "fallback";
    }
    return "?";
}

struct InfoOptions {
    std::string input;
    bool json = false;
    float hPerSpacing = defaults::kHPerSpacing;
};

int runInfo(const InfoOptions& o) {
    auto frames = expandSequence(o.input);
    if (!frames) return fail(frames.error());
    auto set = readParticles(frames->front());
    if (!set) return fail(set.error());
    const std::size_t fileAttributes = set->attributes.size();  // listed; a radius from h is not the file's
    const auto smoothingLength = addRadiusFromSmoothingLength(*set, o.hPerSpacing);
    if (!smoothingLength) return fail(smoothingLength.error());
    printWarnings(*set);
    if (auto st = checkCoordinates(set->positions, frames->front().string()); !st) return fail(st.error());

    // PySPH's files hold several particle arrays, of which one is shown: list them all.
    std::vector<ParticleArrayInfo> arrays;
    if (const ParticleFormat f = formatFromName(o.input); f == ParticleFormat::Hdf5 || f == ParticleFormat::Npz)
        if (auto listed = listParticleArrays(o.input)) arrays = std::move(*listed);
    const Bounds b = computeBounds(set->positions);
    const RadiusEstimate radius = defaultRadius(*set);
    const auto density = attributeStats(*set, kAttrDensity);

    if (o.json) {
        nlohmann::json j;
        j["file"] = frames->front().string();
        if (frames->size() > 1) j["frames"] = frames->size();
        j["count"] = set->size();
        j["bounds_min"] = {b.min.x, b.min.y, b.min.z};
        j["bounds_max"] = {b.max.x, b.max.y, b.max.z};
        j["attributes"] = nlohmann::json::array();
        for (std::size_t k = 0; k < fileAttributes; ++k) {
            const Attribute& a = set->attributes[k];
            j["attributes"].push_back({{"name", a.name}, {"type", typeName(a)}, {"components", a.components}});
        }
        j["radius_estimate"] = radius.radius;
        if (!smoothingLength->empty())
            j["radius_from_smoothing_length"] = {{"attribute", *smoothingLength}, {"h_per_spacing", o.hPerSpacing}};
        j["radius_method"] = radiusMethodName(radius.method);
        j["isolated_particles"] = radius.isolated;
        if (density) j["density"] = {{"min", density->min}, {"median", density->median}, {"max", density->max}};
        if (!arrays.empty()) {
            j["particle_arrays"] = nlohmann::json::array();
            for (const ParticleArrayInfo& p : arrays) j["particle_arrays"].push_back({{"name", p.name}, {"count", p.count}});
        }
        j["warnings"] = set->warnings;
        std::cout << j.dump() << "\n";
        return 0;
    }
    std::printf("file        %s\n", frames->front().string().c_str());
    if (frames->size() > 1) std::printf("frames      %zu (first shown)\n", frames->size());
    std::printf("particles   %zu\n", set->size());
    if (!arrays.empty()) {
        std::printf("arrays     ");
        for (const ParticleArrayInfo& p : arrays) std::printf(" %s (%zu)", p.name.c_str(), p.count);
        std::printf(" (shown: the one named fluid, else the first; another as %s/NAME)\n", o.input.c_str());
    }
    std::printf("bounds      (%.5g, %.5g, %.5g) .. (%.5g, %.5g, %.5g) m\n", b.min.x, b.min.y, b.min.z, b.max.x,
                b.max.y, b.max.z);
    std::printf("attributes ");
    for (std::size_t k = 0; k < fileAttributes; ++k) {
        const Attribute& a = set->attributes[k];
        std::printf(" %s(%s%s)", a.name.c_str(), typeName(a), a.components > 1 && a.components != 3 ? "[]" : "");
    }
    std::printf("%s\n", fileAttributes == 0 ? " none" : "");
    std::printf("radius      %s\n", radius.describe().c_str());
    if (!smoothingLength->empty())
        std::printf("            from the smoothing length: r = %s / (2 x %g) (--h-per-spacing)\n",
                    smoothingLength->c_str(), double(o.hPerSpacing));
    if (density)
        std::printf("density     min %.2f  median %.2f  max %.2f\n", density->min, density->median, density->max);
    return 0;
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
        "  meniscus render 'ParticleData_Fluid_*.bgeo' -o out_%04d.png   a whole sequence\n"
        "  meniscus view frame_21.bgeo                     a window: drag to orbit, wheel to zoom, Esc to quit\n"
        "  meniscus mesh frame_21.bgeo -o f21.ply          the surface as a closed triangle mesh (PLY or OBJ)\n"
        "  meniscus render frame_21.bgeo -o m.png --surface mesh   render that mesh instead of smoothing splats\n"
        "  meniscus compare frame_21.bgeo -o side_by_side.png      screen space and mesh, side by side, timed\n"
        "  meniscus simulate scenes/dam_break.json -o out/frame_%04d.bgeo   liquid from a scene file alone\n"
        "  meniscus whitewater out/ -o diffuse/diffuse_%04d.bgeo   spray, foam and bubbles from that sequence\n"
        "  meniscus convert 'PartFluid_*.vtk' out/f_%04d.bgeo      particle files to another format"};
    app.require_subcommand(1);
    app.set_version_flag("--version", versionLine())->group(group::kHelp);
    useGroupedHelp(&app, {group::kPerformance});
    int threads = 0;
    app.add_option("--threads", threads, "Worker threads (default: all cores); also after a subcommand")
        ->group(group::kPerformance)
        ->check(CLI::NonNegativeNumber);
    app.fallthrough();  // --threads may follow the subcommand: meniscus mesh IN -o OUT --threads 1

    InfoOptions info;
    auto* infoCmd = app.add_subcommand("info", "Describe a particle file or sequence");
    infoCmd->add_option("input", info.input, "Particle file, directory, or pattern (frame_%04d.ply, data_*.bgeo)")
        ->group(group::kInput)
        ->required();
    infoCmd->add_flag("--json", info.json, "Print one JSON object (count, bounds_min, bounds_max, attributes, radius_estimate)")
        ->group(group::kOutput);
    addSmoothingLengthOption(infoCmd, info.hPerSpacing);
    useGroupedHelp(infoCmd, {group::kInput, group::kOutput});

    RenderJob render;
    auto* renderCmd = addRenderCommand(app, render);

    RenderJob demo;
    demo.output = "demo.png";
    demo.radius = kDemoRadiusM;
    auto* demoCmd = app.add_subcommand(
        "demo", "Render the bundled SPlisHSPlasH dam-break frame (no input needed; --radius defaults to 0.025 m, the simulation's own)");
    demoCmd->add_option("-o,--output", demo.output, "Output .png or .exr")
        ->group(group::kOutput)
        ->capture_default_str();
    addCameraOptions(demoCmd, demo);
    addBackendOption(demoCmd, demo);
    useGroupedHelp(demoCmd, renderHelpLayout());

    ViewOptions view;
    auto* viewCmd = app.add_subcommand(
        "view",
        "Show a particle file or sequence in a window, rendered live by the GL backend (needs a display), with "
        "panels for every setting (each change printed as the `render` option that makes it), the timeline, "
        "per-stage times, and saving the view as a scene file. Drag with the left button to orbit, scroll to "
        "zoom, left/right arrows to step through a sequence, space to play it, Tab to hide the panels, C to "
        "print the camera's --eye --target --fov, H for help, Esc or Q to quit; drop a file, folder or scene "
        "file on the window to show it. Without an input it shows the bundled demo frame");
    auto* viewInput = viewCmd->add_option(
        "input", view.render.input,
        "Particle file, directory, or pattern (frame_%04d.ply, data_*.bgeo), or a render scene file (.json, "
        "docs/usage.md#scene-files); default: the demo frame")
        ->group(group::kInput);
    addCameraOptions(viewCmd, view.render);
    addSurfaceOptions(viewCmd, view.render);
    addFluidInputOption(viewCmd, view.render);
    for (const ViewerOptionSpec& row : viewerOptionTable()) {
        CLI::Option* opt = addRow(viewCmd, row, row.field(view));
        if (row.name == "simulate") opt->excludes(viewInput);
    }
    addSolverOption(viewCmd, view.live.solver)->needs("--simulate")->group(group::kInput);
    useGroupedHelp(viewCmd, renderHelpLayout());

    MeshJob mesh;
    auto* meshCmd = addMeshCommand(app, mesh);
    RenderJob compare;
    auto* compareCmd = addCompareCommand(app, compare);
    SimulateJob simulate;
    auto* simulateCmd = addSimulateCommand(app, simulate);
    WhitewaterJob whitewater;
    auto* whitewaterCmd = addWhitewaterCommand(app, whitewater);
    ConvertOptions convert;
    auto* convertCmd = addConvertCommand(app, convert);

    // A subcommand's option before the subcommand: say where it goes.
    if (auto misplaced = optionBeforeSubcommand(argc, argv, app); !misplaced.empty()) {
        std::cerr << "meniscus: error: " << misplaced << " is an option of a subcommand and goes after it (e.g. "
                  << "meniscus render IN -o OUT " << misplaced << " ...); only --threads, --help and --version "
                  << "come before the subcommand\n";
        return 2;
    }
    // MENISCUS_MEMORY_LIMIT (bytes) lowers the memory budget below the
    // system's limits (docs/usage.md#errors), e.g. to test the refusals or to
    // leave room for other programs.
    if (const char* cap = std::getenv("MENISCUS_MEMORY_LIMIT"); cap != nullptr && *cap != '\0') {
        char* end = nullptr;
        const unsigned long long bytes = std::strtoull(cap, &end, 10);
        if (*end != '\0' || bytes == 0 || cap[0] == '-') {
            std::cerr << "meniscus: error: MENISCUS_MEMORY_LIMIT=" << cap << ": a positive number of bytes is needed\n";
            return 2;
        }
        setProgramMemoryCap(bytes, "MENISCUS_MEMORY_LIMIT");
    }
    // `render scene.json`: the file's settings become arguments, the command line's own win.
    std::vector<std::string> words(argv, argv + argc);
    auto expanded = withSceneFile(words, *renderCmd, *renderCmd, render);
    if (!expanded) return fail(expanded.error());
    if (render.sceneFile.empty())
        expanded = withSceneFile(*expanded, *renderCmd, *viewCmd, view.render);
    if (!expanded) return fail(expanded.error());
    std::vector<char*> args;
    for (std::string& w : *expanded) args.push_back(w.data());
    // Bad usage exits 2, as docs/usage.md#errors says (CLI11's own codes are 100 and up).
    try {
        app.parse(int(args.size()), args.data());
    } catch (const CLI::ParseError& e) {
        const RenderJob& scene = render.sceneFile.empty() ? view.render : render;
        // Several existing files where one input goes: the shell expanded an
        // unquoted pattern. Say so instead of listing the paths back.
        if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
            std::size_t files = 0;
            std::error_code ec;
            for (std::size_t i = 1; i < words.size(); ++i) files += std::filesystem::is_regular_file(words[i], ec);
            if (files >= 2) {
                std::cerr << "meniscus: error: " << files << " input files where one input goes: the shell expanded "
                          << "an unquoted pattern; quote it, e.g. 'frames/*.bgeo' or frames/f_%04d.bgeo, and "
                          << "meniscus reads the whole sequence in order\n";
                return 2;
            }
        }
        if (scene.sceneFile.empty() || e.get_exit_code() == 0) return app.exit(e) == 0 ? 0 : 2;
        std::cerr << "meniscus: error: " << withSceneKey(e.what(), scene.sceneFile, scene.sceneKeys) << "\n";
        return 2;
    }

    std::unique_ptr<tbb::global_control> threadLimit;
    if (threads > 0)
        threadLimit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);

    if (*infoCmd) return runInfo(info);
    if (*meshCmd) return runMesh(mesh, threads);
    if (*simulateCmd) return runSimulate(simulate);
    if (*whitewaterCmd) return runWhitewater(whitewater);
    if (*convertCmd) return runConvert(convert);
    if (*compareCmd) return runCompare(compare);
    if (*renderCmd) return runRender(render, nullptr);
    if (*demoCmd) {
        auto set = parseParticles(demoFrameBytes(), kDemoFrameName);
        if (!set) return fail(set.error());
        return runRender(demo, &set.value());
    }
    if (*viewCmd) {
        if (!view.render.input.empty() || !view.simulate.empty()) return runView(view, nullptr);
        auto set = parseParticles(demoFrameBytes(), kDemoFrameName);
        if (!set) return fail(set.error());
        if (view.render.radius == 0.0f) view.render.radius = kDemoRadiusM;
        return runView(view, &set.value());
    }
    return 2;
}
