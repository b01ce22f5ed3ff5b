// The viewer's settings as a scene file and back (scene_save.h).
#include "scene_save.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "meniscus/io.h"
#include "mesh.h"
#include "render_command.h"
#include "meniscus/options.h"
#include "scene_file.h"

namespace meniscus::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Written from the camera, not from the options.
bool cameraOption(const std::string& name) {
    return name == "--eye" || name == "--target" || name == "--fov" || name == "--azimuth" ||
           name == "--elevation" || name == "--distance" || name == "--width" || name == "--height";
}

// The flags' names (a flag set false is absent from a command line).
bool isFlag(const std::string& name) {
    const RenderOptionSpec* s = findRenderOption(name.substr(2));
    return s && s->flag;
}

// An option's value as JSON of its own type: true/false, a whole number, a
// number (in the shortest text that reads back as the same float), a text,
// [x, y, z] (null when unset).
json typedJson(const OptionRef& ref) {
    return std::visit(
        [&](auto* p) -> json {
            using T = std::remove_pointer_t<decltype(p)>;
            if constexpr (std::is_same_v<T, float>) return std::strtod(optionText(ref).c_str(), nullptr);
            else if constexpr (std::is_same_v<T, glm::vec3>) return json::array({p->x, p->y, p->z});
            else if constexpr (std::is_same_v<T, std::optional<glm::vec3>>)
                return *p ? json::array({(*p)->x, (*p)->y, (*p)->z}) : json(nullptr);
            else return *p;
        },
        ref);
}

// `path` relative to `folder` when the two share more than the root (a
// project moved as a whole keeps working), else absolute.
std::string relativeTo(const std::string& path, const fs::path& folder) {
    const fs::path a = fs::absolute(path).lexically_normal(), b = fs::absolute(folder).lexically_normal();
    auto ia = a.begin(), ib = b.begin();
    const bool shared = ia != a.end() && ib != b.end() && ++ia != a.end() && ++ib != b.end() && *ia == *ib;
    const fs::path rel = a.lexically_relative(b);
    return !shared || rel.empty() ? a.generic_string() : rel.generic_string();
}

json vec3Json(const glm::vec3& v) { return json::array({v.x, v.y, v.z}); }

}  // namespace

std::vector<std::pair<std::string, std::string>> optionTexts(const RenderJob& o) {
    RenderJob copy = o;
    std::vector<std::pair<std::string, std::string>> out;
    for (const RenderOptionSpec& s : renderOptionTable()) out.emplace_back("--" + s.name, optionText(s.field(copy)));
    for (const MesherOptionSpec& s : mesherOptionTable())
        out.emplace_back("--" + s.name, optionText(s.field(copy.mesher)));
    return out;
}

Result<RenderJob> reparsed(const RenderJob& o) {
    if (auto st = checkRenderOptions(o); !st) return st.error();
    return o;
}

std::vector<std::string> changedOptions(const RenderJob& before, const RenderJob& after) {
    const auto a = optionTexts(before), b = optionTexts(after);
    std::vector<std::string> out;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
        if (a[i].second == b[i].second) continue;
        if (isFlag(b[i].first) && b[i].second == "true") out.push_back(b[i].first);
        else if (isFlag(b[i].first)) out.push_back(b[i].first + "=false");
        else out.push_back(b[i].first + " " + (b[i].second.empty() ? "''" : b[i].second));
    }
    return out;
}

Result<std::string> sceneFileText(const RenderJob& o, const Camera& camera, const std::string& sceneFile) {
    if (o.input.empty())
        return makeError(sceneFile, "the demo frame has no file a scene could name; open a particle file first");
    const fs::path folder = fs::path(sceneFile).parent_path().empty() ? fs::path(".") : fs::path(sceneFile).parent_path();
    auto up = upRotation(o.up);
    if (!up) return up.error();
    const UpRotation back = up->inverse();  // the camera is in the renderer's frame; the file's eye and target in the data's
    json scene;
    scene["particles"] = relativeTo(o.input, folder);
    if (!o.moreFluids.empty()) {
        json fluids = json::array();
        for (const std::string& f : o.moreFluids) fluids.push_back(relativeTo(f, folder));
        scene["fluid"] = fluids;
    }
    scene["camera"] = {{"eye", vec3Json(back.apply(camera.eye))},
                       {"target", vec3Json(back.apply(camera.target))},
                       {"fov", camera.fovYDegrees}};
    json render = {{"width", camera.width}, {"height", camera.height}};
    // Every option of the tables that is not at its default, typed.
    RenderJob mine = o, fresh;
    const auto put = [&](const std::string& name, const OptionRef& value, const OptionRef& initial) {
        if (cameraOption("--" + name) || optionText(value) == optionText(initial)) return;
        render[name] = typedJson(value);
    };
    for (const RenderOptionSpec& s : renderOptionTable()) put(s.name, s.field(mine), s.field(fresh));
    for (const MesherOptionSpec& s : mesherOptionTable()) put(s.name, s.field(mine.mesher), s.field(fresh.mesher));
    if (!o.select.empty()) render["select"] = o.select;  // an input option, not a look one: not in optionTexts
    scene["render"] = render;
    return scene.dump(2) + "\n";
}

Status saveSceneFile(const std::string& path, const RenderJob& o, const Camera& camera) {
    auto text = sceneFileText(o, camera, path);
    if (!text) return text.error();
    auto pending = PendingFile::begin(path);
    if (!pending) return pending.error();
    {
        std::ofstream out(pending->tmp(), std::ios::binary);
        out << *text;
        if (!out.flush()) return makeError(path, "cannot write the scene file");
    }
    return pending->commit();
}

Result<RenderJob> loadSceneFile(const std::string& path) {
    CLI::App parent;
    RenderJob o;
    CLI::App* render = addRenderCommand(parent, o);
    auto args = sceneFileArgs(path, *render);
    if (!args) return args.error();
    if (auto st = applyTypedSettings(*args, o, o, path, [](const std::string&) { return true; }); !st) return st.error();
    std::vector<std::string> words{"render"};
    bool output = false;
    for (const auto& group : args->groups) {
        output = output || group.front() == "--output";
        words.insert(words.end(), group.begin(), group.end());
    }
    if (!output) words.insert(words.end(), {"--output", "unused.png"});  // render requires one; the viewer has none
    std::vector<std::string> reversed(words.rbegin(), words.rend());
    try {
        parent.parse(reversed);
    } catch (const CLI::ParseError& e) {
        return makeError(path, withSceneKey(e.what(), path, args->keyOfOption));
    }
    o.sceneFile = path;
    o.sceneKeys = args->keyOfOption;
    return o;
}

}  // namespace meniscus::app
