// Render scene files: JSON keys to `render`'s arguments (scene_file.h).
#include "scene_file.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "meniscus/json_text.h"

namespace meniscus::app {
namespace {

using nlohmann::json;

// A list of three numbers as a vec3.
bool readVec3(const json& v, glm::vec3& out) {
    if (!v.is_array() || v.size() != 3) return false;
    for (std::size_t i = 0; i < 3; ++i) {
        if (!v[i].is_number()) return false;
        out[int(i)] = v[i].get<float>();
    }
    return true;
}

// "fill_holes" or "fill-holes" -> "--fill-holes".
std::string optionName(const std::string& key) {
    std::string name = "--" + key;
    for (char& c : name)
        if (c == '_') c = '-';
    return name;
}

class Converter {
public:
    Converter(std::string file, CLI::App& render) : file_(std::move(file)), render_(render) {}

    // Paths in the file are relative to its folder.
    std::string path(const std::string& p) const {
        const std::filesystem::path q(p);
        if (q.is_absolute()) return p;
        return (std::filesystem::path(file_).parent_path() / q).lexically_normal().string();
    }

    // A key or its value is wrong: the settings' error (exit 2), not the data's.
    Error fail(const std::string& key, const std::string& what) const {
        return makeUsageError(file_, key + ": " + what);
    }

    // One setting: `key` (its path in the file, for errors) naming option `name`.
    Status add(const std::string& key, const std::string& name, const json& v) {
        const CLI::Option* opt = render_.get_option_no_throw(name);
        if (!opt || name == "--help" || name == "--output")
            return fail(key, "unknown key (a scene file's keys are `meniscus render`'s options, e.g. width, filter, "
                             "anisotropy; grouped under camera, render, material and light or at the top level)");
        const std::string option = name.substr(2);
        const JobOptionSpec* job = findJobOption(option);
        if (!findRenderOption(option) && !findMesherOption(option) && !job)
            return fail(key, "not a setting of a scene file");
        // The tables' options: typed. A path is the file's folder's; a list of
        // objects (camera.path's keys) is the option's JSON text.
        Result<OptionValue> value = makeError("", "");
        if (option == "geometry") value = geometryValue(v);
        else if ((option == "environment" || option == "backdrop" || option == "backdrop-depth") && v.is_string())
            value = OptionValue(path(v.get<std::string>()));
        else if (v.is_array() && !v.empty() && v.front().is_object()) value = OptionValue(v.dump());
        else value = typedValue(v);
        if (!value) return fail(key, value.error().message);
        if (job && job->path) {
            if (auto* one = std::get_if<std::string>(&*value); one && !one->empty() && one->front() != '[')
                *one = path(*one);
            if (auto* list = std::get_if<std::vector<std::string>>(&*value))
                for (std::string& p : *list) p = path(p);
        }
        out_.typed.push_back({key, option, std::move(*value)});
        out_.keyOfOption.emplace_back(name, key);
        return okStatus();
    }

    // The `geometry` key: a path or an object (docs/geometry.md), or a list
    // of them, as --geometry's list. Paths, the objects' files among them,
    // are the file's folder's.
    Result<OptionValue> geometryValue(const json& v) const {
        std::vector<std::string> specs;
        auto one = [&](json e) -> Status {
            if (e.is_string()) {
                specs.push_back(path(e.get<std::string>()));
                return okStatus();
            }
            if (!e.is_object()) return makeError("", "expected a file name or a geometry object ({\"box\": ...})");
            for (const char* key : {"file", "splishsplash"})
                if (auto it = e.find(key); it != e.end() && it->is_string()) *it = path(it->get<std::string>());
            specs.push_back(e.dump());
            return okStatus();
        };
        if (v.is_array()) {
            for (const json& e : v)
                if (auto st = one(e); !st) return st.error();
        } else if (auto st = one(v); !st) {
            return st.error();
        }
        return OptionValue(std::move(specs));
    }

    // A JSON value as an option's typed value: true/false, a whole number, a
    // number, a text, three numbers, or a list of texts.
    static Result<OptionValue> typedValue(const json& v) {
        if (v.is_boolean()) return OptionValue(v.get<bool>());
        if (v.is_number_integer()) return OptionValue(v.get<std::int64_t>());
        if (v.is_number()) return OptionValue(v.get<double>());
        if (v.is_string()) return OptionValue(v.get<std::string>());
        if (v.is_array() && !v.empty() && std::all_of(v.begin(), v.end(), [](const json& e) { return e.is_string(); }))
            return OptionValue(v.get<std::vector<std::string>>());
        glm::vec3 three;
        if (readVec3(v, three)) return OptionValue(three);
        return makeError("", "expected a number, a string, true/false, a list of three numbers or of names");
    }

