// CPU surface noise, docs/pipeline.md#noise-and-foam (van der Laan, Green &
// Sainz, US 8,947,430, eqs. 14-17): each particle whose front lies near the
// smoothed surface splats a Gaussian sprite of fractal Perlin noise seeded by
// its id; the sum N(x, y) bumps the normals and, in the shading, tints foam.
//
// Parallel scheme: the sprites of the particles whose weight counts (their
// depth below the surface sampled at their projected centre), binned into
// fixed screen tiles (surface_sprites.cpp), are summed one tile per task. The sums are integers (fixed point), so the image does
// not depend on the order or the thread count, and the GL twin, adding with
// atomics in any order, gets the same bits.
#include "cpu/surface_noise.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/parallel_for.h>

#include "cpu/filter_util.h"
#include "cpu/surface_sprites.h"
#include "shared/surface_noise.h"

namespace meniscus::cpu {

namespace {
constexpr int kSpriteTile = kSpriteTilePx;

struct Sprite {
    shared::NoiseSprite sprite;
    float weight;
    float idz;
};

// Adds sprite s's contributions to the n <= kSpriteTile pixels (x0 .. x0 + n - 1, y)
// into sum: shared::noiseContribution per pixel, with the fractal's octaves
// outside the loop over pixels so that the loops vectorise (AVX2 clone: eight
// pixels at a time; no FMA in either clone, so both give the same bits).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void addSpriteSpan(const Sprite& s, int x0, int n, int y, const NoiseParams& p, std::uint32_t* sum) {
    // Whole groups of eight lanes (a sprite row is ~10 pixels: a scalar
    // remainder would cost as much as the vector part); the lanes past n are
    // computed and dropped.
    const int m = (n + 7) & ~7;
    float sx[kSpriteTile], sy[kSpriteTile], g[kSpriteTile], acc[kSpriteTile];
    std::uint32_t inside[kSpriteTile];  // all ones inside the disc, 0 outside or past n
    for (int i = 0; i < m; ++i) {
        const glm::vec2 o = shared::noiseSpriteOffset(s.sprite, x0 + i, y);
        const float s2 = o.x * o.x + o.y * o.y;
        inside[i] = ((s2 < 1.0f) & (i < n)) ? ~0u : 0u;
        sx[i] = o.x * p.frequency;
        sy[i] = o.y * p.frequency;
        g[i] = shared::noiseSpriteGaussian(s2, p.sigma);
        acc[i] = 0.0f;
    }
    // fractalNoise3's loop, octave by octave.
    float norm = 0.0f, amplitude = 1.0f, frequency = 1.0f;
    for (int k = 0; k < p.octaves; ++k) {
        for (int i = 0; i < m; ++i)
            acc[i] = acc[i] + shared::fractalNoiseTerm(glm::vec3(sx[i], sy[i], s.idz), k, frequency, amplitude);
        norm = norm + amplitude;
        amplitude = amplitude * p.gain;
        frequency = frequency * p.lacunarity;
    }
    const float normOr1 = norm > 0.0f ? norm : 1.0f, keep = norm > 0.0f ? 1.0f : 0.0f;
    std::uint32_t add[kSpriteTile];
    for (int i = 0; i < m; ++i) {
        const float noise = (acc[i] * keep) / normOr1;  // fractalNoise3's sum / norm (0 without octaves)
        add[i] = std::uint32_t(shared::noiseToFixed(s.weight, g[i], noise)) & inside[i];
    }
    for (int i = 0; i < n; ++i) sum[i] += add[i];
}
}  // namespace

Image<float> splatNoise(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                        const Image<float>& depth, std::span<const float> idz, std::span<const float> amplitude,
                        const NoiseParams& p) {
    const int W = camera.width, H = camera.height;
    Image<float> out(W, H, 0.0f);
    if (depth.width != W || depth.height != H) return out;
    const SurfaceSprites sprites =
        findSurfaceSprites(camera, positionsWorld, radius, depth, amplitude, p.spriteRadii, p.depthFalloffRadii);
    // One tile per task: 32-bit wrap-around sums (the GL atomics' arithmetic).
    const std::size_t tiles = sprites.start.size() - 1;
    tbb::parallel_for(std::size_t(0), tiles, [&](std::size_t t) {
        if (sprites.start[t] == sprites.start[t + 1]) return;
        const glm::ivec4 tile = spriteTileRect(sprites, t, W, H);
        const int x0 = tile.x, y0 = tile.y, x1 = tile.z, y1 = tile.w;
        std::uint32_t sum[kSpriteTile * kSpriteTile] = {};
        for (std::uint32_t k = sprites.start[t]; k < sprites.start[t + 1]; ++k) {
            const std::uint32_t i = sprites.items[k];
            const Sprite s{sprites.sprite[i], sprites.weight[i], i < idz.size() ? idz[i] : 0.0f};
            const int ax = std::max(x0, s.sprite.rect.x), bx = std::min(x1, s.sprite.rect.z);
            const int ay = std::max(y0, s.sprite.rect.y), by = std::min(y1, s.sprite.rect.w);
            for (int y = ay; y < by; ++y) addSpriteSpan(s, ax, bx - ax, y, p, &sum[(y - y0) * kSpriteTile + (ax - x0)]);
        }
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x)
                if (isFluid(depth.at(x, y)))
                    out.at(x, y) = shared::noiseFromFixed(std::int32_t(sum[(y - y0) * kSpriteTile + (x - x0)]));
    });
    return out;
}

void bumpNormals(const Camera& camera, float radius, const Image<float>& depth, const Image<float>& noise,
                 const NoiseParams& p, Image<glm::vec3>& normals) {
    const int W = depth.width, H = depth.height;
    if (noise.width != W || noise.height != H || normals.width != W || normals.height != H) return;
    const float jump = defaults::kDepthJumpRadii * radius;
    const float spriteF = p.spriteRadii * radius * camera.focalPx();
    forEachRow(H, [&](int y) {
        for (int x = 0; x < W; ++x) {
            const float z = depth.at(x, y);
            if (!isFluid(z)) continue;
            // A neighbour counts when it is fluid of the same surface.
            auto same = [&](int xn, int yn) {
                return xn >= 0 && xn < W && yn >= 0 && yn < H && std::fabs(depth.at(xn, yn) - z) <= jump;
            };
            auto at = [&](int xn, int yn) { return same(xn, yn) ? noise.at(xn, yn) : 0.0f; };
            const float n0 = noise.at(x, y);
            const float dx = shared::noiseDerivative(at(x - 1, y), n0, at(x + 1, y), same(x - 1, y), same(x + 1, y));
            const float dy = shared::noiseDerivative(at(x, y - 1), n0, at(x, y + 1), same(x, y - 1), same(x, y + 1));
            normals.at(x, y) = shared::noisePerturbedNormal(normals.at(x, y), dx, dy, spriteF / z, p.bump);
        }
    });
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// The noise N of the particles near the surface, and the normals bumped by its gradient in place.
void runNoise(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    c.scalarOut(io.at.noise) = splatNoise(s.camera, c.positions(), s.radius, c.scalar(io.at.depth), s.noiseIdz,
                                          s.noiseAmplitude, s.noise);
    bumpNormals(s.camera, s.radius, c.scalar(io.at.depth), c.scalar(io.at.noise), s.noise, c.vec3(io.at.normal));
}

}  // namespace

extern const StageDriver kNoiseStage = {nullptr, runNoise};

}  // namespace meniscus::cpu
