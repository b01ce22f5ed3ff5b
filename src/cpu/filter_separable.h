// Separable depth smoothing with a per-pixel kernel (SPEC §3.5), written once
// for the Gaussian, bilateral and binomial filters: an x pass then a y pass,
// each a 1-D weighted average around the centre pixel.
//  - The kernel radius s = kernelWorldM * f / z0 is the world length projected
//    at the centre depth z0 (constant width in world space, patent "System and
//    method for rendering a particle-based fluid surface"), capped at maxKernelPx.
//  - Weights come from precomputed tables, one normalised row per integer
//    radius n; a real radius s = n + t uses (1-t) row(n) + t row(n+1). Rounding
//    s instead would make the smoothing jump where ceil(s) changes, which shows
//    up as contour lines in the normals of sloped fluid; blending keeps the
//    output continuous in depth (and so in scale).
//  - Taps that are +inf or further than jumpM from z0 get weight 0 and the rest
//    are renormalised, so separate bodies never blend and silhouettes are not
//    pulled toward the background. A +inf centre stays +inf.
// Each output pixel is computed by one task in a fixed tap order, so the result
// is bit-identical for any thread count.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cpu/filter_util.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

// Normalised symmetric 1-D kernels for every integer radius n in
// [0, maxRadius + 1] (the extra row is the upper end of the blend at the cap).
class KernelTable {
public:
    // Gaussian with sigma = n / 3 truncated at |k| <= n (kernel radius = 3 sigma).
    static KernelTable gaussian(int maxRadius);
    // Binomial C(2n, n + k) / 4^n (Pascal's triangle row 2n), Instant Liquids §2.2.
    static KernelTable binomial(int maxRadius);

    int maxRadius() const { return maxRadius_; }
    // Weight of tap k in the kernel of radius n (n <= maxRadius + 1); 0 for |k| > n.
    float weight(int n, int k) const { return row(n)[k]; }
    // Row n centred on tap 0: valid for |k| <= maxRadius + 1.
    const float* row(int n) const { return rows_.data() + std::size_t(n) * stride_ + half_; }
    // row(n + 1) - row(n), for n <= maxRadius.
    const float* diff(int n) const { return diffs_.data() + std::size_t(n) * stride_ + half_; }

private:
    KernelTable(int maxRadius, std::vector<double> rows);
    int maxRadius_ = 0;
    int half_ = 1;    // maxRadius + 1: the widest tap offset
    int stride_ = 3;  // 2 * half_ + 1
    std::vector<float> rows_, diffs_;
};

// No range weight: plain (Gaussian / binomial) spatial kernel.
struct NoRangeWeight {
    float operator()(float) const { return 1.0f; }
};

// Gaussian range weight exp(-dz^2 / (2 sigma^2)) on the depth difference
// (bilateral, thesis eq. 4.3), tabulated over (dz / 5 sigma)^2 with linear
// interpolation so there is no exp per tap; 0 beyond 5 sigma (exp(-12.5)).
class RangeGaussian {
public:
    explicit RangeGaussian(float sigmaM);
    float operator()(float dz) const {
        const float u = std::min(dz * dz * scale_, float(kSteps));
        const int i = int(u);
        return table_[i] + (u - float(i)) * (table_[i + 1] - table_[i]);
    }

private:
    static constexpr int kSteps = 1024;
    float scale_ = 0.0f;  // kSteps / (5 sigma)^2
    std::vector<float> table_;
};

// The per-pixel kernel of one filter.
struct SeparableKernel {
    float kernelWorldM = 0.0f;  // kernel radius in metres; in pixels s = kernelWorldM * f / z0
    float jumpM = 0.0f;         // taps with |z - z0| > jumpM are ignored
};

