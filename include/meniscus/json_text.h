// JSON text read within bounds: every JSON file Meniscus reads (render scene
// files, camera paths, simulation scenes, scene geometry lists and
// SPlisHSPlasH scenes) is read here, so none can make a reader allocate
// without bound or recurse past its stack. Nothing here throws: errors name
// the file and what is wrong with it.
//
// Each kind of file has its limits, named below. They are checked before the
// text is parsed: the size from the file's size where the file has one, else
// (a pipe, /dev/zero) while it is read in bounded pieces, which stop at the
// limit; the nesting by a scan of the bytes (brackets outside strings, minding
// escapes) before a JSON parser builds any value, since values as deep as a
// document may nest are copied, printed and freed by recursive code.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "meniscus/result.h"

namespace meniscus {

// How large and how deeply nested one kind of JSON document may be, and what
// the kind is called in errors ("a render scene file").
struct JsonLimits {
    std::uintmax_t maxBytes;
    int maxDepth;
    const char* kind;
};

namespace json_limits {
// The limits fit what each kind can legitimately need, with a wide margin.
//
// A render scene file (docs/usage.md#scene-files): a few KB of settings, plus
// perhaps a camera path and geometry objects written inline. Its depth is the
// geometry's (objects nest in groups).
inline constexpr JsonLimits kRenderScene{std::uintmax_t(16) << 20, 64, "a render scene file"};
// A --camera-path file or value: a list of keys {"time", "eye", "target",
// "fov"}, about 100 bytes each, so 16 MiB holds a key for every frame of
// more than 100,000; the real depth is 3 ([{"eye": [...]}]).
inline constexpr JsonLimits kCameraPath{std::uintmax_t(16) << 20, 8, "a camera path"};
// A simulation scene (docs/scenes.md): a few KB; the deepest real nesting is
// 5 (fluid[0].box.min[0]).
inline constexpr JsonLimits kSimulationScene{std::uintmax_t(4) << 20, 16, "a simulation scene"};
// Scene geometry (docs/geometry.md): a JSON list of objects, or a
// SPlisHSPlasH scene file (its rigid bodies and boundaries), file or text.
inline constexpr JsonLimits kGeometry{std::uintmax_t(16) << 20, 64, "a geometry JSON file"};
}  // namespace json_limits

// "16 MiB", "4 KiB", "100 bytes": a limit as errors show it.
std::string byteSizeText(std::uintmax_t bytes);

// Whether `text` fits `limits`: its size, then its nesting (by a scan of the
// bytes). The error names `name` and says "larger than the 16 MiB a render
// scene file may be" or "nested deeper than 64 levels (line 3, column 12)".
Status checkJsonText(std::string_view text, const std::string& name, const JsonLimits& limits);

// A JSON file's text, read only if it fits `limits` (checkJsonText): a
// regular file larger than the limit is refused unread, anything else (a
// pipe, a device) is read in pieces and refused at the limit. An empty file
// is an error ("the file is empty").
Result<std::string> readJsonText(const std::filesystem::path& path, const JsonLimits& limits);

}  // namespace meniscus
