// See fluid_scale.h.
#include "core/fluid_scale.h"

#include <cmath>

#include <glm/glm.hpp>

#include "shared/upsample.h"

namespace meniscus {

int fluidDivisor(float scale) {
    if (scale == 1.0f) return 1;
    if (scale == 0.5f) return 2;
    if (scale == 0.25f) return 4;
    return 0;
}

Camera reducedCamera(const Camera& full, int d) {
    if (d <= 1) return full;
    Camera low = full;
    low.width = shared::lowSide(full.width, d);
    low.height = shared::lowSide(full.height, d);
    // f_low = f / d with H_low rows: tan(fov_low / 2) = H_low d / H tan(fov / 2).
    if (low.height * d != full.height) {
        const double t = std::tan(0.5 * double(glm::radians(full.fovYDegrees)));
        low.fovYDegrees = float(glm::degrees(2.0 * std::atan(double(low.height * d) / double(full.height) * t)));
    }
    return low;
}

Image<float> nearestUpsample(const Image<float>& low, int W, int H, int d) {
    Image<float> out(W, H, 0.0f);
    if (low.width <= 0 || low.height <= 0) return out;
    for (int y = 0; y < H; ++y) {
        const int j = shared::nearestLowPixel(y, H, low.height, d);
        for (int x = 0; x < W; ++x) out.at(x, y) = low.at(shared::nearestLowPixel(x, W, low.width, d), j);
    }
    return out;
}

}  // namespace meniscus