namespace detail {

// Filters one line `in` (padded with +inf by table.maxRadius() + 1 on both
// sides) into out[0, len). kernelPxDepth = kernelWorldM * f, so s = kernelPxDepth / z0.
template <class RangeWeight>
void filterLine(const float* in, float* out, int len, const KernelTable& table, float kernelPxDepth, float jumpM,
                const RangeWeight& range) {
    const float maxS = float(table.maxRadius());
    for (int i = 0; i < len; ++i) {
        const float z0 = in[i];
        if (!isFluid(z0)) {
            out[i] = z0;
            continue;
        }
        float s = std::min(maxS, kernelPxDepth / z0);
        if (!(s > 0.0f)) s = 0.0f;
        const int n = int(s);
        const float t = s - float(n);
        const float* a = table.row(n);
        const float* d = table.diff(n);
        const float* line = in + i;
        // Four partial sums in a fixed order: deterministic, and they break the
        // add dependency chain so the compiler can vectorise the taps.
        float sw[4] = {0, 0, 0, 0}, sd[4] = {0, 0, 0, 0};
        const int m = n + 1;
        int k = -m;
        for (; k + 3 <= m; k += 4) {
            for (int l = 0; l < 4; ++l) {
                float dz = line[k + l] - z0;
                const bool ok = std::abs(dz) <= jumpM;  // false for +inf taps
                dz = ok ? dz : 0.0f;
                const float w = ok ? (a[k + l] + t * d[k + l]) * range(dz) : 0.0f;
                sw[l] += w;
                sd[l] += w * dz;
            }
        }
        for (; k <= m; ++k) {
            float dz = line[k] - z0;
            const bool ok = std::abs(dz) <= jumpM;
            dz = ok ? dz : 0.0f;
            const float w = ok ? (a[k] + t * d[k]) * range(dz) : 0.0f;
            sw[0] += w;
            sd[0] += w * dz;
        }
        // The centre tap always counts with a positive weight, so the sum is > 0.
        // Averaging the differences dz (not z) keeps precision far from the eye.
        out[i] = z0 + ((sd[0] + sd[1]) + (sd[2] + sd[3])) / ((sw[0] + sw[1]) + (sw[2] + sw[3]));
    }
}

// Columns gathered per task in the y pass: one cache line of floats.
inline constexpr int kColumnBlock = 16;

}  // namespace detail

// `iterations` times an x pass then a y pass of the per-pixel kernel.
template <class RangeWeight>
Image<float> separableFilter(const Image<float>& depth, float focalPx, const KernelTable& table,
                             const SeparableKernel& kernel, int iterations, const RangeWeight& range) {
    const int w = depth.width, h = depth.height;
    const int pad = table.maxRadius() + 1;
    const float kernelPxDepth = kernel.kernelWorldM * focalPx;
    const float jumpM = kernel.jumpM;
    Image<float> cur = depth;
    if (w <= 0 || h <= 0) return cur;
    Image<float> tmp(w, h);
    for (int it = 0; it < iterations; ++it) {
        // x pass: cur -> tmp, one padded copy of the row per task.
        tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& rows) {
            std::vector<float> line(std::size_t(w + 2 * pad), INFINITY);
            for (int y = rows.begin(); y < rows.end(); ++y) {
                std::copy_n(&cur.at(0, y), w, line.data() + pad);
                detail::filterLine(line.data() + pad, &tmp.at(0, y), w, table, kernelPxDepth, jumpM, range);
            }
        });
        // y pass: tmp -> cur, columns gathered kColumnBlock at a time into
        // contiguous padded lines (row-wise reads, not one cache miss per tap).
        const int blocks = (w + detail::kColumnBlock - 1) / detail::kColumnBlock;
        tbb::parallel_for(tbb::blocked_range<int>(0, blocks, 1), [&](const tbb::blocked_range<int>& bs) {
            const std::size_t lineLen = std::size_t(h + 2 * pad);
            std::vector<float> lines(lineLen * detail::kColumnBlock, INFINITY);
            std::vector<float> outs(std::size_t(h) * detail::kColumnBlock);
            for (int b = bs.begin(); b < bs.end(); ++b) {
                const int x0 = b * detail::kColumnBlock;
                const int nc = std::min(detail::kColumnBlock, w - x0);
                for (int y = 0; y < h; ++y)
                    for (int c = 0; c < nc; ++c) lines[c * lineLen + pad + y] = tmp.at(x0 + c, y);
                for (int c = 0; c < nc; ++c)
                    detail::filterLine(lines.data() + c * lineLen + pad, outs.data() + std::size_t(c) * h, h, table,
                                       kernelPxDepth, jumpM, range);
                for (int y = 0; y < h; ++y)
                    for (int c = 0; c < nc; ++c) cur.at(x0 + c, y) = outs[std::size_t(c) * h + y];
            }
        });
    }
    return cur;
}

}  // namespace meniscus::cpu