    // Every key of a section ("camera", "render") or of the top level: the
    // option of that name, else the section's own (camera.path: --camera-path).
    Status addAll(const std::string& prefix, const json& section) {
        if (!section.is_object()) return fail(prefix, "expected an object of settings");
        for (const auto& [k, v] : section.items()) {
            std::string name = optionName(k);
            if (!render_.get_option_no_throw(name) && render_.get_option_no_throw(optionName(prefix + "-" + k)))
                name = optionName(prefix + "-" + k);
            if (auto st = add(prefix + "." + k, name, v); !st) return st;
        }
        return okStatus();
    }

    void push(const std::string& key, std::vector<std::string> group) {
        out_.keyOfOption.emplace_back(group.front(), key);
        out_.groups.push_back(std::move(group));
    }
    SceneArgs& out() { return out_; }

private:
    std::string file_;
    CLI::App& render_;
    SceneArgs out_;
};

// JSON text within `limits` (its size and nesting checked before it is
// parsed, so no value is deeper than the recursive code below can take).
Result<json> parseJson(std::string_view text, const std::string& path, const JsonLimits& limits) {
    if (auto fits = checkJsonText(text, path, limits); !fits) return fits.error();
    try {
        return json::parse(text.begin(), text.end());
    } catch (const json::exception& e) {
        return makeError(path, std::string("not valid JSON: ") + e.what());
    }
}

// A camera path's JSON text; errors start with `where` ("--camera-path: ").
// A file's text that is too large, too deep or not JSON is the data's error
// (exit 1); text given as the option's value, and wrong keys, the option's (2).
Result<std::vector<CameraKey>> cameraPathOf(std::string_view text, const std::string& where, float defaultFov,
                                            bool file) {
    const auto unreadable = [&](const std::string& message) {
        return file ? makeError("", where + message) : makeUsageError("", where + message);
    };
    if (auto fits = checkJsonText(text, "", json_limits::kCameraPath); !fits) return unreadable(fits.error().message);
    json root;
    try {
        root = json::parse(text.begin(), text.end());
    } catch (const json::exception& e) {
        return unreadable(std::string("not valid JSON: ") + e.what());
    }
    if (!root.is_array() || root.empty())
        return makeUsageError("", where + "expected a list of at least one key, [{\"time\": 0, \"eye\": [x, y, z], "
                                     "\"target\": [x, y, z], \"fov\": 40}, ...]");
    std::vector<CameraKey> keys;
    for (std::size_t k = 0; k < root.size(); ++k) {
        const json& e = root[k];
        const std::string which = where + "key " + std::to_string(k + 1) + ": ";
        if (!e.is_object()) return makeUsageError("", which + "expected an object {\"time\": ..., \"eye\": ..., ...}");
        CameraKey key;
        key.fovYDegrees = defaultFov;
        for (const auto& [name, v] : e.items()) {
            if (name != "time" && name != "eye" && name != "target" && name != "fov")
                return makeUsageError("", which + "unknown field \"" + name + "\" (expected time, eye, target, fov)");
            const bool vector = name == "eye" || name == "target";
            const bool ok = vector ? readVec3(v, name == "eye" ? key.eye : key.target) : v.is_number();
            if (!ok)
                return makeUsageError("", which + name + ": expected " +
                                         (vector ? "[x, y, z] in metres" : name == "time" ? "seconds" : "degrees"));
            if (name == "time") key.timeS = v.get<double>();
            if (name == "fov") key.fovYDegrees = v.get<float>();
        }
        for (const char* need : {"time", "eye", "target"})
            if (!e.contains(need)) return makeUsageError("", which + "needs \"" + need + "\"");
        keys.push_back(key);
    }
    if (std::string bad = checkCameraPath(keys); !bad.empty()) return makeUsageError("", where + bad);
    return keys;
}

}  // namespace

Result<std::vector<CameraKey>> cameraPathFromText(std::string_view text, float defaultFov) {
    return cameraPathOf(text, "--camera-path: ", defaultFov, false);
}

Result<std::vector<CameraKey>> readCameraPath(const std::string& spec, float defaultFov) {
    const std::size_t first = spec.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && spec[first] == '[') return cameraPathFromText(spec, defaultFov);
    // Errors name the option and the file.
    const std::string where = "--camera-path " + spec + ": ";
    auto text = readJsonText(spec, json_limits::kCameraPath);
    if (!text) return makeError("", where + text.error().message);
    return cameraPathOf(*text, where, defaultFov, true);
}

