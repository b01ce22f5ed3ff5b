// The viewer's settings as a render scene file, and back. The look is held as
// `render`'s options (the library's option table, include/meniscus/options.h):
// what the panels change is checked as the command line checks it and printed
// as option text, so the viewer shows what `meniscus render` with the printed
// options (or the saved file) writes.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "common.h"
#include "meniscus/camera.h"
#include "meniscus/result.h"

namespace meniscus::app {

// Every option of the render and mesher tables, as "--name" and its value's
// text (optionText; flags "true"/"false"), in the tables' order.
std::vector<std::pair<std::string, std::string>> optionTexts(const RenderJob& o);

// `o` when every option is in its range (checkRenderOptions), else an error
// naming the option.
Result<RenderJob> reparsed(const RenderJob& o);

// The options whose text differs between `before` and `after`, as command-line
// words: {"--iterations 3", "--noise"} ("--noise=false" for a flag turned off).
std::vector<std::string> changedOptions(const RenderJob& before, const RenderJob& after);

// A scene file for `meniscus render` (and `view`) showing o.input through
// `camera` (the renderer's camera, y up; written in the data's frame through
// o.up): "particles" and "fluid" relative to the file's folder, "camera"
// (eye, target, fov), "render" (width, height and every look option that is
// not the default). An error when there is no input file (the demo frame).
Result<std::string> sceneFileText(const RenderJob& o, const Camera& camera, const std::string& sceneFile);
// sceneFileText written to `path` under a temporary name, then renamed.
Status saveSceneFile(const std::string& path, const RenderJob& o, const Camera& camera);

// A scene file read into options (`render`'s checks, errors naming the file
// and key); its keys that only `render` has (output, fps, ...) are ignored.
Result<RenderJob> loadSceneFile(const std::string& path);

}  // namespace meniscus::app
