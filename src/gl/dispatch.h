// Work-group counts for the compute passes, written once.
#pragma once

#include <algorithm>

#include "gl/objects.h"

namespace meniscus::gl {

// The minimum GL_MAX_COMPUTE_WORK_GROUP_COUNT per dimension; shaders that may
// need more loop past it (grid-stride loops).
constexpr GLuint kMaxGroups = 65535;

constexpr GLuint ceilDiv(GLuint a, GLuint b) { return (a + b - 1) / b; }

// Work groups of a 1-D grid-stride pass over `items`, `perGroup` of them per
// group and round (local size x items per invocation: llvmpipe pays a fixed
// cost per work group, so per-pixel passes give each invocation a few), at
// least 1 and at most kMaxGroups.
inline GLuint gridGroups(GLuint items, GLuint perGroup) {
    return std::clamp<GLuint>(ceilDiv(items, perGroup), 1, kMaxGroups);
}

}  // namespace meniscus::gl