bool isJsonFile(const std::string& path) { return std::filesystem::path(path).extension() == ".json"; }

Result<SceneArgs> sceneFileArgs(const std::string& path, CLI::App& render) {
    auto text = readJsonText(path, json_limits::kRenderScene);
    if (!text) return text.error();
    return sceneTextArgs(*text, path, render);
}

Result<SceneArgs> sceneTextArgs(std::string_view text, const std::string& path, CLI::App& render) {
    auto root = parseJson(text, path, json_limits::kRenderScene);
    if (!root) return root.error();
    if (!root->is_object()) return makeUsageError(path, "a scene file is a JSON object ({\"particles\": ..., ...})");
    Converter c(path, render);
    // A simulation scene (docs/scenes.md: a domain and fluid or emitters) is
    // the particles themselves: render simulates it.
    if (!root->contains("particles") && root->contains("domain")) {
        SceneArgs simulation;
        simulation.groups.push_back({path});
        return simulation;
    }
    if (!root->contains("particles"))
        return makeUsageError(path, "a render scene file needs \"particles\": a particle file, folder or pattern, or a "
                               "simulation scene (docs/scenes.md)");
    const json& particles = (*root)["particles"];
    if (!particles.is_string() || particles.get<std::string>().empty())
        return c.fail("particles", "expected the particle file, folder or pattern (a string)");
    c.push("particles", {c.path(particles.get<std::string>())});
    for (const auto& [k, v] : root->items()) {
        if (k == "particles") continue;
        Status st = okStatus();
        if (k == "output") {
            if (!v.is_string() || v.get<std::string>().empty())
                return c.fail(k, "expected the image, pattern or movie to write (a string)");
            c.push(k, {"--output", c.path(v.get<std::string>())});
        } else if (k == "camera" || k == "render") {
            st = c.addAll(k, v);
        } else if (k == "material") {
            // A preset, one per fluid, or {"preset": ..., custom values}.
            if (v.is_object()) {
                for (const auto& [mk, mv] : v.items()) {
                    const std::string key = "material." + mk;
                    st = mk == "preset" ? c.add(key, "--material", mv) : c.add(key, optionName(mk), mv);
                    if (!st) return st.error();
                }
            } else {
                st = c.add(k, "--material", v);
            }
        } else if (k == "light") {
            // {"direction": [x, y, z]} (toward the light) or the list itself.
            if (v.is_object() && (v.size() != 1 || !v.contains("direction")))
                return c.fail(k, "expected {\"direction\": [x, y, z]} (toward the light)");
            const json& dir = v.is_object() ? v["direction"] : v;
            st = c.add(v.is_object() ? "light.direction" : k, "--light", dir);
        } else {
            st = c.add(k, optionName(k), v);
        }
        if (!st) return st.error();
    }
    return std::move(c.out());
}

Status applyTypedSettings(const SceneArgs& args, meniscus::RenderOptions& o, JobOptions& job, const std::string& file,
                          const std::function<bool(const std::string& option)>& accepts) {
    for (const SceneArgs::Typed& t : args.typed) {
        if (!accepts(t.option)) continue;
        const Status st = findJobOption(t.option) ? setJobOption(job, t.option, t.value)
                                                  : setRenderOption(o, t.option, t.value);
        if (!st) return makeUsageError(file, t.key + ": " + st.error().message);
    }
    return okStatus();
}

std::string withSceneKey(const std::string& message, const std::string& sceneFile,
                         const std::vector<std::pair<std::string, std::string>>& keyOfOption) {
    for (const auto& [option, key] : keyOfOption) {
        const std::size_t at = message.find(option);
        const char after = at == std::string::npos || at + option.size() >= message.size() ? ' '
                                                                                            : message[at + option.size()];
        if (at != std::string::npos && !std::isalnum(static_cast<unsigned char>(after)) && after != '-')
            return sceneFile + ": " + key + ": " + message;
    }
    return message;
}

}  // namespace meniscus::app
