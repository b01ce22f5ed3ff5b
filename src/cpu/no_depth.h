// The depth of a pixel with no surface: +infinity, in every depth image of the
// CPU stages (docs/conventions.md), one constant for all of them.
#pragma once

#include <limits>

namespace meniscus::cpu {

inline constexpr float kInf = std::numeric_limits<float>::infinity();

}  // namespace meniscus::cpu
