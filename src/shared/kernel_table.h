// Weight tables of the separable filters (docs/pipeline.md#smoothing: Gaussian,
// bilateral, binomial) and of the thickness blur (docs/pipeline.md#thickness),
// written once for both backends: the CPU filters read them directly
// (src/cpu/filter_separable.h), the GL backend uploads them as they are
// (src/gl/filter_separable.cpp). C++ only. Built once per filter call (a few
// hundred entries), so no exp or factorial per pixel.
#pragma once

#include <cstddef>
#include <vector>

namespace meniscus::shared {

// Taps are read in groups of this many: the CPU's SIMD lanes (one SSE / NEON
// register of floats) and the GL shaders' vec4 texels.
inline constexpr int kTapGroup = 4;

// Normalised symmetric 1-D kernels for every integer radius n in
// [0, maxRadius + 1] (the extra row is the upper end of the blend at the cap).
class KernelTable {
public:
    // Gaussian with sigma = n / 3 truncated at |k| <= n (kernel radius = 3 sigma).
    static KernelTable gaussian(int maxRadius);
    // Binomial C(2n, n + k) / 4^n (Pascal's triangle row 2n), Instant Liquids §2.2.
    static KernelTable binomial(int maxRadius);

    int maxRadius() const { return maxRadius_; }
    // Taps stored on each side of tap 0, zero past n (and the no-fluid padding
    // the filtered lines need): maxRadius + 1 for the blend, + kTapGroup - 1 to
    // finish the last group of taps.
    int padPx() const { return half_; }
    // Weight of tap k in the kernel of radius n (n <= maxRadius + 1); 0 for |k| > n.
    float weight(int n, int k) const { return row(n)[k]; }
    // Row n centred on tap 0: valid for |k| <= padPx().
    const float* row(int n) const { return rows_.data() + std::size_t(n) * stride_ + half_; }
    // row(n + 1) - row(n), for n <= maxRadius.
    const float* diff(int n) const { return diffs_.data() + std::size_t(n) * stride_ + half_; }

private:
    KernelTable(int maxRadius, std::vector<double> rows);
    int maxRadius_ = 0;
    int half_ = 4;    // padPx()
    int stride_ = 9;  // 2 * half_ + 1
    std::vector<float> rows_, diffs_;
};

}  // namespace meniscus::shared
