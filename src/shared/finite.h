// Whether a point's or vector's three coordinates are all finite: the check
// every reader, camera and checkpoint applies before trusting a value.
#pragma once

#include <cmath>

#include <glm/vec3.hpp>

namespace meniscus {

inline bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace meniscus
