// CPU hole filling, docs/pipeline.md#hole-filling (the rule and formulas:
// src/shared/hole_fill.h). Per row in parallel; the nearest covered pixels
// along the row (two scans of the row) and the column (two sweeps of blocks of
// columns) come without a walk, so the row and the column turn most of the
// background away at once; only pixels they close, one of them narrowly, walk
// the diagonals. Reads the splat as it came (a copy), so a filled pixel never
// closes another and the order of the rows does not matter.
#include "cpu/hole_fill.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "shared/hole_fill.h"

namespace meniscus::cpu {

namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

struct LineEnd {
    int steps = 0;  // 0: no covered pixel within maxPx
    float z = kInf, t = 0.0f;
};

// The nearest covered pixel from (x, y) along (dx, dy), at most maxPx steps.
LineEnd walk(const Image<float>& depth, const Image<float>* thickness, int x, int y, int dx, int dy, int maxPx) {
    const int W = depth.width, H = depth.height;
    for (int i = 1; i <= maxPx; ++i) {
        const int xx = x + i * dx, yy = y + i * dy;
        if (xx < 0 || xx >= W || yy < 0 || yy >= H) break;
        const float z = depth.at(xx, yy);
        if (z < kInf) return {i, z, thickness ? thickness->at(xx, yy) : 0.0f};
    }
    return {};
}
}  // namespace

namespace {

// One pass: fills from `depth` and `thickness` as they are on entry.
std::size_t fillPass(const Camera& camera, float radius, const HoleFillParams& p, const Image<float>* sceneDepth,
                     Image<float>& depth, Image<float>& thickness) {
    const int W = depth.width, H = depth.height;
    const Image<float> src = depth;
    const bool hasT = thickness.width == W && thickness.height == H;
    const Image<float> srcT = hasT ? thickness : Image<float>();
    const Image<float>* T = hasT ? &srcT : nullptr;
    const bool hasScene = sceneDepth && sceneDepth->width == W && sceneDepth->height == H;
    const float f = camera.focalPx();
    const int maxPx = p.reachPx;
    // Every pixel's distance to the nearest covered pixel above and below in
    // its column (255: none within 254 >= reachPx), by sweeps down and up
    // blocks of columns in parallel; bytes, to keep the sweeps' traffic small.
    const std::size_t pixels = std::size_t(W) * std::size_t(H);
    std::vector<std::uint8_t> up(pixels), down(pixels);
    tbb::parallel_for(tbb::blocked_range<int>(0, W, 64), [&](const tbb::blocked_range<int>& cols) {
        std::vector<int> dist(std::size_t(cols.size()));
        for (int pass = 0; pass < 2; ++pass) {
            std::fill(dist.begin(), dist.end(), 255);
            std::vector<std::uint8_t>& out = pass == 0 ? up : down;
            for (int k = 0; k < H; ++k) {
                const int y = pass == 0 ? k : H - 1 - k;
                const float* row = &src.pixels[std::size_t(y) * std::size_t(W)];
                std::uint8_t* o = &out[std::size_t(y) * std::size_t(W)];
                for (int x = cols.begin(); x < cols.end(); ++x) {
                    int& d = dist[std::size_t(x - cols.begin())];
                    d = row[x] < kInf ? 0 : std::min(d + 1, 255);
                    o[x] = std::uint8_t(d);
                }
            }
        }
    });
    std::atomic<std::size_t> filled{0};
    tbb::parallel_for(0, H, [&](int y) {
        // The row's nearest covered pixel at or left of x (-1: none), and at or right (W: none).
        std::vector<int> left(static_cast<std::size_t>(W)), right(static_cast<std::size_t>(W));
        for (int x = 0, last = -1; x < W; ++x) left[std::size_t(x)] = last = src.at(x, y) < kInf ? x : last;
        for (int x = W - 1, next = W; x >= 0; --x) right[std::size_t(x)] = next = src.at(x, y) < kInf ? x : next;
        std::size_t n = 0;
        for (int x = 0; x < W; ++x) {
            const int xl = left[std::size_t(x)], xr = right[std::size_t(x)];
            if (xl == x || xl < 0 || xr >= W || x - xl > maxPx || xr - x > maxPx) continue;
            const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
            const int du = up[i], dd = down[i];
            if (du > maxPx || dd > maxPx) continue;
            const int yu = y - du, yd = y + dd;
            float zs[4], ts[4];
            bool closed = true;
            int narrow = 0;
            for (int k = 0; k < 4 && closed; ++k) {
                const int dx = shared::holeLineDx(k), dy = shared::holeLineDy(k);
                LineEnd a, b;
                if (k == 0) {
                    a = {x - xl, src.at(xl, y), T ? T->at(xl, y) : 0.0f};
                    b = {xr - x, src.at(xr, y), T ? T->at(xr, y) : 0.0f};
                } else if (k == 1) {
                    a = {y - yu, src.at(x, yu), T ? T->at(x, yu) : 0.0f};
                    b = {yd - y, src.at(x, yd), T ? T->at(x, yd) : 0.0f};
                } else if (narrow == 0) {  // row and column both long: three narrow lines are out of reach
                    closed = false;
                    break;
                } else {
                    a = walk(src, T, x, y, -dx, -dy, maxPx);
                    if (a.steps != 0) b = walk(src, T, x, y, dx, dy, maxPx);
                }
                if (a.steps == 0 || b.steps == 0) {
                    closed = false;
                    break;
                }
                zs[k] = shared::holeInterpolate(a.z, b.z, a.steps, b.steps);
                ts[k] = shared::holeInterpolate(a.t, b.t, a.steps, b.steps);
                const float length = shared::holeLineLengthPx(a.steps, b.steps, k >= 2);
                closed = shared::holeLineSameSurface(a.z, b.z, zs[k], length, radius, f, p.jumpRadii);
                narrow += shared::holeLineNarrow(zs[k], length, radius, f, p.maxSpanRadii) ? 1 : 0;
            }
            if (!closed || narrow < shared::kHoleNarrowLines) continue;
            const float z = shared::holeMean(zs[0], zs[1], zs[2], zs[3]);
            if (hasScene && !(z < sceneDepth->at(x, y))) continue;
            depth.at(x, y) = z;
            if (hasT) {
                const float t = shared::holeMean(ts[0], ts[1], ts[2], ts[3]);
                thickness.at(x, y) = std::max(thickness.at(x, y), t);
            }
            ++n;
        }
        filled += n;
    });
    return filled.load();
}

}  // namespace

std::size_t fillHoles(const Camera& camera, float radius, const HoleFillParams& p, const Image<float>* sceneDepth,
                      Image<float>& depth, Image<float>& thickness) {
    if (!p.enabled || depth.width <= 0 || depth.height <= 0 || p.reachPx < 1) return 0;
    std::size_t filled = 0;
    for (int pass = 0; pass < p.passes; ++pass) {
        const std::size_t n = fillPass(camera, radius, p, sceneDepth, depth, thickness);
        filled += n;
        if (n == 0) break;  // nothing new: later passes would fill nothing either
    }
    return filled;
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runFillHoles(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    fillHoles(s.camera, s.radius, s.holeFill, &c.scalar(io.at.sceneDepth), c.scalarOut(io.at.raw),
              c.scalarOut(io.at.thickness));
}

}  // namespace

extern const StageDriver kFillHolesStage = {nullptr, runFillHoles};

}  // namespace meniscus::cpu
