// The bilateral filter's range weight (see filter_separable.h); the spatial
// weight tables are shared::KernelTable (src/shared/kernel_table.cpp).
#include "cpu/filter_separable.h"

#include <limits>

namespace meniscus::cpu {

RangeGaussian::RangeGaussian(float sigmaM) {
    // sigma <= 0 (or NaN): only equal depths count; sigma = inf: every tap does.
    const double s = double(sigmaM);
    scale_ = sigmaM > 0.0f ? float(1.0 / (2.0 * s * s * std::log(2.0))) : std::numeric_limits<float>::max();
}

}  // namespace meniscus::cpu
