// findSurfaceSprites (surface_sprites.h): one parallel pass over the particles
// for their sprites and weights, then a counting sort of the counted ones into
// fixed screen tiles (serial: a few tens of thousands of sprites, ~1 ms).
#include "cpu/surface_sprites.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace meniscus::cpu {

SurfaceSprites findSurfaceSprites(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                                  const Image<float>& depth, std::span<const float> amplitude, float spriteRadii,
                                  float falloffRadii) {
    const int W = camera.width, H = camera.height;
    constexpr int kTile = kSpriteTilePx;
    SurfaceSprites out;
    out.tilesX = (W + kTile - 1) / kTile;
    out.tilesY = (H + kTile - 1) / kTile;
    const std::size_t tiles = std::size_t(out.tilesX) * std::size_t(out.tilesY);
    out.start.assign(tiles + 1, 0);
    if (depth.width != W || depth.height != H) return out;
    const std::size_t n = positionsWorld.size();
    const glm::vec3 right = camera.right(), up = camera.trueUp(), back = camera.back(), eye = camera.eye;
    const float f = camera.focalPx();
    const float spriteM = spriteRadii * radius, falloffM = falloffRadii * radius;

    // 1. Each particle's sprite and weight (independent per particle). The
    // view-space centre is binParticles' (glm::dot's order), as on GL.
    out.sprite.resize(n);
    out.weight.assign(n, 0.0f);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            const glm::vec3 d = positionsWorld[i] - eye;
            const glm::vec3 c{glm::dot(d, right), glm::dot(d, up), glm::dot(d, back)};
            const float z = -c.z;
            if (!(z > camera.nearM)) continue;
            const shared::NoiseSprite s = shared::noiseSprite(c, f, W, H, spriteM);
            if (s.rect.x >= s.rect.z || s.rect.y >= s.rect.w) continue;
            const float fx = std::floor(s.centre.x), fy = std::floor(s.centre.y);
            if (!(fx >= 0.0f && fx < float(W) && fy >= 0.0f && fy < float(H))) continue;  // centre off screen
            const float a = amplitude.size() == n ? amplitude[i] : 1.0f;
            const float w = shared::noiseParticleWeight(z, depth.at(int(fx), int(fy)), radius, falloffM, a);
            if (!(w >= shared::kNoiseMinWeight)) continue;
            out.sprite[i] = s;
            out.weight[i] = w;
        }
    });

    // 2. The counted sprites binned per tile (the sums over them are exact, so
    // any order would do; particle order keeps it simple).
    std::vector<glm::ivec4> rects(n);
    std::vector<std::uint8_t> on(n);
    for (std::size_t i = 0; i < n; ++i) {
        rects[i] = out.sprite[i].rect;
        on[i] = out.weight[i] > 0.0f;
    }
    binIntoTiles(rects, on, out.tilesX, out.tilesY, out.start, out.items);
    return out;
}

void binIntoTiles(std::span<const glm::ivec4> rects, std::span<const std::uint8_t> on, int tilesX, int tilesY,
                  std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& items) {
    constexpr int kTile = kSpriteTilePx;
    const std::size_t tiles = std::size_t(tilesX) * std::size_t(tilesY);
    auto forTiles = [&](const glm::ivec4& r, auto&& fn) {
        for (int ty = r.y / kTile; ty <= (r.w - 1) / kTile; ++ty)
            for (int tx = r.x / kTile; tx <= (r.z - 1) / kTile; ++tx) fn(std::size_t(ty) * std::size_t(tilesX) + tx);
    };
    start.assign(tiles + 1, 0);
    for (std::size_t i = 0; i < rects.size(); ++i)
        if (on[i]) forTiles(rects[i], [&](std::size_t t) { ++start[t + 1]; });
    for (std::size_t t = 0; t < tiles; ++t) start[t + 1] += start[t];
    items.resize(start[tiles]);
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < rects.size(); ++i)
        if (on[i]) forTiles(rects[i], [&](std::size_t t) { items[next[t]++] = std::uint32_t(i); });
}

glm::ivec4 spriteTileRect(const SurfaceSprites& s, std::size_t t, int width, int height) {
    const int x0 = int(t % std::size_t(s.tilesX)) * kSpriteTilePx, y0 = int(t / std::size_t(s.tilesX)) * kSpriteTilePx;
    return {x0, y0, std::min(width, x0 + kSpriteTilePx), std::min(height, y0 + kSpriteTilePx)};
}

}  // namespace meniscus::cpu
