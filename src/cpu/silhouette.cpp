// CPU silhouette reduction, docs/pipeline.md#silhouette-reduction (Cords &
// Staadt 2008, "Instant Liquids" §3: the binary depth map smoothed by the
// filter's kernel, the liquid shown only where it reaches 1). Here the window
// is a square of uniform weights, so its fluid count comes from a summed-area
// table in four reads, and S = count / area is the same bits on the GL twin;
// the liquid fades into the scene colour behind it where S < 1 rather than only
// clipping (SilhouetteParams::fadeFrom = 1 clips as the paper).
#include "cpu/silhouette.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "shared/silhouette.h"
#include "cpu/no_depth.h"

namespace meniscus::cpu {

std::vector<std::uint32_t> fluidSummedArea(const Image<float>& depth) {
    const int W = depth.width, H = depth.height;
    const std::size_t stride = std::size_t(W) + 1;
    std::vector<std::uint32_t> sat(stride * (std::size_t(H) + 1), 0u);
    // Rows in parallel (each its own prefix sum), then the columns.
    tbb::parallel_for(0, H, [&](int y) {
        std::uint32_t run = 0;
        std::uint32_t* row = sat.data() + (std::size_t(y) + 1) * stride;
        for (int x = 0; x < W; ++x) {
            run += depth.at(x, y) < std::numeric_limits<float>::infinity() ? 1u : 0u;
            row[x + 1] = run;
        }
    });
    tbb::parallel_for(tbb::blocked_range<int>(1, W + 1, 64), [&](const tbb::blocked_range<int>& r) {
        for (int y = 1; y <= H; ++y) {
            std::uint32_t* row = sat.data() + std::size_t(y) * stride;
            const std::uint32_t* up = row - stride;
            for (int x = r.begin(); x < r.end(); ++x) row[x] += up[x];
        }
    });
    return sat;
}

namespace {

// S of the window of pixel (x, y) sized at depth z, from the W x H mask's table.
float windowFraction(const std::vector<std::uint32_t>& sat, int W, int H, int x, int y, float z, float radiusM,
                     float focal, int maxPx) {
    const std::size_t stride = std::size_t(W) + 1;
    const glm::ivec4 w = shared::silhouetteWindow(x, y, z, radiusM, focal, maxPx, W, H);
    auto at = [&](int xx, int yy) { return sat[std::size_t(yy) * stride + std::size_t(xx)]; };
    const std::uint32_t count = at(w.z, w.w) - at(w.x, w.w) - at(w.z, w.y) + at(w.x, w.y);
    return shared::silhouetteFraction(int(count), (w.z - w.x) * (w.w - w.y));
}

template <class F>
void forFluidFractions(const Camera& camera, const Image<float>& depth, float radius, const SilhouetteParams& p, F&& f) {
    const int W = depth.width, H = depth.height;
    const std::vector<std::uint32_t> sat = fluidSummedArea(depth);
    const float radiusM = p.radiusRadii * radius, focal = camera.focalPx();
    tbb::parallel_for(0, H, [&](int y) {
        for (int x = 0; x < W; ++x) {
            const float z = depth.at(x, y);
            if (z < kInf) f(x, y, windowFraction(sat, W, H, x, y, z, radiusM, focal, p.maxPx));
        }
    });
}
}  // namespace

Image<float> silhouetteMap(const Camera& camera, const Image<float>& depth, float radius, const SilhouetteParams& p) {
    Image<float> s(depth.width, depth.height, 0.0f);
    forFluidFractions(camera, depth, radius, p, [&](int x, int y, float S) { s.at(x, y) = S; });
    return s;
}

Image<float> reduceSilhouettes(const Camera& camera, const Image<float>& depth, const Image<glm::vec4>& behind,
                               float radius, const SilhouetteParams& p, Image<glm::vec4>& color) {
    const int W = camera.width, H = camera.height;
    Image<float> s(W, H, 0.0f);
    if (depth.width != W || depth.height != H || behind.width != W || behind.height != H || color.width != W ||
        color.height != H)
        return s;
    // The liquid's colours before any fade, for the background pixels next to it.
    const Image<glm::vec4> liquid = color;
    const std::vector<std::uint32_t> sat = fluidSummedArea(depth);
    const float radiusM = p.radiusRadii * radius, focal = camera.focalPx();
    tbb::parallel_for(0, H, [&](int y) {
        for (int x = 0; x < W; ++x) {
            float z = depth.at(x, y);
            const bool fluid = z < kInf;
            glm::vec4 sum(0.0f);
            int n = 0;
            if (!fluid) {  // past the contour: the fluid 8-neighbours, in row order
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int xx = x + dx, yy = y + dy;
                        if ((dx == 0 && dy == 0) || xx < 0 || yy < 0 || xx >= W || yy >= H) continue;
                        const float zn = depth.at(xx, yy);
                        if (!(zn < kInf)) continue;
                        z = std::min(z, zn);
                        sum += liquid.at(xx, yy);
                        ++n;
                    }
                if (n == 0) continue;
            }
            const float S = windowFraction(sat, W, H, x, y, z, radiusM, focal, p.maxPx);
            const float a = shared::silhouetteAlpha(S, p.fadeFrom);
            if (fluid) {
                s.at(x, y) = S;
                if (a < 1.0f) color.at(x, y) = shared::silhouetteBlend(color.at(x, y), behind.at(x, y), a);
            } else if (a > 0.0f) {
                color.at(x, y) = shared::silhouetteBlend(shared::silhouetteOuterColor(sum, n), behind.at(x, y), a);
            }
        }
    });
    return s;
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// Faded in place on the colour (a copy of the scene when the slot names the
// cached scene: the cache is never faded).
void runSilhouette(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    Image<glm::vec4>& color = c.colorToPaint(io.at.color);
    c.scalarOut(io.at.silhouette) =
        reduceSilhouettes(s.camera, c.scalar(io.at.depth), c.color(io.at.sceneColor), s.radius, s.silhouette, color);
}

}  // namespace

extern const StageDriver kSilhouetteStage = {nullptr, runSilhouette};

}  // namespace meniscus::cpu
