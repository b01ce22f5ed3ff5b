// Narrow-range filter: N. Truong and C. Yuksel, "A Narrow-Range Filter for
// Screen-Space Fluid Rendering", Proc. ACM Comput. Graph. Interact. Tech. 1(1)
// (I3D 2018), as restated in docs/pipeline.md#narrow-range-filter. The authors'
// demo shader (github.com/ttnghia/RealTimeFluidRendering,
// Shaders/filter-narrow-range.fs.glsl) was read for the details; this is an
// independent implementation.
//
// For a fluid pixel of eye depth z0 (metres) and threshold τ = lambda·r the
// accepted range starts as [z0 − τ, z0 + τ]. Taps are visited from the centre
// outward in mirror pairs (t, −t) with Gaussian weights, σ = R/3 for a kernel
// radius R = ceil(filterSizeRadii·r·f/z0) pixels, capped at maxKernelPx:
//  - a tap in front of the range (z < lower: an occluding surface) gets weight 0
//    and so does its mirror, which keeps the mean unbiased;
//  - a tap behind it (z > upper, including +inf "no fluid") counts as z0 + mu·r,
//    which rounds silhouettes instead of pulling them toward the background;
//  - a tap inside widens the range to include [z − τ, z + τ] (range extension).
// Result: weighted mean over the centre (weight 1) and the accepted taps.
// `separable` runs the 1-D filter along x, then along y; `iterations` repeats.
//
// Parameters (NarrowRangeParams): iterations (count), filterSizeRadii (world
// kernel radius in particle radii r), lambda (range threshold, radii), mu
// (behind-tap depth offset, radii), maxKernelPx (pixels), separable (bool).
//
// Choices and differences from the demo shader:
//  - 2-D taps cover the disc dx² + dy² ≤ R² (the shader's square misses the
//    axes), sorted by distance, ties by (dy, dx): "centre outward", one order for
//    every pixel. Both taps of a pair are classified against the range as it was
//    before the pair, then both widen it (the shader lets the first widen the
//    range for the second); an inside tap widens the range even when its mirror
//    zeroes its weight, as in the shader.
//  - The 1-D filter uses one range for both sides (the shader keeps one per
//    side), so 1-D and 2-D are the same procedure over different tap lists.
//  - Taps outside the image are ignored with their mirror (a −inf frame, i.e.
//    "in front"), so the border neither pulls nor rounds the surface.
//  - Deviations z − z0 are accumulated, not z, to keep float precision.
//  - Speed: precomputed tap tables (offset, weight) per kernel radius (the tap
//    order and weights from src/shared/narrow_range.h, as the GL twin's), and eight
//    adjacent pixels filtered at once in vector lanes (each lane is the exact
//    scalar computation of its pixel, so results do not depend on grouping).
//    The lane function is compiled twice (GCC target_clones: AVX2 and the SSE2
//    baseline, picked at run time); both do the same IEEE operations (no FMA),
//    so the output is the same on every x86-64 machine.
// Each output pixel depends only on the previous buffer (row-parallel), so the
// result is bit-identical for any thread count.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include "cpu/filter_util.h"
#include "cpu/filters.h"
#include "shared/narrow_range.h"
#include "cpu/no_depth.h"

