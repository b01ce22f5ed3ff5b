// The narrow-range filter's taps and weights
// (docs/pipeline.md#narrow-range-filter; Truong & Yuksel, I3D 2018), written
// once for both backends: the CPU's tap tables
// (src/cpu/filter_narrow_range.cpp) and the GL backend's uploaded ones
// (src/gl/filter_narrow_range.cpp) are built from these. C++ only.
#pragma once

#include <vector>

namespace meniscus::shared {

// One tap of the 2-D kernel at offset (dx, dy) pixels; d2 = dx^2 + dy^2.
struct DiscTap {
    int dx, dy, d2;
};

// The half disc dx^2 + dy^2 <= R^2 with dy > 0, or dy = 0 and dx > 0 (each
// tap's mirror covers the other half), in the one "centre outward" order every
// pixel visits: by d2, ties by dy, then dx. d2 being the first key, the list
// for any radius r < R is the prefix with d2 <= r^2.
std::vector<DiscTap> narrowRangeHalfDisc(int R);

// The Gaussian weight of a tap at squared distance d2 in the kernel of radius
// R pixels (sigma = R / 3), evaluated in double.
float narrowRangeWeight(int d2, int R);

}  // namespace meniscus::shared
