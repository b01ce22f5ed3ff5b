// CPU thickness stage, docs/pipeline.md#thickness. The fluid thickness seen
// through a pixel is the summed length of its ray inside the particle spheres
// (van der Laan et al. 2009, US 8,947,430 eq. 13 accumulate per-sprite
// thickness additively; here the chord is exact ray-sphere instead of a sprite
// profile), clipped to the part in front of the opaque scene and beyond the
// near plane. Spheres of radius r at spacing s fill only 4/3 pi r^3 / s^3 of
// the space, so the sum is scaled by w = s^3 / (4/3 pi r^3): a block at rest
// spacing then reads its true depth on average.
//
// The chords come from the same tiled binning and tile pass as the depth splat
// (splat.cpp), summed per pixel in fixed point (shared/splat_chords.h), so the
// result depends neither on the thread count nor on how the particles are
// ordered or split. The stage comes in two halves for sort-last rendering
// (meniscus/sort_last.h): splatPartial (splat.cpp) leaves the depth and the
// integer sums, which processes can combine exactly, and resolveThickness
// below turns a (combined) partial into metres: the weight, the blur with the
// combined depth and, on a coarser grid, the upsampling onto its fluid pixels.
//
// Optional blur (thesis §4.1.3): a separable Gaussian whose sigma is constant
// in world space (blurSigmaRadii * r, projected with the raw fluid depth at the
// centre pixel). Only fluid pixels are written, so thickness does not bleed into
// the background; their kernels do gather the zeros just outside the fluid,
// which thins the silhouettes smoothly as intended. The kernel radius is the
// whole number of pixels R = ceil(3 sigma_px) (capped), and the weights use
// sigma = R/3 from a table per R: sigma is rounded up by at most 1/3 px, and no
// exp is evaluated per pixel. Kernel radii are capped at min(maxKernelPx, 255)
// (shared::thicknessBlurCapPx).
//
// Lower resolution (docs/pipeline.md#thickness allows it;
// params.resolutionDivisor): the chords through the centres of d x d pixel
// blocks, blurred on that grid, upsampled bilinearly. The thickness only drives
// absorption and the refraction offset, both low-frequency after the blur,
// while the chords and the blur are most of this stage's time at full
// resolution.
#include "cpu/thickness.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cpu/filter_separable.h"  // KernelTable, the vector helpers, transpose
#include "cpu/filter_util.h"
#include "cpu/splat.h"
#include "shared/splat_chords.h"
#include "shared/thickness.h"