namespace meniscus::cpu {

namespace {


// One tap pair: +offset and −offset (linear, in the padded buffer), weight w.
struct Tap {
    std::ptrdiff_t offset;
    float w;
};

// Tap lists for kernel radii 0..Rmax: taps[R] holds the pairs for radius R.
using TapTables = std::vector<std::vector<Tap>>;

// taps[R]: the prefix of the largest radius's half disc inside radius R.
TapTables tapTables2D(int Rmax, std::ptrdiff_t stride) {
    TapTables t(Rmax + 1);
    const std::vector<shared::DiscTap> disc = shared::narrowRangeHalfDisc(Rmax);
    for (int R = 1; R <= Rmax; ++R)
        for (std::size_t i = 0; i < disc.size() && disc[i].d2 <= R * R; ++i)
            t[R].push_back({disc[i].dy * stride + disc[i].dx, shared::narrowRangeWeight(disc[i].d2, R)});
    return t;
}

TapTables tapTables1D(int Rmax, std::ptrdiff_t step) {
    TapTables t(Rmax + 1);
    for (int R = 1; R <= Rmax; ++R)
        for (int k = 1; k <= R; ++k) t[R].push_back({k * step, shared::narrowRangeWeight(k * k, R)});
    return t;
}

struct Setup {
    float f, world, tau, behind;
    int Rmax;
};

// Eight floats (GCC/Clang vector extension: one AVX register, or two SSE ones):
// compares give lane masks, `m ? a : b` selects per lane, arithmetic is per
// lane IEEE.
constexpr int kLanes = 8;
typedef float FloatN __attribute__((vector_size(4 * kLanes)));

// Narrow-range means of the kLanes adjacent pixels c[0..kLanes) over the
// pairs `taps` (one kernel for all lanes), into out[0..kLanes). Each lane is exactly
// the scalar computation for its pixel; lanes of +inf pixels produce garbage
// that the caller discards.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void filterN(const float* c, const std::vector<Tap>& taps, float tau, float behind, float* out) {
    using T = FloatN;
    T z0, a, b;  // (loaded with memcpy: unaligned, and no vector-typed calls across the clones)
    std::memcpy(&z0, c, sizeof z0);
    T lower = z0 - tau, upper = z0 + tau;
    const T zero{};
    T sum = zero;   // deviations from z0; the centre adds weight 1, deviation 0
    T wsum = zero;  // over pairs (each tap of a pair has weight w)
    const T dBehind = zero + behind;  // a behind tap counts as z0 + mu·r
    for (const Tap& t : taps) {
        std::memcpy(&a, c + t.offset, sizeof a);
        std::memcpy(&b, c - t.offset, sizeof b);
        // Not in front: the depths are never NaN, so `a >= lower` is
        // !(a < lower), and one mask per tap serves the weights and the range.
        const auto inA = a >= lower, inB = b >= lower;
        const auto behindA = a > upper, behindB = b > upper;
        const T da = behindA ? dBehind : a - z0;
        const T db = behindB ? dBehind : b - z0;
        // A tap in front drops the pair (keeps the mean unbiased).
        const auto keep = inA & inB;
        sum += keep ? t.w * (da + db) : zero;
        wsum += keep ? zero + t.w : zero;
        // Range extension by inside taps. A front tap never raises `upper`
        // and a behind tap never lowers `lower` (the range is at least 2τ
        // wide), so each bound needs only one mask.
        const T la = inA ? a - tau : lower, lb = inB ? b - tau : lower;
        const T ua = behindA ? upper : a + tau, ub = behindB ? upper : b + tau;
        lower = la < lower ? la : lower;
        lower = lb < lower ? lb : lower;
        upper = ua > upper ? ua : upper;
        upper = ub > upper ? ub : upper;
    }
    const T result = z0 + sum / (2.0f * wsum + 1.0f);
    std::memcpy(out, &result, sizeof result);
}

// Kernel radius (pixels) of a pixel of depth z; 0 for +inf.
int kernelPx(float z, const Setup& s) { return isFluid(z) ? projectedRadiusPx(s.world, s.f, z, s.Rmax) : 0; }

// One pass over the padded buffers: dst = narrow-range(src) using `taps`.
// kLanes adjacent pixels are filtered at once with the kernel of the first; the
// leading ones that share that kernel radius are kept (at least the first),
// the rest are redone in the next step with their own kernel. Every pixel of
// dst's image area is written; its frame is left as it is.
void pass(const float* src, float* dst, int W, int H, int pad, const TapTables& taps, const Setup& s) {
    const std::ptrdiff_t PW = W + 2 * pad;
    forEachRow(H, [&](int y) {
        const std::size_t row = std::size_t(y + pad) * PW + pad;
        const float* in = &src[row];
        float* out = &dst[row];
        for (int x = 0; x < W;) {
            const int R = kernelPx(in[x], s);
            if (R == 0) {  // +inf, or a kernel under one pixel
                out[x] = in[x];
                ++x;
                continue;
            }
            float z[kLanes];
            filterN(in + x, taps[R], s.tau, s.behind, z);
            int n = 1;
            while (n < kLanes && x + n < W && kernelPx(in[x + n], s) == R) ++n;
            std::copy(z, z + n, out + x);
            x += n;
        }
    });
}

}  // namespace

