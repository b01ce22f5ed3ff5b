// CPU velocity whitening map, docs/pipeline.md#noise-and-foam (Cords & Staadt
// 2008, "Instant Liquids" §4: "particle velocities are projected into
// screen-space ... resulting in the velocity map"; the colour is shifted to
// white by it). Instant Liquids draws the velocity of the nearest particle;
// here, so that the map is smooth like the surface it tints, the particles near
// the surface (the noise's sprites, surface_sprites.cpp) splat their whiteness
// with the sprite's Gaussian and the map is the weighted mean. Fixed-point
// sums: the same bits for any thread count, and as the GL twin's atomics.
#include "cpu/velocity_map.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <cstdint>

#include <tbb/parallel_for.h>

#include "cpu/filter_util.h"
#include "cpu/surface_sprites.h"
#include "shared/velocity_map.h"

namespace meniscus::cpu {

Image<float> splatWhitening(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                            const Image<float>& depth, std::span<const float> whiteness, const WhiteningParams& p) {
    const int W = camera.width, H = camera.height;
    Image<float> out(W, H, 0.0f);
    if (depth.width != W || depth.height != H) return out;
    const SurfaceSprites sprites =
        findSurfaceSprites(camera, positionsWorld, radius, depth, {}, p.spriteRadii, p.depthFalloffRadii);
    constexpr int kTile = kSpriteTilePx;
    const std::size_t tiles = sprites.start.size() - 1;
    tbb::parallel_for(std::size_t(0), tiles, [&](std::size_t t) {
        if (sprites.start[t] == sprites.start[t + 1]) return;
        const glm::ivec4 tile = spriteTileRect(sprites, t, W, H);
        std::uint32_t white[kTile * kTile] = {}, norm[kTile * kTile] = {};
        for (std::uint32_t k = sprites.start[t]; k < sprites.start[t + 1]; ++k) {
            const std::uint32_t i = sprites.items[k];
            const shared::NoiseSprite& s = sprites.sprite[i];
            const float wi = i < whiteness.size() ? whiteness[i] : 0.0f;
            for (int y = std::max(tile.y, s.rect.y); y < std::min(tile.w, s.rect.w); ++y)
                for (int x = std::max(tile.x, s.rect.x); x < std::min(tile.z, s.rect.z); ++x) {
                    int a, b;
                    shared::whiteningContribution(s, x, y, sprites.weight[i], wi, p.sigma, a, b);
                    const int k2 = (y - tile.y) * kTile + (x - tile.x);
                    white[k2] += std::uint32_t(a);
                    norm[k2] += std::uint32_t(b);
                }
        }
        for (int y = tile.y; y < tile.w; ++y)
            for (int x = tile.x; x < tile.z; ++x) {
                const int k2 = (y - tile.y) * kTile + (x - tile.x);
                if (isFluid(depth.at(x, y)))
                    out.at(x, y) = shared::whiteningFromFixed(std::int32_t(white[k2]), std::int32_t(norm[k2]));
            }
    });
    return out;
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runWhitening(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    c.scalarOut(io.at.whitening) =
        splatWhitening(s.camera, c.positions(), s.radius, c.scalar(io.at.depth), s.whiteness, s.whitening);
}

}  // namespace

extern const StageDriver kWhiteningStage = {nullptr, runWhitening};

}  // namespace meniscus::cpu
