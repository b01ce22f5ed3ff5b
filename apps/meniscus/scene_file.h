// Render scene files: `meniscus render scene.json` reads particles, camera,
// light, material, render settings and output from one JSON file. Every key is
// one of `render`'s options, so each CLI option has its scene-file twin and
// both are checked by the same code. The options of the library's table are
// set typed from the JSON values (no text in between); the command's own
// (output, fps, ...) become arguments; options given on the command line as
// well override both. Schema: docs/usage.md#scene-files.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "meniscus/camera_path.h"
#include "meniscus/options.h"
#include "meniscus/result.h"

namespace CLI {
class App;
}

namespace meniscus::app {

// Paths in the file (particles, output, diffuse, fluid) are relative to the
// file's folder.
//
// Whether `path` ends in .json: `render` takes it as a scene file.
bool isJsonFile(const std::string& path);

struct SceneArgs {
    // The settings of the library's option tables (include/meniscus/options.h),
    // typed from the JSON as they are: {"render.width", "width", 320}; paths
    // made the file's folder's.
    struct Typed {
        std::string key;     // its path in the file, for errors
        std::string option;  // the table's name
        OptionValue value;
    };
    std::vector<Typed> typed;
    // The input and output as `render`'s arguments: {INPUT}, {"--output", OUT}.
    std::vector<std::vector<std::string>> groups;
    // For each option set by the file, its key ("camera.eye"), so later errors
    // about the option can name the key.
    std::vector<std::pair<std::string, std::string>> keyOfOption;
};

// The file's settings as arguments of `render` (whose options `render`
// declares): an error naming the file and the key for an unknown key, a value
// of the wrong kind, or JSON that does not parse.
// The file is read within json_limits::kRenderScene (json_text.h): one that
// cannot be read, too large or too deep, or not JSON is an error of the
// data's (exit 1); a wrong key or value is the settings' (Error::usage, 2).
Result<SceneArgs> sceneFileArgs(const std::string& path, CLI::App& render);
// The same for the file's text, already read; `path` names it and its folder
// is the one relative paths are taken from.
Result<SceneArgs> sceneTextArgs(std::string_view text, const std::string& path, CLI::App& render);

// The typed settings of `args` set on `o` and `job` (those `accepts` takes:
// a subcommand's own options); an error naming `file` and the key.
Status applyTypedSettings(const SceneArgs& args, meniscus::RenderOptions& o, JobOptions& job, const std::string& file,
                          const std::function<bool(const std::string& option)>& accepts);

// --camera-path's value: a JSON array of keys, {"time": seconds, "eye":
// [x, y, z], "target": [x, y, z], "fov": degrees} (fov optional: `defaultFov`;
// metres in the data's coordinates), in increasing time: the text itself
// (starting with '[', as a scene file's camera.path passes it) or a file
// holding it. Errors start with "--camera-path" (withSceneKey then names the
// scene file's key) and name the file, the key's number and the field. The
// text is read within json_limits::kCameraPath; a file that cannot be read,
// too large or too deep, or not JSON is the data's error, wrong keys and
// values (and any fault of text given as the value) the option's
// (Error::usage).
Result<std::vector<CameraKey>> readCameraPath(const std::string& spec, float defaultFov);
// The same for the JSON text itself, whatever it starts with.
Result<std::vector<CameraKey>> cameraPathFromText(std::string_view text, float defaultFov);

// `message` (about an option, "--width: ...") prefixed with the file and key
// that set that option, when one did.
std::string withSceneKey(const std::string& message, const std::string& sceneFile,
                         const std::vector<std::pair<std::string, std::string>>& keyOfOption);

}  // namespace meniscus::app
