// Thickness parameters derived once for both backends (see thickness.h).
#include "shared/thickness.h"

#include <algorithm>
#include <numbers>

namespace meniscus::shared {

float thicknessWeight(float radius, const ThicknessParams& params) {
    const float s = params.spacingM > 0.0f ? params.spacingM : 2.0f * radius;
    const float q = s / radius;  // the ratio, so w is the same at every scale
    return q * q * q * (3.0f / (4.0f * std::numbers::pi_v<float>));
}

int thicknessDivisor(int resolutionDivisor) { return resolutionDivisor >= 4 ? 4 : resolutionDivisor >= 2 ? 2 : 1; }

int thicknessBlurCapPx(int maxKernelPx) { return std::min(kThicknessBlurMaxPx, std::max(0, maxKernelPx)); }

}  // namespace meniscus::shared
