// One frame, two techniques: the screen-space pipeline (splat, smoothing,
// normals) and the isosurface path (mesh, rasterised), through the same
// camera, scene, thickness and shading; each panel labelled with its times,
// measured as the bench measures them (MeshStats for the meshing, the wall
// time of Renderer::render for the rendering, after one warm-up render that
// casts the scene and, on GL, compiles the shaders).
#include "compare.h"

#include <chrono>
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>

#include "help_format.h"
#include "label.h"
#include "mesh.h"
#include "meniscus/io.h"
#include "meniscus/surface.h"

namespace meniscus::app {

CLI::App* addCompareCommand(CLI::App& app, RenderJob& o) {
    o.width = 640;
    o.height = 360;
    auto* cmd = app.add_subcommand(
        "compare",
        "Render one frame with the screen-space path and with the mesh path (isosurface, rasterised) side by side "
        "in one PNG, each labelled with its time in milliseconds; the same table is printed on stdout");
    cmd->add_option("input", o.input, "One particle file")
        ->group(group::kInput)
        ->required();
    cmd->add_option("-o,--output", o.output, "Output .png (two panels of --width x --height pixels)")
        ->group(group::kOutput)
        ->required();
    addCameraOptions(cmd, o);
    addSelectOption(cmd, o.select);
    addBackendOption(cmd, o);
    addMesherTableOptions(cmd, o.mesher);
    useGroupedHelp(cmd, renderHelpLayout());
    return cmd;
}

namespace {

using Clock = std::chrono::steady_clock;

// The wall time of one render after a warm-up (scene cast, shader compiles).
Result<double> timedRender(Renderer& renderer, const ParticleSet& set, const RenderSettings& s, Aovs* out) {
    if (auto warm = renderer.render(ParticleView::of(set), s); !warm) return warm.error();
    const auto t0 = Clock::now();
    auto aovs = renderer.render(ParticleView::of(set), s);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (!aovs) return aovs.error();
    *out = std::move(*aovs);
    return ms;
}

void caption(Image<glm::vec4>& image, int x0, int width, const std::string& top, const std::string& bottom) {
    const int scale = width >= 480 ? 2 : 1;
    const int bar = scale * 22;
    for (int y = 0; y < std::min(bar, image.height); ++y)
        for (int x = x0; x < x0 + width; ++x) image.at(x, y) = glm::mix(image.at(x, y), glm::vec4(0, 0, 0, 1), 0.7f);
    drawLabel(image, x0 + 4 * scale, 2 * scale, top, scale, glm::vec4(1.0f));
    drawLabel(image, x0 + 4 * scale, 12 * scale, bottom, scale, glm::vec4(0.8f, 0.9f, 1.0f, 1.0f));
}

}  // namespace

int runCompare(const RenderJob& o) {
    if (!isPng(o.output)) return fail(o.output + ": output must end in .png");
    if (!o.fluidAttribute.empty())
        return failUsage("--fluid-attribute: compare draws one fluid (the mesh path has no fluids of its own)");
    auto parsed = settingsFromOptions(o);
    if (!parsed) return fail(parsed.error());
    RenderSettings settings = std::move(*parsed);
    settings.colorOnly = true;
    auto frames = openFrames(o.input, nullptr, o.hPerSpacing);
    if (!frames) return fail(frames.error());
    if (frames->count() != 1) return fail(o.input + ": compare takes one frame, not a sequence");
    if (auto st = frames->setSelection(o.select); !st) return fail(st.error());
    auto up = upRotation(o.up);
    if (!up) return fail(up.error());
    frames->up = *up;
    auto set = fixForSequence(o, *frames, settings);
    if (!set) return fail(set.error());

    auto made = makeRenderer(o);
    if (!made) return fail(made.error());
    Renderer renderer = std::move(*made);

    Aovs screen, meshed;
    auto screenMs = timedRender(renderer, *set, settings, &screen);
    if (!screenMs) return fail(screenMs.error());

    const MeshParams params = mesherParams(o.mesher, settings.radiusM, 0);
    MeshStats stats;
    auto mesh = extractSurface(ParticleView::of(*set), params, &stats);
    if (!mesh) return fail(Error{frames->files[0].string(), mesh.error().message}.describe());
    settings.mesh = &*mesh;
    auto meshMs = timedRender(renderer, *set, settings, &meshed);
    if (!meshMs) return fail(meshMs.error());

    const int w = o.width, h = o.height;
    Image<glm::vec4> both(2 * w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            both.at(x, y) = screen.color.at(x, y);
            both.at(w + x, y) = meshed.color.at(x, y);
        }
    char top[160], bottom[160];
    const std::string backend = renderer.backendName().substr(0, renderer.backendName().find(' '));
    std::snprintf(top, sizeof top, "SCREEN SPACE (%s FILTER)", o.filter.c_str());
    std::snprintf(bottom, sizeof bottom, "RENDER %.1f MS (%s)", *screenMs, backend.c_str());
    caption(both, 0, w, top, bottom);
    std::snprintf(top, sizeof top, "MESH (%s FIELD, CUBE %.2g R, %zu TRIANGLES)", o.mesher.field.c_str(),
                  double(o.mesher.cubeSize), mesh->triangleCount());
    std::snprintf(bottom, sizeof bottom, "MESHING %.1f MS + RENDER %.1f MS (%s)", stats.msTotal, *meshMs, backend.c_str());
    caption(both, w, w, top, bottom);
    if (auto st = writePng(o.output, both, false); !st) return fail(st.error());

    std::printf("| path | meshing | rendering | total |\n| --- | --- | --- | --- |\n");
    std::printf("| screen space (%s) | - | %.1f ms | %.1f ms |\n", o.filter.c_str(), *screenMs, *screenMs);
    std::printf("| mesh (%s field, cube %.2g r, %zu triangles) | %.1f ms | %.1f ms | %.1f ms |\n", o.mesher.field.c_str(),
                double(o.mesher.cubeSize), mesh->triangleCount(), stats.msTotal, *meshMs, stats.msTotal + *meshMs);
    std::cerr << "meniscus: wrote " << o.output << " (" << renderer.backendName() << ", " << stats.threads
              << " threads)\n";
    return 0;
}

}  // namespace meniscus::app
