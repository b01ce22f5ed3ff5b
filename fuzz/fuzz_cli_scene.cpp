// libFuzzer target: render scene files (sceneTextArgs, apps/meniscus/
// scene_file.cpp): JSON text to `render`'s settings, set as the CLI sets
// them. An error names the file and says what is wrong; settings that read
// are set on fresh options without a throw (a refused value is an error
// naming the file and the key).
#include <string_view>

#include <CLI/CLI.hpp>

#include "fuzz_reader.h"
#include "render_command.h"
#include "scene_file.h"

namespace {

// `render`'s options, declared once as the CLI declares them.
struct Render {
    CLI::App app;
    meniscus::app::RenderJob job;
    CLI::App* cmd = meniscus::app::addRenderCommand(app, job);
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace meniscus;
    static Render render;
    const std::string name = "/nonexistent-fuzz-scene-dir/fuzz.json";
    const auto args = app::sceneTextArgs(std::string_view(reinterpret_cast<const char*>(data), size), name, *render.cmd);
    if (!fuzz::checkError(args, name)) return 0;
    RenderOptions options;
    JobOptions job;
    const Status st = app::applyTypedSettings(*args, options, job, name, [](const std::string&) { return true; });
    if (!st && (st.error().file != name || st.error().message.empty())) fuzz::broken("an error not naming the file", st.error().describe());
    return 0;
}
