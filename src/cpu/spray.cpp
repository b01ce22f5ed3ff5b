// CPU spray drops, docs/pipeline.md#classification, docs/pipeline.md#noise-and-foam
// (the NVIDIA SSFR patent draws the particles that left the body of water as spray
// particles instead of surface). Each drop is projected with its velocity
// (sprayDrop: a capsule along its path over the exposure), binned into screen
// tiles, and its optical depth summed per pixel in fixed point where it is in front
// of the fluid and the scene; the cover 1 - exp(-sum) of lit drop colour is laid
// over the image. The sums are exact, so the order of the drops does not matter
// (the GL twin adds them with atomics): order-independent compositing is right here
// because all drops share one colour.
#include "cpu/spray.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <cstdint>
#include <vector>

#include <tbb/parallel_for.h>

#include "cpu/surface_sprites.h"
#include "shared/spray.h"
#include "shared/studio.h"

namespace meniscus::cpu {

Image<float> drawSpray(const Camera& camera, std::span<const glm::vec3> positionsWorld,
                       std::span<const glm::vec3> velocitiesWorld, float radius, const Image<float>& depth,
                       const Image<float>* sceneDepth, const SprayParams& p, const glm::vec3& lightDirWorld,
                       Image<glm::vec4>& color, const shared::EnvironmentMap& environment) {
    const int W = camera.width, H = camera.height;
    Image<float> cover(W, H, 0.0f);
    if (depth.width != W || depth.height != H || color.width != W || color.height != H) return cover;
    const bool hasScene = sceneDepth && sceneDepth->width == W && sceneDepth->height == H;
    const std::size_t n = positionsWorld.size();
    const glm::vec3 right = camera.right(), up = camera.trueUp(), back = camera.back(), eye = camera.eye;
    const float f = camera.focalPx(), sizeM = p.sizeRadii * radius;

    // The drops on screen (shared with the GL twin's host code).
    std::vector<shared::SprayDrop> drops(n);
    std::vector<glm::ivec4> rects(n);
    std::vector<std::uint8_t> on(n, 0);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        const glm::vec3 v = i < velocitiesWorld.size() ? velocitiesWorld[i] : glm::vec3(0.0f);
        if (!shared::sprayDropOfWorld(positionsWorld[i], v, eye, right, up, back, f, W, H, camera.nearM, sizeM,
                                      p.streakSeconds, p.opacity, drops[i]))
            return;
        rects[i] = drops[i].rect;
        on[i] = rects[i].x < rects[i].z && rects[i].y < rects[i].w;
    });
    SurfaceSprites tiles;  // only its tile grid and bins
    tiles.tilesX = (W + kSpriteTilePx - 1) / kSpriteTilePx;
    tiles.tilesY = (H + kSpriteTilePx - 1) / kSpriteTilePx;
    binIntoTiles(rects, on, tiles.tilesX, tiles.tilesY, tiles.start, tiles.items);

    const glm::vec3 lit = shared::sprayLight(lightDirWorld, back, environment);
    const std::size_t count = tiles.start.size() - 1;
    tbb::parallel_for(std::size_t(0), count, [&](std::size_t t) {
        if (tiles.start[t] == tiles.start[t + 1]) return;
        const glm::ivec4 r = spriteTileRect(tiles, t, W, H);
        std::uint32_t sum[kSpriteTilePx * kSpriteTilePx] = {};
        for (std::uint32_t k = tiles.start[t]; k < tiles.start[t + 1]; ++k) {
            const shared::SprayDrop& d = drops[tiles.items[k]];
            for (int y = std::max(r.y, d.rect.y); y < std::min(r.w, d.rect.w); ++y)
                for (int x = std::max(r.x, d.rect.x); x < std::min(r.z, d.rect.z); ++x) {
                    // Hidden behind the fluid or the scene (+inf where none).
                    if (!(d.z < depth.at(x, y)) || (hasScene && !(d.z < sceneDepth->at(x, y)))) continue;
                    sum[(y - r.y) * kSpriteTilePx + (x - r.x)] += std::uint32_t(shared::sprayContribution(d, x, y));
                }
        }
        for (int y = r.y; y < r.w; ++y)
            for (int x = r.x; x < r.z; ++x) {
                const std::int32_t s = std::int32_t(sum[(y - r.y) * kSpriteTilePx + (x - r.x)]);
                if (s <= 0) continue;
                const float c = shared::sprayCover(s);
                glm::vec4& px = color.at(x, y);
                const glm::vec3 rgb = shared::sprayOver(glm::vec3(px), c, p.color, lit);
                px = glm::vec4(rgb, shared::sprayAlphaOver(px.a, c));
                cover.at(x, y) = c;
            }
    });
    return cover;
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// Drawn over the colour in place (a copy of the scene when the slot names the
// cached scene: the cache is never painted over).
void runSpray(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    Image<glm::vec4>& color = c.colorToPaint(io.at.color);
    c.scalarOut(io.at.spray) = drawSpray(s.camera, s.sprayPositions, s.sprayVelocities, s.radius,
                                         c.scalar(io.at.depth), &c.scalar(io.at.sceneDepth), s.spray,
                                         s.shading.lightDirWorld, color, s.environment);
}

}  // namespace

extern const StageDriver kSprayStage = {nullptr, runSpray};

}  // namespace meniscus::cpu