Image<float> filterNarrowRange(const Image<float>& depth, const Camera& camera, float radius,
                               const NarrowRangeParams& p) {
    const int W = depth.width, H = depth.height;
    if (W <= 0 || H <= 0 || p.iterations <= 0 || !(radius > 0.0f)) return depth;

    Setup s;
    s.f = camera.focalPx();
    s.world = p.filterSizeRadii * radius;
    s.tau = p.lambda * radius;
    s.behind = p.mu * radius;
    // The filtered depth never gets nearer than the nearest input depth (every
    // accepted value is an input depth or lies behind z0), so the kernel radius
    // at the nearest pixel bounds all iterations. Kernels wider than the image
    // are pointless, which also bounds the padding. (The minimum per row in
    // parallel, then over the rows: a min does not depend on the order.)
    std::vector<float> rowMin(std::size_t(H), kInf);
    forEachRow(H, [&](int y) {
        const float* in = &depth.pixels[std::size_t(y) * W];
        float m = kInf;
        for (int x = 0; x < W; ++x) m = std::min(m, in[x]);
        rowMin[std::size_t(y)] = m;
    });
    float zMin = kInf;
    for (float z : rowMin) zMin = std::min(zMin, z);
    if (!isFluid(zMin)) return depth;
    s.Rmax = projectedRadiusPx(s.world, s.f, zMin, std::max(0, std::min(p.maxKernelPx, std::max(W, H))));
    if (s.Rmax == 0) return depth;

    // Padded copies with a −inf frame: taps there are "in front" and are dropped
    // with their mirror. Rmax + kLanes - 1 wide: lane loads reach further right.
    // Left uninitialised and written row by row in parallel (a serial fill of
    // both would cost more than the copy): `a` the frame and the depth, `b`
    // only the frame, since every pass writes the whole image area.
    const int pad = s.Rmax + kLanes - 1;
    const std::ptrdiff_t PW = W + 2 * pad;
    const std::size_t padded = std::size_t(PW) * std::size_t(H + 2 * pad);
    std::unique_ptr<float[]> a(new float[padded]), b(new float[padded]);
    tbb::parallel_for(tbb::blocked_range<int>(0, H + 2 * pad, 4), [&](const tbb::blocked_range<int>& rows) {
        for (int py = rows.begin(); py < rows.end(); ++py) {
            float* ra = &a[std::size_t(py) * PW];
            float* rb = &b[std::size_t(py) * PW];
            const int y = py - pad;
            if (y < 0 || y >= H) {
                std::fill(ra, ra + PW, -kInf);
                std::fill(rb, rb + PW, -kInf);
                continue;
            }
            const float* in = &depth.pixels[std::size_t(y) * W];
            std::fill(ra, ra + pad, -kInf);
            std::copy(in, in + W, ra + pad);
            std::fill(ra + pad + W, ra + PW, -kInf);
            std::fill(rb, rb + pad, -kInf);
            std::fill(rb + pad + W, rb + PW, -kInf);
        }
    });

    if (p.separable) {
        const TapTables tx = tapTables1D(s.Rmax, 1), ty = tapTables1D(s.Rmax, PW);
        for (int it = 0; it < p.iterations; ++it) {
            pass(a.get(), b.get(), W, H, pad, tx, s);
            pass(b.get(), a.get(), W, H, pad, ty, s);
        }
    } else {
        const TapTables t2 = tapTables2D(s.Rmax, PW);
        for (int it = 0; it < p.iterations; ++it) {
            pass(a.get(), b.get(), W, H, pad, t2, s);
            std::swap(a, b);
        }
    }

    Image<float> out(W, H);
    forEachRow(H, [&](int y) {
        const float* src = &a[std::size_t(y + pad) * PW + pad];
        std::copy(src, src + W, &out.pixels[std::size_t(y) * W]);
    });
    return out;
}

}  // namespace meniscus::cpu
