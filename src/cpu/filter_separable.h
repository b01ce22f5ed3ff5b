// Separable depth smoothing with a per-pixel kernel
// (docs/pipeline.md#smoothing), written once for the Gaussian, bilateral and
// binomial filters: an x pass then a y pass, each a 1-D weighted average around
// the centre pixel. The formulas (the kernel radius projected at the centre
// depth, the weights blended between the tables' integer radii, the bilateral
// range weight, the renormalised result) are src/shared/separable_filter.h,
// which the GL twin calls too; the weight tables are shared::KernelTable.
//  - Taps that are +inf or further than jumpM from z0 get weight 0 and the rest
//    are renormalised, so separate bodies never blend and silhouettes are not
//    pulled toward the background. A +inf centre stays +inf (a NaN one, not a
//    valid depth, comes out +inf too).
// Each output pixel is computed by one task in a fixed tap order, so the result
// is bit-identical for any thread count.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/lanes.h"
#include "cpu/filter_util.h"
#include "meniscus/types.h"
#include "shared/kernel_table.h"
#include "shared/separable_filter.h"

namespace meniscus::cpu {

namespace detail {

// kLanes taps at a time in GCC/Clang vector types (SSE/AVX on x86-64, NEON on
// ARM): the per-tap work is a handful of flops, so without SIMD the loop is
// bound by one scalar add chain and mispredicted exclusion branches. Lanes are
// summed in a fixed order, so the result does not depend on the thread count.
using lanes::FloatV;  // core/lanes.h: one SSE / NEON register, wider is slower on baseline x86-64
using lanes::IntV;
using lanes::kLanes;
using lanes::loadV;
using lanes::selectV;
static_assert(kLanes == shared::kTapGroup, "the kernel tables pad rows for groups of kLanes taps");

}  // namespace detail

// The weight tables, shared with the GL backend.
using shared::KernelTable;

// No range weight: plain (Gaussian / binomial) spatial kernel.
struct NoRangeWeight {
    detail::FloatV operator()(detail::FloatV) const { return detail::FloatV{} + 1.0f; }  // x * 1 folds away
};

// Gaussian range weight exp(-dz^2 / (2 sigma^2)) on the depth difference
// (bilateral, thesis eq. 4.3), kLanes at a time as 2^-x (the series:
// shared::separableRangeWeight): 2^-trunc(x) from the exponent bits. A table
// lookup would need a scalar gather per lane.
class RangeGaussian {
public:
    explicit RangeGaussian(float sigmaM);
    detail::FloatV operator()(detail::FloatV dz) const {
        using detail::FloatV;
        using detail::IntV;
        FloatV x = shared::separableRangeExponent(dz, scale_);
        x = x < shared::kSeparableRangeCap ? x : FloatV{} + shared::kSeparableRangeCap;
        const IntV i = __builtin_convertvector(x, IntV);  // x >= 0: truncation = floor
        const IntV bits = (127 - i) << 23;
        FloatV pow2;
        std::memcpy(&pow2, &bits, sizeof pow2);
        return shared::separableRangeWeight(x, __builtin_convertvector(i, FloatV), pow2);
    }
    float operator()(float dz) const { return (*this)(detail::FloatV{} + dz)[0]; }

private:
    float scale_ = 0.0f;  // 1 / (2 sigma^2 ln 2)
};

// The per-pixel kernel of one filter.
struct SeparableKernel {
    float kernelWorldM = 0.0f;  // kernel radius in metres; in pixels s = kernelWorldM * f / z0
    float jumpM = 0.0f;         // taps with |z - z0| > jumpM are ignored
};

namespace detail {

// Lines being filtered hold this finite stand-in for "no fluid" (+inf or NaN
// in the image), so that an excluded tap's 0 * dz is 0, never NaN, and the tap
// loop needs no extra select; it is never within the jump of a real depth.
inline constexpr float kNoFluid = std::numeric_limits<float>::max();
inline float toLine(float z) { return isFluid(z) ? z : kNoFluid; }

// Filters one line `in` (kNoFluid for no fluid, padded with kNoFluid by
// table.padPx() on both sides) into out[0, len) (+inf for no fluid).
// kernelPxDepth = kernelWorldM * f, so the kernel radius is s = kernelPxDepth / z0.
template <class RangeWeight>
void filterLine(const float* in, float* out, int len, const KernelTable& table, float kernelPxDepth, float jumpM,
                const RangeWeight& range) {
    const float maxS = float(table.maxRadius());
    const FloatV jumpV = FloatV{} + jumpM;
    const IntV absMask = IntV{} + 0x7fffffff;
    for (int i = 0; i < len; ++i) {
        const float z0 = in[i];
        if (!(z0 < kNoFluid)) {
            out[i] = INFINITY;
            continue;
        }
        const float s = shared::separableKernelPx(kernelPxDepth, z0, maxS);
        const int n = int(s);
        const float t = shared::separableBlend(s, n);
        const float* a = table.row(n);
        const float* d = table.diff(n);
        const float* line = in + i;
        const FloatV z0V = FloatV{} + z0;
        FloatV sw{}, sd{};
        // Taps -m .. m rounded up to whole groups of kLanes; the extra taps have
        // weight 0 in the zero-padded table rows.
        const int m = n + 1;
        for (int k = -m; k <= m; k += kLanes) {
            const FloatV dz = loadV(line + k) - z0V;
            const IntV ok = selectV(absMask, dz) <= jumpV;  // |dz| <= jump
            const FloatV w = selectV(ok, shared::separableSpatialWeight(loadV(a + k), loadV(d + k), t) * range(dz));
            sw += w;
            sd += w * dz;
        }
        // The centre tap always counts with a positive weight, so the sum is > 0.
        out[i] = shared::separableResult(z0, sw, sd);
    }
}

// Columns gathered per task in the y pass: one cache line of floats.
inline constexpr int kColumnBlock = 16;

// dst[c * dstStride + r] = src[r * srcStride + c] for r < rows, c < cols. The
// inner loop runs over the short side (one cache line of the image) so that
// the image is read / written one line at a time, never one line per element
// (a row stride of 1280 floats also aliases in L1). Raw restrict pointers:
// through Image::at the compiler must assume the buffers alias.
template <class Map>
void transpose(const float* __restrict src, std::size_t srcStride, float* __restrict dst, std::size_t dstStride,
               int rows, int cols, Map map) {
    if (rows >= cols) {
        for (int r = 0; r < rows; ++r)
            for (int c = 0; c < cols; ++c) dst[c * dstStride + r] = map(src[r * srcStride + c]);
    } else {
        for (int c = 0; c < cols; ++c)
            for (int r = 0; r < rows; ++r) dst[c * dstStride + r] = map(src[r * srcStride + c]);
    }
}

}  // namespace detail

// `iterations` times an x pass then a y pass of the per-pixel kernel.
template <class RangeWeight>
Image<float> separableFilter(const Image<float>& depth, float focalPx, const KernelTable& table,
                             const SeparableKernel& kernel, int iterations, const RangeWeight& range) {
    const int w = depth.width, h = depth.height;
    const int pad = table.padPx();
    const float kernelPxDepth = kernel.kernelWorldM * focalPx;
    const float jumpM = kernel.jumpM;
    Image<float> cur = depth;
    if (w <= 0 || h <= 0) return cur;
    Image<float> tmp(w, h);
    for (int it = 0; it < iterations; ++it) {
        // x pass: cur -> tmp, one padded copy of the row per task.
        tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& rows) {
            std::vector<float> line(std::size_t(w + 2 * pad), detail::kNoFluid);
            for (int y = rows.begin(); y < rows.end(); ++y) {
                std::transform(&cur.at(0, 0) + std::size_t(y) * w, &cur.at(0, 0) + std::size_t(y + 1) * w,
                               line.data() + pad, detail::toLine);
                detail::filterLine(line.data() + pad, &tmp.at(0, y), w, table, kernelPxDepth, jumpM, range);
            }
        });
        // y pass: tmp -> cur, columns gathered kColumnBlock at a time into
        // contiguous padded lines (row-wise reads, not one cache miss per tap).
        const int blocks = (w + detail::kColumnBlock - 1) / detail::kColumnBlock;
        tbb::parallel_for(tbb::blocked_range<int>(0, blocks, 1), [&](const tbb::blocked_range<int>& bs) {
            const std::size_t lineLen = std::size_t(h + 2 * pad);
            std::vector<float> lines(lineLen * detail::kColumnBlock, detail::kNoFluid);
            std::vector<float> outs(std::size_t(h) * detail::kColumnBlock);
            for (int b = bs.begin(); b < bs.end(); ++b) {
                const int x0 = b * detail::kColumnBlock;
                const int nc = std::min(detail::kColumnBlock, w - x0);
                detail::transpose(&tmp.at(x0, 0), std::size_t(w), lines.data() + pad, lineLen, h, nc, detail::toLine);
                for (int c = 0; c < nc; ++c)
                    detail::filterLine(lines.data() + c * lineLen + pad, outs.data() + std::size_t(c) * h, h, table,
                                       kernelPxDepth, jumpM, range);
                detail::transpose(outs.data(), std::size_t(h), &cur.at(x0, 0), std::size_t(w), nc, h,
                                  [](float z) { return z; });
            }
        });
    }
    return cur;
}

}  // namespace meniscus::cpu
