// CPU surface noise, SPEC §3.7 (van der Laan, Green & Sainz, US 8,947,430,
// eqs. 14-17): each particle whose front lies near the smoothed surface
// splats a Gaussian sprite of fractal Perlin noise seeded by its id; the sum
// N(x, y) bumps the normals and, in the shading, tints foam.
//
// Parallel scheme: one pass over the particles finds those whose weight
// counts (their depth below the surface sampled at their projected centre)
// and their sprites, which are then binned into fixed screen tiles and summed
// one tile per task. The sums are integers (fixed point), so the image does
// not depend on the order or the thread count, and the GL twin, adding with
// atomics in any order, gets the same bits.
#include "cpu/surface_noise.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/parallel_for.h>

#include "cpu/filter_util.h"
#include "shared/surface_noise.h"

namespace meniscus::cpu {

namespace {
constexpr int kTile = 32;

struct Sprite {
    shared::NoiseSprite sprite;
    float weight;
    float idz;
};

// Adds sprite s's contributions to the n <= kTile pixels (x0 .. x0 + n - 1, y)
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
    float sx[kTile], sy[kTile], g[kTile], acc[kTile];
    std::uint32_t inside[kTile];  // all ones inside the disc, 0 outside or past n
    for (int i = 0; i < m; ++i) {
        const glm::vec2 o = shared::noiseSpriteOffset(s.sprite, x0 + i, y);
        const float s2 = o.x * o.x + o.y * o.y;
        inside[i] = (s2 < 1.0f) & (i < n) ? ~0u : 0u;
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
    std::uint32_t add[kTile];
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
    const std::size_t n = positionsWorld.size();
    const glm::vec3 right = camera.right(), up = camera.trueUp(), back = camera.back(), eye = camera.eye;
    const float f = camera.focalPx();
    const float spriteM = p.spriteRadii * radius, falloffM = p.depthFalloffRadii * radius;

    // 1. Each particle's sprite and weight (independent per particle).
    std::vector<Sprite> all(n);
    std::vector<std::uint8_t> on(n, 0);
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
            all[i] = {s, w, i < idz.size() ? idz[i] : 0.0f};
            on[i] = 1;
        }
    });

    // 2. The counted sprites binned per tile (any order would do: sums are exact).
    const int tilesX = (W + kTile - 1) / kTile, tilesY = (H + kTile - 1) / kTile;
    const std::size_t tiles = std::size_t(tilesX) * std::size_t(tilesY);
    std::vector<std::uint32_t> start(tiles + 1, 0), items;
    auto forTiles = [&](const glm::ivec4& r, auto&& fn) {
        for (int ty = r.y / kTile; ty <= (r.w - 1) / kTile; ++ty)
            for (int tx = r.x / kTile; tx <= (r.z - 1) / kTile; ++tx) fn(std::size_t(ty) * tilesX + tx);
    };
    for (std::size_t i = 0; i < n; ++i)
        if (on[i]) forTiles(all[i].sprite.rect, [&](std::size_t t) { ++start[t + 1]; });
    for (std::size_t t = 0; t < tiles; ++t) start[t + 1] += start[t];
    items.resize(start[tiles]);
    {
        std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
        for (std::size_t i = 0; i < n; ++i)
            if (on[i]) forTiles(all[i].sprite.rect, [&](std::size_t t) { items[next[t]++] = std::uint32_t(i); });
    }

    // 3. One tile per task: 32-bit wrap-around sums (the GL atomics' arithmetic).
    tbb::parallel_for(std::size_t(0), tiles, [&](std::size_t t) {
        if (start[t] == start[t + 1]) return;
        const int x0 = int(t % std::size_t(tilesX)) * kTile, y0 = int(t / std::size_t(tilesX)) * kTile;
        const int x1 = std::min(W, x0 + kTile), y1 = std::min(H, y0 + kTile);
        std::uint32_t sum[kTile * kTile] = {};
        for (std::uint32_t k = start[t]; k < start[t + 1]; ++k) {
            const Sprite& s = all[items[k]];
            const int ax = std::max(x0, s.sprite.rect.x), bx = std::min(x1, s.sprite.rect.z);
            const int ay = std::max(y0, s.sprite.rect.y), by = std::min(y1, s.sprite.rect.w);
            for (int y = ay; y < by; ++y) addSpriteSpan(s, ax, bx - ax, y, p, &sum[(y - y0) * kTile + (ax - x0)]);
        }
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x)
                if (isFluid(depth.at(x, y)))
                    out.at(x, y) = shared::noiseFromFixed(std::int32_t(sum[(y - y0) * kTile + (x - x0)]));
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

}  // namespace meniscus::cpu
