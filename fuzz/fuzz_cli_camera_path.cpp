// libFuzzer target: camera paths, --camera-path's JSON and a render scene
// file's camera.path (cameraPathFromText, apps/meniscus/scene_file.cpp). An
// error is the option's and says so ("--camera-path: ..."); a path that reads
// is one checkCameraPath accepts (finite keys in increasing time, fov in
// (0, 180)), and the camera along it stays finite.
#include <cmath>
#include <string_view>

#include "fuzz_reader.h"
#include "meniscus/camera_path.h"
#include "scene_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace meniscus;
    const auto keys = app::cameraPathFromText(std::string_view(reinterpret_cast<const char*>(data), size), 40.0f);
    if (!keys) {
        if (keys.error().message.rfind("--camera-path: ", 0) != 0) fuzz::broken("an error not naming the option", keys.error().message);
        if (!keys.error().usage) fuzz::broken("a camera path's error that is not the option's", keys.error().message);
        return 0;
    }
    if (const std::string bad = checkCameraPath(*keys); !bad.empty()) fuzz::broken("a path checkCameraPath refuses", bad);
    const double first = keys->front().timeS, last = keys->back().timeS;
    for (double t : {first - 1.0, first, 0.5 * (first + last), last, last + 1.0}) {
        const CameraKey c = cameraPathAt(*keys, t);
        if (!std::isfinite(c.fovYDegrees) || !(c.fovYDegrees > 0.0f && c.fovYDegrees < 180.0f))
            fuzz::broken("a fov out of (0, 180) along the path", "");
    }
    return 0;
}
