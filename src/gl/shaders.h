// The GL backend's shader sources: the files under src/gl/shaders, embedded at
// build time by cmake/embed_shaders.cmake.
#pragma once

#include <string_view>

namespace meniscus::gl {

// The text of src/gl/shaders/<fileName> (e.g. "splat_depth.comp"); empty when
// there is no such file.
std::string_view shaderSource(std::string_view fileName);

}  // namespace meniscus::gl
