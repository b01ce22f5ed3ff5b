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

#include "cpu/filter_util.h"
#include "cpu/splat.h"

namespace meniscus::cpu {

namespace {

// Normalised Gaussian weights for kernel radius R = 1..maxR (sigma = R/3),
// each 2R+1 long, stored one after another; offset(R) = R*R - 1 (sum of 2k+1 for k < R, minus the R=0 slot).
struct GaussianTables {
    std::vector<float> w;
    explicit GaussianTables(int maxR) {
        for (int R = 1; R <= maxR; ++R) {
            const std::size_t first = w.size();
            double sum = 0.0;
            for (int k = -R; k <= R; ++k) {
                const double v = std::exp(-4.5 * double(k) * double(k) / (double(R) * double(R)));
                w.push_back(float(v));
                sum += v;
            }
            for (std::size_t i = first; i < w.size(); ++i) w[i] = float(double(w[i]) / sum);
        }
    }
    // The 2R+1 weights for radius R >= 1, centred: weights(R)[R] is the centre tap.
    const float* weights(int R) const { return w.data() + (std::size_t(R) * std::size_t(R) - 1); }
};

// One 1-D pass: dst = src blurred along x or y at the pixels with a kernel
// radius (radiusPx > 0); other pixels copied. Taps outside the image are left
// out and the remaining weights renormalised.
void blurPass(const Image<float>& src, Image<float>& dst, const Image<std::uint8_t>& radiusPx,
              const GaussianTables& tables, bool alongX) {
    const int W = src.width, H = src.height;
    const std::ptrdiff_t step = alongX ? 1 : W;
    forEachRow(H, [&](int y) {
        const float* srow = &src.pixels[std::size_t(y) * std::size_t(W)];
        const std::uint8_t* rrow = &radiusPx.pixels[std::size_t(y) * std::size_t(W)];
        float* drow = &dst.pixels[std::size_t(y) * std::size_t(W)];
        for (int x = 0; x < W; ++x) {
            const int R = rrow[x];
            if (R == 0) {
                drow[x] = srow[x];
                continue;
            }
            const float* w = tables.weights(R) + R;  // w[k] for k in [-R, R]
            const int pos = alongX ? x : y, size = alongX ? W : H;
            const int lo = std::max(-R, -pos), hi = std::min(R, size - 1 - pos);
            const float* p = srow + x;
            if (lo == -R && hi == R) {
                // The whole kernel (weights sum to 1): symmetric pairs into two
                // partial sums, halving the multiplies and the add chain.
                float s0 = w[0] * p[0], s1 = 0.0f;
                int k = 1;
                for (; k < R; k += 2) {
                    s0 += w[k] * (p[-k * step] + p[k * step]);
                    s1 += w[k + 1] * (p[-(k + 1) * step] + p[(k + 1) * step]);
                }
                if (k == R) s0 += w[k] * (p[-k * step] + p[k * step]);
                drow[x] = s0 + s1;
            } else {
                float sum = 0.0f, wsum = 0.0f;
                for (int k = lo; k <= hi; ++k) {
                    sum += w[k] * p[k * step];
                    wsum += w[k];
                }
                drow[x] = sum / wsum;
            }
        }
    });
}

void blurThickness(Image<float>& thickness, const Image<float>& rawDepth, const Camera& camera, float radius,
                   const ThicknessParams& params) {
    const int maxR = std::min(255, std::max(0, params.maxKernelPx));
    if (!(params.blurSigmaRadii > 0.0f) || maxR == 0) return;
    if (rawDepth.width != thickness.width || rawDepth.height != thickness.height) return;
    const GaussianTables tables(maxR);
    // Kernel radius (3 sigma) per pixel, once for both passes; 0 = no fluid, not blurred.
    const float worldRadiusM = 3.0f * params.blurSigmaRadii * radius;
    const float f = camera.focalPx();
    Image<std::uint8_t> radiusPx(thickness.width, thickness.height);
    forEachRow(thickness.height, [&](int y) {
        for (int x = 0; x < thickness.width; ++x) {
            const float z = rawDepth.at(x, y);
            radiusPx.at(x, y) = std::uint8_t(isFluid(z) ? projectedRadiusPx(worldRadiusM, f, z, maxR) : 0);
        }
    });
    Image<float> tmp(thickness.width, thickness.height);
    blurPass(thickness, tmp, radiusPx, tables, true);
    blurPass(tmp, thickness, radiusPx, tables, false);
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
