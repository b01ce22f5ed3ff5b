// `render`'s command line (render_command.h).
#include "render_command.h"

#include <CLI/CLI.hpp>

#include "help_format.h"
#include "mesh.h"
#include "render.h"

namespace meniscus::app {

CLI::App* addRenderCommand(CLI::App& parent, RenderJob& render) {
    auto* renderCmd = parent.add_subcommand("render", "Render a particle file or sequence to PNG, EXR or an MP4 movie");
    renderCmd->add_option("input", render.input,
                          "Particle file, directory, or pattern (frame_%04d.ply, data_*.bgeo), or a render scene "
                          "file (.json with \"particles\", docs/usage.md#scene-files) whose settings the command "
                          "line's own options override")
        ->group(group::kInput)
        ->required();
    renderCmd->add_option("-o,--output", render.output,
                          "Output .png (8-bit sRGB), .exr (float AOVs) or .mp4 (an H.264 movie of every frame, in "
                          "order); images of a sequence need a pattern like out_%04d.png")
        ->group(group::kOutput)
        ->required();
    addSequenceOptions(renderCmd, render);
    addCameraOptions(renderCmd, render);
    addBackendOption(renderCmd, render);
    addSurfaceOptions(renderCmd, render);
    addFluidInputOption(renderCmd, render);
    addJobTableOptions(renderCmd, render, {"diffuse"});
    useGroupedHelp(renderCmd, renderHelpLayout());
    return renderCmd;
}

}  // namespace meniscus::app
