// The viewer's settings as a render scene file, and back. The look is held as
// `render`'s options: what the panels change is written as option text and read
// back through the command line's own parser, so the viewer shows exactly what
// `meniscus render` with the printed options (or the saved file) writes.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "common.h"
#include "meniscus/camera.h"
#include "meniscus/result.h"

namespace meniscus::app {

// Every option addCameraOptions and addSurfaceOptions declare, as "--name" and its value's text
// (flags: "true"/"false"), in declaration order.
std::vector<std::pair<std::string, std::string>> optionTexts(const RenderOptions& o);

// `o` passed through the command line's parser: each option's text parsed
// again, so a value is what `render` would get from the printed text. An
// error (naming the option) for a value the parser refuses.
Result<RenderOptions> reparsed(const RenderOptions& o);

// The options whose text differs between `before` and `after`, as command-line
// words: {"--iterations 3", "--noise"} ("--noise=false" for a flag turned off).
std::vector<std::string> changedOptions(const RenderOptions& before, const RenderOptions& after);

// A scene file for `meniscus render` (and `view`) showing o.input through
// `camera` (the renderer's camera, y up; written in the data's frame through
// o.up): "particles" and "fluid" relative to the file's folder, "camera"
// (eye, target, fov), "render" (width, height and every look option that is
// not the default). An error when there is no input file (the demo frame).
Result<std::string> sceneFileText(const RenderOptions& o, const Camera& camera, const std::string& sceneFile);
// sceneFileText written to `path` under a temporary name, then renamed.
Status saveSceneFile(const std::string& path, const RenderOptions& o, const Camera& camera);

// A scene file read into options (`render`'s checks, errors naming the file
// and key); its keys that only `render` has (output, fps, ...) are ignored.
Result<RenderOptions> loadSceneFile(const std::string& path);

}  // namespace meniscus::app
