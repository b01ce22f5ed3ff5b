// CPU thickness stage, SPEC §3.4. The fluid thickness seen through a pixel is
// the summed length of its ray inside the particle spheres (van der Laan et
// al. 2009, US 8,947,430 eq. 13 accumulate per-sprite thickness additively;
// here the chord is exact ray-sphere instead of a sprite profile), clipped to
// the part in front of the opaque scene and beyond the near plane. Spheres of
// radius r at spacing s fill only 4/3 pi r^3 / s^3 of the space, so the sum is
// scaled by w = s^3 / (4/3 pi r^3): a block at rest spacing then reads its true
// depth on average.
//
// The chords come from the same tiled binning and tile pass as the depth splat
// (splat.cpp): the per-pixel sum runs in bin order, a fixed order, so the
// result does not depend on the thread count.
//
// Optional blur (thesis §4.1.3): a separable Gaussian whose sigma is constant
// in world space (blurSigmaRadii * r, projected with the raw fluid depth at the
// centre pixel). Only fluid pixels are written, so thickness does not bleed into
// the background; their kernels do gather the zeros just outside the fluid,
// which thins the silhouettes smoothly as intended. The kernel radius is the
// whole number of pixels R = ceil(3 sigma_px) (capped), and the weights use
// sigma = R/3 from a table per R: sigma is rounded up by at most 1/3 px, and no
// exp is evaluated per pixel. Kernel radii are capped at min(maxKernelPx, 255).
#include "cpu/thickness.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cpu/filter_separable.h"  // KernelTable, the vector helpers, transpose
#include "cpu/filter_util.h"
#include "cpu/splat.h"

namespace meniscus::cpu {

namespace {

using detail::FloatV;
using detail::kLanes;

// One 1-D pass over a line of `len` pixels: out[i] = in[i] blurred with the
// Gaussian of radius rad[i] (table row rad[i], sigma = rad[i] / 3), or copied
// where rad[i] = 0. `in` is padded with table.padPx() zeros on both sides, so
// the taps run in whole groups of kLanes (the table rows are zero past the
// radius) without bounds checks. Taps off the image are left out and the
// remaining weights renormalised.
void blurLine(const float* in, const std::uint8_t* rad, float* out, int len, const KernelTable& table) {
    for (int i = 0; i < len; ++i) {
        const int R = rad[i];
        if (R == 0) {
            out[i] = in[i];
            continue;
        }
        const float* w = table.row(R);
        const float* p = in + i;
        FloatV s{};
        for (int k = -R; k <= R; k += kLanes) s += detail::loadV(p + k) * detail::loadV(w + k);
        float sum = (s[0] + s[1]) + (s[2] + s[3]);
        if (i < R || i + R >= len) {
            float wsum = 0.0f;
            for (int k = std::max(-R, -i); k <= std::min(R, len - 1 - i); ++k) wsum += w[k];
            sum /= wsum;
        }
        out[i] = sum;
    }
}

void blurThickness(Image<float>& thickness, const Image<float>& rawDepth, const Camera& camera, float radius,
                   const ThicknessParams& params) {
    const int maxR = std::min(255, std::max(0, params.maxKernelPx));
    if (!(params.blurSigmaRadii > 0.0f) || maxR == 0) return;
    const int W = thickness.width, H = thickness.height;
    if (rawDepth.width != W || rawDepth.height != H || W <= 0 || H <= 0) return;
    const KernelTable table = KernelTable::gaussian(maxR);
    const int pad = table.padPx();
    // Kernel radius (3 sigma) per pixel, once for both passes; 0 = no fluid, not blurred.
    const float worldRadiusM = 3.0f * params.blurSigmaRadii * radius;
    const float f = camera.focalPx();
    Image<std::uint8_t> radiusPx(W, H);
    forEachRow(H, [&](int y) {
        for (int x = 0; x < W; ++x) {
            const float z = rawDepth.at(x, y);
            radiusPx.at(x, y) = std::uint8_t(isFluid(z) ? projectedRadiusPx(worldRadiusM, f, z, maxR) : 0);
        }
    });
    Image<float> tmp(W, H);
    // x pass: thickness -> tmp, through a zero-padded copy of each row.
    tbb::parallel_for(tbb::blocked_range<int>(0, H, 4), [&](const tbb::blocked_range<int>& rows) {
        std::vector<float> line(std::size_t(W + 2 * pad), 0.0f);
        for (int y = rows.begin(); y < rows.end(); ++y) {
            const std::size_t o = std::size_t(y) * W;
            std::copy_n(thickness.pixels.data() + o, W, line.data() + pad);
            blurLine(line.data() + pad, radiusPx.pixels.data() + o, tmp.pixels.data() + o, W, table);
        }
    });
    // y pass: tmp -> thickness, columns gathered kColumnBlock at a time into
    // contiguous padded lines (row-wise reads, not one cache miss per tap).
    constexpr int kBlock = detail::kColumnBlock;
    const int blocks = (W + kBlock - 1) / kBlock;
    tbb::parallel_for(tbb::blocked_range<int>(0, blocks, 1), [&](const tbb::blocked_range<int>& bs) {
        const std::size_t lineLen = std::size_t(H + 2 * pad);
        std::vector<float> lines(lineLen * kBlock, 0.0f), outs(std::size_t(H) * kBlock);
        std::vector<std::uint8_t> rads(std::size_t(H) * kBlock);
        for (int b = bs.begin(); b < bs.end(); ++b) {
            const int x0 = b * kBlock, nc = std::min(kBlock, W - x0);
            detail::transpose(&tmp.at(x0, 0), std::size_t(W), lines.data() + pad, lineLen, H, nc,
                              [](float v) { return v; });
            for (int y = 0; y < H; ++y)
                for (int c = 0; c < nc; ++c) rads[std::size_t(c) * H + y] = radiusPx.at(x0 + c, y);
            for (int c = 0; c < nc; ++c)
                blurLine(lines.data() + c * lineLen + pad, rads.data() + std::size_t(c) * H,
                         outs.data() + std::size_t(c) * H, H, table);
            detail::transpose(outs.data(), std::size_t(H), &thickness.at(x0, 0), std::size_t(W), nc, H,
                              [](float v) { return v; });
        }
    });
}

}  // namespace

float thicknessWeight(float radius, const ThicknessParams& params) {
    const float s = params.spacingM > 0.0f ? params.spacingM : 2.0f * radius;
    const float q = s / radius;  // the ratio, so w is the same at every scale
    return q * q * q * (3.0f / (4.0f * std::numbers::pi_v<float>));
}

Image<float> computeThickness(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                              const ThicknessParams& params, const Image<float>* sceneDepth,
                              const Image<float>& rawDepth) {
    Image<float> thickness(camera.width, camera.height, 0.0f);
    const SplatBins bins = binParticles(camera, positionsWorld, radius);
    splatBins(camera, bins, radius, sceneDepth, nullptr, &thickness, thicknessWeight(radius, params));
    blurThickness(thickness, rawDepth, camera, radius, params);
    return thickness;
}

DepthAndThickness splatDepthAndThickness(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                                         const ThicknessParams& params, const Image<float>* sceneDepth) {
    DepthAndThickness out{Image<float>(camera.width, camera.height), Image<float>(camera.width, camera.height)};
    const SplatBins bins = binParticles(camera, positionsWorld, radius);
    splatBins(camera, bins, radius, sceneDepth, &out.depth, &out.thickness, thicknessWeight(radius, params));
    blurThickness(out.thickness, out.depth, camera, radius, params);
    return out;
}

}  // namespace meniscus::cpu
