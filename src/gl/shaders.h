// The GL backend's shader sources: the files under src/gl/shaders (stages and
// .glsl snippets) and src/shared (per-pixel math and the parameter block shared
// with C++), embedded at build time by cmake/embed_shaders.cmake.
#pragma once

#include <string>
#include <string_view>

#include "gl/objects.h"
#include "meniscus/result.h"

namespace meniscus::gl {

// The text of an embedded file by its name (e.g. "splat_depth.comp",
// "frame_params.h"); empty when there is no such file.
std::string_view shaderSource(std::string_view fileName);

// The source ready for the driver: every `#include "name"` line replaced by the
// embedded file of that name (recursively, each file once), and the
// `#extension GL_GOOGLE_include_directive` line (which lets glslangValidator
// follow the same includes in CI) dropped, as are `#include <...>` lines (the
// C++ side of a src/shared header). An error names the missing file.
Result<std::string> resolveIncludes(std::string_view fileName);

// A compute program from one embedded shader file, includes resolved; an error
// carries the driver's log.
Result<Program> loadComputeProgram(std::string_view fileName);

// A vertex + fragment program from two embedded files, includes resolved.
Result<Program> loadRenderProgram(std::string_view vertexFile, std::string_view fragmentFile);

}  // namespace meniscus::gl
