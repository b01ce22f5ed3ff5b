// CPU depth splat, SPEC §3.3. Each particle is a sphere of radius r; every pixel
// whose ray hits it gets the eye depth of the nearest intersection, and the
// minimum over particles wins. This is the exact, perspective-correct version of
// the point-sprite depth of van der Laan et al. 2009 (US 8,947,430) and Cords &
// Staadt 2008 ("Instant Liquids", §2.1; its eq. 2 gives the projected radius —
// here the exact projected bounding box is used instead).
//
// Parallel scheme: particles are binned into fixed screen tiles, then each tile
// is splatted by one task. A min is order-independent, so the result is the
// same for any thread count.
#include "splat.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

namespace meniscus::cpu {

namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kTile = 32;  // pixels
}  // namespace

PixelRect projectedSphereBounds(const Camera& camera, const glm::vec3& c, float r) {
    const float depth = -c.z;  // eye depth of the centre
    PixelRect full{0, 0, camera.width, camera.height};
    if (depth + r <= 0.0f) return {};      // wholly behind the eye
    if (depth - r <= 0.0f) return full;    // reaches the eye plane: unbounded projection
    // Tangent lines from the eye to the sphere's cross-section in the xz (resp.
    // yz) plane bound the projection exactly: the image-plane slope bounds are
    // (a*depth ± r*sqrt(a² + depth² - r²)) / (depth² - r²) for a = c.x or c.y.
    const float f = camera.focalPx();
    const float den = depth * depth - r * r;
    auto slopes = [&](float a) {
        const float root = r * std::sqrt(std::max(a * a + den, 0.0f));
        return glm::vec2((a * depth - root) / den, (a * depth + root) / den);
    };
    const glm::vec2 sx = slopes(c.x), sy = slopes(c.y);
    const float cx = 0.5f * float(camera.width), cy = 0.5f * float(camera.height);
    // Pixel centres are at +0.5: pixel i is inside when i + 0.5 is in [lo, hi].
    const float xlo = cx + f * sx.x, xhi = cx + f * sx.y;
    const float ylo = cy - f * sy.y, yhi = cy - f * sy.x;  // +y view is up, rows go down
    auto clampI = [](float v, int hi) { return int(std::clamp(v, -1.0f, float(hi) + 1.0f)); };
    // A hundredth of a pixel of slack against rounding in the slopes (float
    // error here is ~1e-3 px at 16k pixels); the exact ray test decides coverage.
    constexpr float eps = 0.01f;
    PixelRect rect;
    rect.x0 = std::max(0, clampI(std::ceil(xlo - 0.5f - eps), camera.width));
    rect.x1 = std::min(camera.width, clampI(std::floor(xhi - 0.5f + eps), camera.width) + 1);
    rect.y0 = std::max(0, clampI(std::ceil(ylo - 0.5f - eps), camera.height));
    rect.y1 = std::min(camera.height, clampI(std::floor(yhi - 0.5f + eps), camera.height) + 1);
    return rect;
}

float raySphereEyeDepth(const glm::vec3& ray, const glm::vec3& c, float r) {
    // Along the unit direction u = ray/|ray|: closest approach b = u·c, squared
    // miss distance |c - b u|² (computed from the vector, not c·c - b², to keep
    // precision for small spheres far away). Since ray.z = -1, the eye depth of
    // the point t*u is t/|ray|.
    const float len = std::sqrt(glm::dot(ray, ray));
    const glm::vec3 u = ray / len;
    const float b = glm::dot(u, c);
    const glm::vec3 off = c - b * u;
    const float h2 = r * r - glm::dot(off, off);
    if (h2 < 0.0f) return kInf;
    const float t = b - std::sqrt(h2);
    if (t <= 0.0f) return kInf;  // nearest hit behind the eye
    return t / len;
}

Image<float> splatDepth(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                        const Image<float>* sceneDepth) {
    const int W = camera.width, H = camera.height;
    Image<float> depth(W, H, kInf);
    const int tilesX = (W + kTile - 1) / kTile, tilesY = (H + kTile - 1) / kTile;

    // View-space centres and screen rectangles, in parallel (independent per particle).
    const std::size_t n = positionsWorld.size();
    std::vector<glm::vec3> centres(n);
    std::vector<PixelRect> rects(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        centres[i] = camera.toView(positionsWorld[i]);
        rects[i] = projectedSphereBounds(camera, centres[i], radius);
    });

    // Bin particle indices per tile: count, prefix sum, fill (serial, in
    // particle order, so the bins are the same for any thread count).
    std::vector<std::uint32_t> start(std::size_t(tilesX) * std::size_t(tilesY) + 1, 0);
    auto forTiles = [&](const PixelRect& r, auto&& fn) {
        if (r.empty()) return;
        for (int ty = r.y0 / kTile; ty <= (r.y1 - 1) / kTile; ++ty)
            for (int tx = r.x0 / kTile; tx <= (r.x1 - 1) / kTile; ++tx) fn(std::size_t(ty) * tilesX + tx);
    };
    for (std::size_t i = 0; i < n; ++i) forTiles(rects[i], [&](std::size_t t) { ++start[t + 1]; });
    for (std::size_t t = 1; t < start.size(); ++t) start[t] += start[t - 1];
    std::vector<std::uint32_t> items(start.back());
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
        forTiles(rects[i], [&](std::size_t t) { items[fill[t]++] = std::uint32_t(i); });

    // Pixel rays without calling Camera per pixel (focalPx() costs a tan).
    const float nearM = camera.nearM;
    const float invF = 1.0f / camera.focalPx();
    const float halfW = 0.5f * float(W), halfH = 0.5f * float(H);
    tbb::parallel_for(0, tilesX * tilesY, [&](int t) {
        const int tx = t % tilesX, ty = t / tilesX;
        const int bx0 = tx * kTile, by0 = ty * kTile;
        const int bx1 = std::min(W, bx0 + kTile), by1 = std::min(H, by0 + kTile);
        for (std::uint32_t k = start[t]; k < start[t + 1]; ++k) {
            const std::uint32_t i = items[k];
            const PixelRect& r = rects[i];
            for (int y = std::max(r.y0, by0); y < std::min(r.y1, by1); ++y)
                for (int x = std::max(r.x0, bx0); x < std::min(r.x1, bx1); ++x) {
                    const glm::vec3 ray{(float(x) + 0.5f - halfW) * invF, -(float(y) + 0.5f - halfH) * invF, -1.0f};
                    const float z = raySphereEyeDepth(ray, centres[i], radius);
                    if (z < nearM) continue;  // clipped by the near plane (a miss is +inf and never wins)
                    float& d = depth.at(x, y);
                    if (z < d && (!sceneDepth || z < sceneDepth->at(x, y))) d = z;
                }
        }
    });
    return depth;
}

}  // namespace meniscus::cpu
