// CPU normals stage, docs/pipeline.md#normals. The formulas (the exact
// back-projection P = z * ray(x+1/2, y+1/2), the choice of neighbour
// difference per axis, n = normalize(dP/dx × dP/dy) turned toward the eye)
// are src/shared/normals.h, which the GL twin calls too; this file runs them
// over the image.
//
// Speed: the per-pixel logic is branch-free (both candidates computed, one
// selected) so GCC vectorises each row (target_clones: AVX2 or the SSE2
// baseline; the same IEEE operations in either, no FMA); non-fluid lanes
// between the first and last fluid pixel of a row are computed too and written
// as (0,0,0); outside that span the row loop writes (0,0,0), so a frame's
// normals reuse the last frame's buffer without a serial zero fill.
#include "cpu/normals.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "cpu/filter_util.h"
#include "shared/normals.h"

namespace meniscus::cpu {

namespace {

// The normal of pixel x of a row (shared::normalsAt) into dst[0..2]. Inlined
// into the row loop, which it keeps branch-free.
inline void normalAt(float z, float zl, float zr, float zu, float zd, float rxc, float rxl, float rxr, float ryc,
                     float ryu, float ryd, float jump, float* dst) {
    const glm::vec3 n = shared::normalsAt(z, zl, zr, zu, zd, rxc, rxl, rxr, ryc, ryu, ryd, jump);
    dst[0] = n.x;
    dst[1] = n.y;
    dst[2] = n.z;
}

// One row. up / down: the neighbouring rows (an all-+inf row at the border).
// flatten: the shared formulas are inlined into the loop (GCC's heuristics
// leave them calls, and a loop with a call does not vectorise).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default"), flatten))
#endif
void normalsRow(const float* row, const float* up, const float* down, const float* rx, float ryc, float ryu,
                float ryd, int w, float jump, float* dst) {
    constexpr float kInf = INFINITY;
    // Only the span from the first to the last fluid pixel of the row: the
    // caller writes the rest (0,0,0) (most of a frame is background).
    int first = 0, last = w - 1;
    while (first < w && !(row[first] < kInf)) ++first;
    if (first == w) return;
    while (!(row[last] < kInf)) --last;
    // rx[x + 1] is the ray of column x (rx[0], rx[w + 1]: the columns outside).
    for (int x = std::max(first, 1); x <= std::min(last, w - 2); ++x)
        normalAt(row[x], row[x - 1], row[x + 1], up[x], down[x], rx[x + 1], rx[x], rx[x + 2], ryc, ryu, ryd, jump,
                 &dst[3 * x]);
    // The two end columns: their outer neighbour is outside the image.
    if (first == 0)
        normalAt(row[0], kInf, w > 1 ? row[1] : kInf, up[0], down[0], rx[1], rx[0], rx[2], ryc, ryu, ryd, jump,
                 &dst[0]);
    if (w > 1 && last == w - 1) {
        const int x = w - 1;
        normalAt(row[x], row[x - 1], kInf, up[x], down[x], rx[x + 1], rx[x], rx[x + 2], ryc, ryu, ryd, jump,
                 &dst[3 * x]);
    }
}

}  // namespace

void computeNormals(const Image<float>& depth, const Camera& camera, float radius, float jumpRadii,
                    Image<glm::vec3>& out) {
    const int w = depth.width, h = depth.height;
    if (w <= 0 || h <= 0) {
        out = Image<glm::vec3>(w, h);
        return;
    }
    // Every pixel is written below: the rows' spans by normalsRow, the rest
    // (0,0,0) by the row loop, so a buffer of the right size is reused as it is.
    if (out.width != w || out.height != h || out.pixels.size() != std::size_t(w) * std::size_t(h)) {
        out.width = w;
        out.height = h;
        resizeFresh(out.pixels, std::size_t(w) * std::size_t(h));
    }

    // Ray components per column / row, computed exactly as Camera::pixelRay does,
    // so P(x, y) = z * (rx[x], ry[y], -1) equals camera.unproject(x+0.5, y+0.5, z).
    const float f = camera.focalPx();
    std::vector<float> rx(std::size_t(w) + 2), ry(std::size_t(h) + 2);
    for (int x = -1; x <= w; ++x) rx[std::size_t(x + 1)] = shared::normalsRayX(x, 0.5f * float(w), f);
    for (int y = -1; y <= h; ++y) ry[std::size_t(y + 1)] = shared::normalsRayY(y, 0.5f * float(h), f);
    const float jump = jumpRadii * radius;
    const std::vector<float> infRow(std::size_t(w), INFINITY);
    static_assert(sizeof(glm::vec3) == 3 * sizeof(float));

    forEachRow(h, [&](int y) {
        const float* row = &depth.pixels[std::size_t(y) * std::size_t(w)];
        const float* up = y > 0 ? row - w : infRow.data();
        const float* down = y + 1 < h ? row + w : infRow.data();
        glm::vec3* px = &out.pixels[std::size_t(y) * std::size_t(w)];
        // (0,0,0) outside the span from the first to the last fluid pixel
        // (normalsRow writes the span, non-fluid pixels in it included).
        int first = 0, last = w - 1;
        while (first < w && !(row[first] < INFINITY)) ++first;
        while (last >= first && !(row[last] < INFINITY)) --last;
        std::fill(px, px + first, glm::vec3(0.0f));
        std::fill(px + last + 1, px + w, glm::vec3(0.0f));
        normalsRow(row, up, down, rx.data(), ry[std::size_t(y + 1)], ry[std::size_t(y)], ry[std::size_t(y + 2)], w,
                   jump, &px->x);
    });
}

Image<glm::vec3> computeNormals(const Image<float>& depth, const Camera& camera, float radius, float jumpRadii) {
    Image<glm::vec3> out;
    computeNormals(depth, camera, radius, jumpRadii, out);
    return out;
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runNormals(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    computeNormals(c.scalar(io.at.depth), s.camera, s.radius, defaults::kDepthJumpRadii, c.vec3(io.at.normal));
}

}  // namespace

extern const StageDriver kNormalsStage = {nullptr, runNormals};

}  // namespace meniscus::cpu
