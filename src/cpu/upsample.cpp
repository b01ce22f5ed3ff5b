// CPU reduced-resolution processing: see upsample.h and src/shared/upsample.h.
#include "cpu/upsample.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <limits>
#include <vector>

#include <tbb/parallel_for.h>

#include "shared/fluids.h"
#include "shared/upsample.h"
#include "cpu/no_depth.h"

namespace meniscus::cpu {

namespace {
}  // namespace

Image<float> reduceSceneDepth(const Image<float>& full, int lowW, int lowH, int d) {
    Image<float> out(lowW, lowH, kInf);
    const int W = full.width, H = full.height;
    if (W <= 0 || H <= 0) return out;
    tbb::parallel_for(0, lowH, [&](int j) {
        const glm::ivec2 ys = shared::lowPixelSpan(j, H, lowH, d);
        for (int i = 0; i < lowW; ++i) {
            const glm::ivec2 xs = shared::lowPixelSpan(i, W, lowW, d);
            float z = 0.0f;
            for (int y = ys.x; y < ys.y; ++y)
                for (int x = xs.x; x < xs.y; ++x) z = std::max(z, full.at(x, y));
            out.at(i, j) = z;
        }
    });
    return out;
}

Upsampled upsampleSurface(const Image<float>& lowDepth, const Image<glm::vec3>& lowNormal,
                          const Image<float>& lowThickness, const Image<float>* lowNoise,
                          const Image<float>* sceneDepth, int W, int H, int d, float jumpM) {
    Upsampled out;
    out.depth = Image<float>(W, H, kInf);
    out.normal = Image<glm::vec3>(W, H, glm::vec3(0.0f));
    out.thickness = Image<float>(W, H, 0.0f);
    out.coverage = Image<float>(W, H, 0.0f);
    const bool noise = lowNoise != nullptr;
    if (noise) out.noise = Image<float>(W, H, 0.0f);
    const int lw = lowDepth.width, lh = lowDepth.height;
    if (W <= 0 || H <= 0 || lw <= 0 || lh <= 0) return out;
    const bool hides = sceneDepth && sceneDepth->width == W && sceneDepth->height == H;
    const bool hasNormal = lowNormal.width == lw && lowNormal.height == lh;
    const bool hasThickness = lowThickness.width == lw && lowThickness.height == lh;
    const bool hasNoise = noise && lowNoise->width == lw && lowNoise->height == lh;
    // The columns' taps and fractions, the same for every row.
    std::vector<glm::ivec2> colTaps(static_cast<std::size_t>(W));
    std::vector<float> colFrac(static_cast<std::size_t>(W));
    for (int x = 0; x < W; ++x)
        shared::upsampleTaps(shared::lowCoordinate(x, W, lw, d), lw, colTaps[std::size_t(x)], colFrac[std::size_t(x)]);
    tbb::parallel_for(0, H, [&](int y) {
        glm::ivec2 ty;
        float fy;
        shared::upsampleTaps(shared::lowCoordinate(y, H, lh, d), lh, ty, fy);
        const float* row0 = &lowDepth.at(0, ty.x);
        const float* row1 = &lowDepth.at(0, ty.y);
        for (int x = 0; x < W; ++x) {
            const glm::ivec2 tx = colTaps[std::size_t(x)];
            // Background under all four taps (most of a frame): nothing to do.
            if (!(row0[tx.x] < kInf) && !(row0[tx.y] < kInf) && !(row1[tx.x] < kInf) && !(row1[tx.y] < kInf)) continue;
            const glm::vec4 w = shared::upsampleWeights(colFrac[std::size_t(x)], fy);
            const glm::vec4 z(row0[tx.x], row0[tx.y], row1[tx.x], row1[tx.y]);
            const float c = shared::upsampleCoverage(z, w);
            out.coverage.at(x, y) = c;
            if (!shared::upsampleIsFluid(c)) continue;
            const glm::vec4 b = shared::upsampleBlendWeights(z, w, jumpM);
            const float sum = shared::upsampleWeightSum(b);
            const float depth = shared::upsampleDepth(z, b, sum);
            if (hides && !(depth < sceneDepth->at(x, y))) continue;
            out.depth.at(x, y) = depth;
            if (hasNormal)
                out.normal.at(x, y) =
                    shared::upsampleNormal(lowNormal.at(tx.x, ty.x), lowNormal.at(tx.y, ty.x),
                                           lowNormal.at(tx.x, ty.y), lowNormal.at(tx.y, ty.y), b);
            if (hasThickness)
                out.thickness.at(x, y) = shared::upsampleLinear(
                    glm::vec4(lowThickness.at(tx.x, ty.x), lowThickness.at(tx.y, ty.x), lowThickness.at(tx.x, ty.y),
                              lowThickness.at(tx.y, ty.y)),
                    b, sum);
            if (hasNoise)
                out.noise.at(x, y) = shared::upsampleLinear(
                    glm::vec4(lowNoise->at(tx.x, ty.x), lowNoise->at(tx.y, ty.x), lowNoise->at(tx.x, ty.y),
                              lowNoise->at(tx.y, ty.y)),
                    b, sum);
        }
    });
    return out;
}

void blendFluidEdges(const Image<float>& depth, const Image<float>& coverage, const Image<glm::vec4>& behind,
                     Image<glm::vec4>& color, Image<glm::vec4>* emission, Image<glm::vec4>* transmit) {
    const int W = color.width, H = color.height;
    for (const auto* img : {&depth, &coverage})
        if (img->width != W || img->height != H) return;
    if (behind.width != W || behind.height != H) return;
    const bool split = emission && transmit && emission->width == W && emission->height == H &&
                       transmit->width == W && transmit->height == H;
    tbb::parallel_for(0, H, [&](int y) {
        for (int x = 0; x < W; ++x) {
            if (!(depth.at(x, y) < kInf)) continue;
            const float c = coverage.at(x, y);
            color.at(x, y) = shared::upsampleEdgeBlend(color.at(x, y), behind.at(x, y), c);
            if (!split) continue;
            emission->at(x, y) = glm::vec4(shared::fluidEdgeEmission(glm::vec3(emission->at(x, y)), c), 1.0f);
            transmit->at(x, y) = glm::vec4(shared::fluidEdgeTransmittance(glm::vec3(transmit->at(x, y)), c), 0.0f);
        }
    });
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// The scene depth reduced to the current (low) camera's size.
void runReduceSceneDepth(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    c.scalarOut(Slot::LowSceneDepth) =
        reduceSceneDepth(c.scalar(io.at.sceneDepth), s.camera.width, s.camera.height, s.fluidDivisor);
}

// The low surface (the Low* slots) upsampled into the surface's full-size images.
void runUpsample(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    const bool noise = s.noise.enabled;
    Upsampled up = upsampleSurface(c.scalar(Slot::LowDepth), c.vec3(Slot::LowNormal), c.scalar(Slot::LowThickness),
                                   noise ? &c.scalar(Slot::LowNoise) : nullptr, &c.scalar(io.at.sceneDepth),
                                   s.camera.width, s.camera.height, s.fluidDivisor, s.upsampleJumpM);
    c.scalarOut(io.at.depth) = std::move(up.depth);
    c.vec3(io.at.normal) = std::move(up.normal);
    c.scalarOut(io.at.thickness) = std::move(up.thickness);
    if (noise) c.scalarOut(io.at.noise) = std::move(up.noise);
    c.scalarOut(io.at.coverage) = std::move(up.coverage);
}

void runFluidEdges(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const bool split = io.at.emission != Slot::None;
    blendFluidEdges(c.scalar(io.at.depth), c.scalar(io.at.coverage), c.color(io.at.sceneColor), c.colorOut(io.at.color),
                    split ? &c.colorOut(io.at.emission) : nullptr, split ? &c.colorOut(io.at.transmit) : nullptr);
}

}  // namespace

extern const StageDriver kReduceSceneDepthStage = {nullptr, runReduceSceneDepth};
extern const StageDriver kUpsampleStage = {nullptr, runUpsample};
extern const StageDriver kFluidEdgesStage = {nullptr, runFluidEdges};

}  // namespace meniscus::cpu
