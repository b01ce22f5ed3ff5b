// Taps and weights of the narrow-range filter (see narrow_range.h).
#include "shared/narrow_range.h"

#include <algorithm>
#include <cmath>

namespace meniscus::shared {

std::vector<DiscTap> narrowRangeHalfDisc(int R) {
    std::vector<DiscTap> taps;
    for (int dy = 0; dy <= R; ++dy)
        for (int dx = -R; dx <= R; ++dx) {
            if (dy == 0 && dx <= 0) continue;
            const int d2 = dx * dx + dy * dy;
            if (d2 <= R * R) taps.push_back({dx, dy, d2});
        }
    std::sort(taps.begin(), taps.end(), [](const DiscTap& a, const DiscTap& b) {
        if (a.d2 != b.d2) return a.d2 < b.d2;
        if (a.dy != b.dy) return a.dy < b.dy;
        return a.dx < b.dx;
    });
    return taps;
}

float narrowRangeWeight(int d2, int R) {
    const double sigma = double(R) / 3.0;
    return float(std::exp(-double(d2) / (2.0 * sigma * sigma)));
}

}  // namespace meniscus::shared
