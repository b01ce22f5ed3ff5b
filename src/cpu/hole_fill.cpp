// CPU hole filling, docs/pipeline.md#hole-filling (the rule and formulas:
// src/shared/hole_fill.h). Per row in parallel; the nearest covered pixels
// along the row (the ends of the row's runs of uncovered pixels, found eight
// coverage bytes at a time) and the column (two sweeps of blocks of columns
// over the coverage bytes) come without a walk, so the row and the column turn most of the
// background away at once; only pixels they close, one of them narrowly, walk
// the diagonals. A pass reads the splat as it came into the pass: its fills
// are kept per row and written once every row is done, so a filled pixel
// never closes another within a pass and the order of the rows does not
// matter (without copying the depth and thickness per pass).
#include "cpu/hole_fill.h"
#include "cpu/cpu_backend.h"
#include "cpu/filter_util.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstring>
#include <cstdint>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "shared/hole_fill.h"
#include "cpu/no_depth.h"

namespace meniscus::cpu {

namespace {

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

// A pixel one pass fills, kept until the pass has read all it reads.
struct Fill {
    int x;
    float z, t;
};

// A pass's scratch, pixels bytes each (kept across the passes).
struct Scratch {
    std::vector<std::uint8_t> covered, up, down;
    std::vector<std::vector<Fill>> fills;  // per row
};

// The first index in [x, n) where c differs from v (0 or 1), or n: eight
// bytes at a time, since the runs of covered and uncovered pixels are long.
int nextOther(const std::uint8_t* c, int x, int n, std::uint8_t v) {
    const std::uint64_t all = v ? 0x0101010101010101ull : 0u;
    if constexpr (std::endian::native == std::endian::little) {  // byte i of the word is c[x + i]
        for (; x + 8 <= n; x += 8) {
            std::uint64_t w;
            std::memcpy(&w, c + x, sizeof w);
            if (const std::uint64_t d = w ^ all) return x + std::countr_zero(d) / 8;
        }
    }
    while (x < n && c[x] == v) ++x;
    return x;
}

// One pass: fills from `depth` and `thickness` as they are on entry. The
// rows read them unchanged (the fills of a row are kept and written after
// every row is done), so no copy of either is needed.
std::size_t fillPass(const Camera& camera, float radius, const HoleFillParams& p, const Image<float>* sceneDepth,
                     Image<float>& depth, Image<float>& thickness, Scratch& S) {
    const int W = depth.width, H = depth.height;
    const Image<float>& src = depth;
    const bool hasT = thickness.width == W && thickness.height == H;
    const Image<float>* T = hasT ? &thickness : nullptr;
    const bool hasScene = sceneDepth && sceneDepth->width == W && sceneDepth->height == H;
    const float f = camera.focalPx();
    const int maxPx = p.reachPx;
    // Coverage, a byte per pixel (1: covered), for the sweeps and the row scans.
    std::uint8_t* const covered = S.covered.data();
    forEachRow(H, [&](int y) {
        const float* row = &src.pixels[std::size_t(y) * std::size_t(W)];
        std::uint8_t* o = covered + std::size_t(y) * std::size_t(W);
        for (int x = 0; x < W; ++x) o[x] = row[x] < kInf ? 1 : 0;
    });
    // Every pixel's distance to the nearest covered pixel above and below in
    // its column (255: none within 254 >= reachPx), by sweeps down and up
    // blocks of columns in parallel, in bytes (a saturating count).
    tbb::parallel_for(tbb::blocked_range<int>(0, W, 64), [&](const tbb::blocked_range<int>& cols) {
        const int x0 = cols.begin(), n = int(cols.size());
        std::vector<std::uint8_t> dist(static_cast<std::size_t>(n));
        for (int pass = 0; pass < 2; ++pass) {
            std::fill(dist.begin(), dist.end(), std::uint8_t(255));
            std::uint8_t* out = pass == 0 ? S.up.data() : S.down.data();
            for (int k = 0; k < H; ++k) {
                const int y = pass == 0 ? k : H - 1 - k;
                const std::uint8_t* c = covered + std::size_t(y) * std::size_t(W) + x0;
                std::uint8_t* o = out + std::size_t(y) * std::size_t(W) + x0;
                for (int i = 0; i < n; ++i) {
                    const std::uint8_t d = dist[std::size_t(i)];
                    dist[std::size_t(i)] = c[i] ? std::uint8_t(0) : std::uint8_t(d + (d != 255));
                    o[i] = dist[std::size_t(i)];
                }
            }
        }
    });
    const std::uint8_t* const up = S.up.data();
    const std::uint8_t* const down = S.down.data();
    tbb::parallel_for(tbb::blocked_range<int>(0, H, 4), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y) {
            std::vector<Fill>& rowFills = S.fills[std::size_t(y)];
            rowFills.clear();
            // The runs of uncovered pixels with a covered pixel on both sides
            // (xl = s - 1 and xr = e, the row's nearest covered pixels of each
            // of them); only the pixels within maxPx of both are candidates.
            const std::uint8_t* c = covered + std::size_t(y) * std::size_t(W);
            for (int e = nextOther(c, 0, W, 1); e < W;) {
                const int s = e;
                e = nextOther(c, s, W, 0);
                if (s == 0 || e == W) {
                    e = nextOther(c, e, W, 1);
                    continue;
                }
                const int xl = s - 1, xr = e;
                const int first = std::max(s, xr - maxPx), last = std::min(e - 1, xl + maxPx);
                e = nextOther(c, e, W, 1);
                for (int x = first; x <= last; ++x) {
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
                    rowFills.push_back({x, z, hasT ? shared::holeMean(ts[0], ts[1], ts[2], ts[3]) : 0.0f});
                }
            }
        }
    });
    // Every row has read what it reads: write the fills (each row its own pixels).
    std::atomic<std::size_t> filled{0};
    forEachRow(H, [&](int y) {
        const std::vector<Fill>& rowFills = S.fills[std::size_t(y)];
        for (const Fill& fl : rowFills) {
            depth.at(fl.x, y) = fl.z;
            if (hasT) thickness.at(fl.x, y) = std::max(thickness.at(fl.x, y), fl.t);
        }
        if (!rowFills.empty()) filled += rowFills.size();
    });
    return filled.load();
}

}  // namespace

std::size_t fillHoles(const Camera& camera, float radius, const HoleFillParams& p, const Image<float>* sceneDepth,
                      Image<float>& depth, Image<float>& thickness) {
    if (!p.enabled || depth.width <= 0 || depth.height <= 0 || p.reachPx < 1) return 0;
    std::size_t filled = 0;
    const std::size_t pixels = std::size_t(depth.width) * std::size_t(depth.height);
    Scratch S;  // every byte is written by each pass
    resizeFresh(S.covered, pixels);
    resizeFresh(S.up, pixels);
    resizeFresh(S.down, pixels);
    S.fills.resize(std::size_t(depth.height));
    for (int pass = 0; pass < p.passes; ++pass) {
        const std::size_t n = fillPass(camera, radius, p, sceneDepth, depth, thickness, S);
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