namespace meniscus::cpu {

namespace {

using detail::FloatV;
using detail::kLanes;

// One 1-D pass over pixels [begin, end) of a line of `len` pixels: out[i] =
// in[i] blurred with the Gaussian of radius rad[i] (table row rad[i], sigma =
// rad[i] / 3), or copied where rad[i] = 0. `in` holds the line at [0, len) and
// table.padPx() zeros on both sides, so the taps run in whole groups of kLanes
// (the table rows are zero past the radius) without bounds checks. Taps off
// the image are left out and the remaining weights renormalised.
void blurLine(const float* in, const std::uint8_t* rad, float* out, int begin, int end, int len,
              const KernelTable& table) {
    for (int i = begin; i < end; ++i) {
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

void blurThickness(Image<float>& thickness, const Image<float>& rawDepth, float f, float radius,
                   const ThicknessParams& params) {
    const int maxR = shared::thicknessBlurCapPx(params.maxKernelPx);
    if (!(params.blurSigmaRadii > 0.0f) || maxR == 0) return;
    const int W = thickness.width, H = thickness.height;
    if (rawDepth.width != W || rawDepth.height != H || W <= 0 || H <= 0) return;
    const KernelTable table = KernelTable::gaussian(maxR);
    const int pad = table.padPx();
    // Kernel radius (3 sigma) per pixel, once for both passes; 0 = no fluid, not blurred.
    const float worldRadiusM = 3.0f * params.blurSigmaRadii * radius;
    // As projectedRadiusPx (ceil(worldM f / z) in [0, maxR]; +inf depth gives
    // 0), kLanes at a time: on baseline x86-64 std::ceil is a library call.
    const float kPxDepth = worldRadiusM * f;
    Image<std::uint8_t> radiusPx(W, H);
    forEachRow(H, [&](int y) {
        const float* z = &rawDepth.pixels[std::size_t(y) * W];
        std::uint8_t* out = &radiusPx.pixels[std::size_t(y) * W];
        int x = 0;
        for (; x + kLanes <= W; x += kLanes) {
            FloatV px = kPxDepth / detail::loadV(z + x);
            px = detail::selectV(px > 0.0f, px);  // also NaN -> 0
            const detail::IntV below = px < float(maxR);
            px = detail::selectV(below, px) + detail::selectV(~below, FloatV{} + float(maxR));
            const detail::IntV i = __builtin_convertvector(px, detail::IntV);  // px >= 0: trunc = floor
            const detail::IntV up = __builtin_convertvector(i, FloatV) < px;   // -1 where px is not whole
            for (int l = 0; l < kLanes; ++l) out[x + l] = std::uint8_t(i[l] - up[l]);
        }
        for (; x < W; ++x) out[x] = std::uint8_t(isFluid(z[x]) ? projectedRadiusPx(worldRadiusM, f, z[x], maxR) : 0);
    });
    Image<float> tmp(W, H);
    // Only the span of each line that holds fluid is filtered: the rest keeps
    // its value through both passes (about half the image is never touched).
    // x pass: thickness -> tmp, through a zero-padded copy of each row.
    tbb::parallel_for(tbb::blocked_range<int>(0, H, 4), [&](const tbb::blocked_range<int>& rows) {
        std::vector<float> line(std::size_t(W + 2 * pad), 0.0f);
        for (int y = rows.begin(); y < rows.end(); ++y) {
            const std::size_t o = std::size_t(y) * W;
            const std::uint8_t* rad = radiusPx.pixels.data() + o;
            int first = 0, last = W - 1;
            while (first < W && rad[first] == 0) ++first;
            while (last > first && rad[last] == 0) --last;
            const float* src = thickness.pixels.data() + o;
            float* dst = tmp.pixels.data() + o;
            if (first == W) {
                std::copy_n(src, W, dst);
                continue;
            }
            std::copy_n(src, W, line.data() + pad);
            std::copy_n(src, first, dst);
            std::copy(src + last + 1, src + W, dst + last + 1);
            blurLine(line.data() + pad, rad, dst, first, last + 1, W, table);
        }
    });
    // y pass: tmp -> thickness, columns gathered kColumnBlock at a time into
    // contiguous padded lines (row-wise reads, not one cache miss per tap).
    // Outside the fluid rows of a block tmp equals thickness already.
    constexpr int kBlock = detail::kColumnBlock;
    const int blocks = (W + kBlock - 1) / kBlock;
    tbb::parallel_for(tbb::blocked_range<int>(0, blocks, 1), [&](const tbb::blocked_range<int>& bs) {
        const std::size_t lineLen = std::size_t(H + 2 * pad);
        std::vector<float> lines(lineLen * kBlock, 0.0f), outs(std::size_t(H) * kBlock);
        std::vector<std::uint8_t> rads(std::size_t(H) * kBlock);
        for (int b = bs.begin(); b < bs.end(); ++b) {
            const int x0 = b * kBlock, nc = std::min(kBlock, W - x0);
            int first = H, last = -1;
            for (int y = 0; y < H; ++y) {
                const std::uint8_t* rad = &radiusPx.at(x0, y);
                std::uint8_t any = 0;
                for (int c = 0; c < nc; ++c) {
                    rads[std::size_t(c) * H + y] = rad[c];
                    any |= rad[c];
                }
                if (any) first = std::min(first, y), last = y;
            }
            if (last < 0) continue;
            // Taps reach maxR rows beyond the fluid rows; rows further away are never read.
            const int lo = std::max(0, first - maxR), hi = std::min(H, last + 1 + maxR);
            detail::transpose(&tmp.at(x0, lo), std::size_t(W), lines.data() + pad + lo, lineLen, hi - lo, nc,
                              [](float v) { return v; });
            for (int c = 0; c < nc; ++c)
                blurLine(lines.data() + c * lineLen + pad, rads.data() + std::size_t(c) * H,
                         outs.data() + std::size_t(c) * H, first, last + 1, H, table);
            detail::transpose(outs.data() + first, std::size_t(H), &thickness.at(x0, first), std::size_t(W), nc,
                              last + 1 - first, [](float v) { return v; });
        }
    });
}

// The fixed-point chord sums in metres times the calibration weight `weight`
// (shared::chordSumToMetres, as shaders/splat_resolve.comp).
Image<float> chordsToMetres(const Image<std::uint32_t>& chords, float radius, float weight) {
    Image<float> out(chords.width, chords.height);
    forEachRow(chords.height, [&](int y) {
        const std::size_t row = std::size_t(y) * std::size_t(chords.width);
        for (std::size_t i = row; i < row + std::size_t(chords.width); ++i)
            out.pixels[i] = shared::chordSumToMetres(chords.pixels[i], radius, weight);
    });
    return out;
}

// Thickness on the grid of one pixel per d x d block (d > 1): `low`, the
// chords through the block centres in metres, blurred there (sigma projected
// with the nearest fluid depth of the block and focal length f / d, so it is
// the same world length), then bilinearly upsampled onto the full-resolution
// fluid pixels (0 elsewhere). Chords and blur cost ~1/d^2 and ~1/d^3 of full
// resolution; the thickness only feeds absorption and the refraction offset,
// which are smooth, so the detail lost is below what the blur removes anyway.
Image<float> lowResThickness(const Camera& camera, Image<float> low, float radius, const ThicknessParams& params,
                             const Image<float>& rawDepth, int d) {
    const int W = camera.width, H = camera.height;
    const int w = (W + d - 1) / d, h = (H + d - 1) / d;
    Image<float> out(W, H, 0.0f);
    if (rawDepth.width != W || rawDepth.height != H) return out;
    // The nearest fluid depth of each block (+inf when it has none): the min
    // over the block's rows, then over its columns.
    Image<float> lowDepth(w, h);
    forEachRow(h, [&](int j) {
        std::vector<float> rowMin(rawDepth.pixels.begin() + std::size_t(d) * j * W,
                                  rawDepth.pixels.begin() + (std::size_t(d) * j + 1) * W);
        for (int y = d * j + 1; y < std::min(H, d * j + d); ++y) {
            const float* z = &rawDepth.pixels[std::size_t(y) * W];
            for (int x = 0; x < W; ++x) rowMin[x] = std::min(rowMin[x], z[x]);
        }
        for (int i = 0; i < w; ++i) {
            float z = rowMin[d * i];
            for (int x = d * i + 1; x < std::min(W, d * i + d); ++x) z = std::min(z, rowMin[x]);
            lowDepth.at(i, j) = z;
        }
    });
    blurThickness(low, lowDepth, camera.focalPx() / float(d), radius, params);
    // Bilinear: full pixel x samples the low grid at (x + 1/2) / d - 1/2,
    // clamped at the border. Taps and weights per column, once.
    struct Tap {
        int i0, i1;
        float f;
    };
    auto taps = [d](int n, int lowN) {
        std::vector<Tap> t(static_cast<std::size_t>(n));
        for (int x = 0; x < n; ++x) {
            const float u = std::clamp((float(x) + 0.5f) / float(d) - 0.5f, 0.0f, float(lowN - 1));
            const int i0 = std::min(int(u), lowN - 1);
            t[std::size_t(x)] = {i0, std::min(i0 + 1, lowN - 1), u - float(i0)};
        }
        return t;
    };
    const std::vector<Tap> tx = taps(W, w), ty = taps(H, h);
    forEachRow(H, [&](int y) {
        const float* z = &rawDepth.pixels[std::size_t(y) * W];
        int first = 0, last = W - 1;  // only the span of the row that holds fluid
        while (first < W && !isFluid(z[first])) ++first;
        while (last > first && !isFluid(z[last])) --last;
        if (first == W) return;
        // Interpolate between the two low rows first, then along the row.
        const Tap& v = ty[std::size_t(y)];
        const float* r0 = &low.pixels[std::size_t(v.i0) * w];
        const float* r1 = &low.pixels[std::size_t(v.i1) * w];
        std::vector<float> row(static_cast<std::size_t>(w));
        for (int i = tx[first].i0; i <= tx[last].i1; ++i) row[i] = r0[i] + v.f * (r1[i] - r0[i]);
        float* o = &out.pixels[std::size_t(y) * W];
        for (int x = first; x <= last; ++x) {
            const Tap& u = tx[std::size_t(x)];
            const float t = row[u.i0] + u.f * (row[u.i1] - row[u.i0]);
            o[x] = isFluid(z[x]) ? t : 0.0f;
        }
    });
    return out;
}

// The second half of the stage: chords on the thickness grid into metres,
// blurred, upsampled at d > 1; rawDepth is the (combined) splat depth.
Image<float> resolve(const Camera& camera, const Image<std::uint32_t>& chords, const Image<float>& rawDepth,
                     float radius, const ThicknessParams& params) {
    const int W = camera.width, H = camera.height, d = shared::thicknessDivisor(params.resolutionDivisor);
    if (chords.width != (W + d - 1) / d || chords.height != (H + d - 1) / d) return Image<float>(W, H, 0.0f);
    Image<float> thickness = chordsToMetres(chords, radius, shared::thicknessWeight(radius, params));
    if (d > 1) return lowResThickness(camera, std::move(thickness), radius, params, rawDepth, d);
    blurThickness(thickness, rawDepth, camera.focalPx(), radius, params);
    return thickness;
}

}  // namespace

Image<float> computeThickness(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                              const ThicknessParams& params, const Image<float>* sceneDepth,
                              const Image<float>& rawDepth, std::span<const EllipsoidShape> shapes) {
    const SplatBins bins = binParticles(camera, positionsWorld, radius, shapes);
    const int d = shared::thicknessDivisor(params.resolutionDivisor);
    Image<std::uint32_t> chords((camera.width + d - 1) / d, (camera.height + d - 1) / d);
    splatChordsLowRes(camera, bins, radius, sceneDepth, d, chords);
    return resolve(camera, chords, rawDepth, radius, params);
}

Image<float> resolveThickness(const Camera& camera, const SplatPartial& partial, float radius,
                              const ThicknessParams& params) {
    return resolve(camera, partial.chords, partial.depth, radius, params);
}

DepthAndThickness splatDepthAndThickness(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                                         const ThicknessParams& params, const Image<float>* sceneDepth,
                                         std::span<const EllipsoidShape> shapes) {
    SplatPartial partial = splatPartial(camera, positionsWorld, radius, params, sceneDepth, shapes);
    Image<float> thickness = resolveThickness(camera, partial, radius, params);
    return {std::move(partial.depth), std::move(thickness)};
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runSplat(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    auto dt = splatDepthAndThickness(s.camera, c.positions(), s.radius, s.thickness, &c.scalar(io.at.sceneDepth),
                                     s.shapes);
    c.scalarOut(io.at.raw) = std::move(dt.depth);
    c.scalarOut(io.at.thickness) = std::move(dt.thickness);
}

// Sort-last: this process's share of the whole frame (FrameSettings::splatRange) into *io.partial.
void runSplatPartial(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    std::span<const glm::vec3> positions = c.positions();
    std::span<const EllipsoidShape> shapes = s.shapes;
    if (const auto& r = s.splatRange) {
        positions = positions.subspan(r->begin, r->end - r->begin);
        if (!shapes.empty()) shapes = shapes.subspan(r->begin, r->end - r->begin);
    }
    *io.partial = splatPartial(s.camera, positions, s.radius, s.thickness, &c.scalar(io.at.sceneDepth), shapes);
}

// Sort-last: the combined partial resolved into the raw depth and thickness.
void runResolveSplat(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    c.scalarOut(io.at.thickness) = resolveThickness(s.camera, *io.partial, s.radius, s.thickness);
    c.scalarOut(io.at.raw) = std::move(io.partial->depth);
}

}  // namespace

extern const StageDriver kSplatStage = {nullptr, runSplat};
extern const StageDriver kSplatPartialStage = {nullptr, runSplatPartial};
extern const StageDriver kResolveSplatStage = {nullptr, runResolveSplat};

}  // namespace meniscus::cpu
