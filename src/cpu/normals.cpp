// CPU normals stage, docs/pipeline.md#normals. After van der Laan, Green & Sainz 2009
// (US 8,947,430, eqs. 3-6) and Cords & Staadt 2008 ("Instant Liquids" §2.3,
// perspective-correct normals): every fluid pixel is back-projected with its
// smoothed eye depth to the view-space point P = z * ray(x+1/2, y+1/2), and
// n = normalize(dP/dx × dP/dy).
//
// Choices:
//  - The exact inverse projection is used (the patent drops the W terms of its
//    eq. 5; keeping them costs nothing and makes a plane's normal exact).
//  - Per axis: the central difference where both neighbours continue the
//    surface; at a discontinuity (neighbour +inf, outside the image, |dz| above
//    jumpRadii * r) or where the two one-sided differences disagree by more than
//    that, the one-sided difference with the smaller |dz| (patent), so the
//    normals of separate bodies never mix.
//  - With no usable neighbour along an axis, the tangent is the screen axis
//    made perpendicular to the view ray, i.e. the surface is taken to face the
//    camera along that axis (a one-pixel sliver faces the eye exactly).
//  - Image rows grow downward while view-space y grows upward, so the "y"
//    tangent is taken toward the row above: n = tx × tUp then has +z toward
//    the camera for a surface facing it.
//  - Speed: the per-pixel logic is branch-free (both candidates computed, one
//    selected) so GCC vectorises each row (target_clones: AVX2 or the SSE2
//    baseline; the same IEEE operations in either, no FMA); non-fluid lanes
//    between the first and last fluid pixel of a row are computed too and
//    written as (0,0,0); outside that span the zero-filled output is kept.
#include "cpu/normals.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "cpu/filter_util.h"

namespace meniscus::cpu {

namespace {

// Tangent along one image axis from the point p (depth z) and its two
// neighbours (m: previous, p: next; zm, zp their depths, +inf when outside the
// image or no fluid), or the fallback f when neither neighbour is usable.
// Branch-free: neighbours with infinite depth give non-finite points, but those
// lanes are never selected (rejected by their depth first).
inline void axisTangent(float px, float py, float pz, float z, float mx, float my, float mz, float zm, float qx,
                        float qy, float qz, float zp, float jump, float fx, float fy, float fz, float* tx, float* ty,
                        float* tz) {
    const float dzm = z - zm, dzp = zp - z;  // +inf - finite = +inf: never usable
    const bool okm = std::fabs(dzm) <= jump, okp = std::fabs(dzp) <= jump;
    // Smooth surface: central difference. A crease (the two sides disagree):
    // the flatter side. One usable side: that one.
    const bool central = okm & okp & (std::fabs(dzp - dzm) <= jump);
    const bool plus = okp & (!okm | (std::fabs(dzp) < std::fabs(dzm)));
    *tx = central ? qx - mx : plus ? qx - px : okm ? px - mx : fx;
    *ty = central ? qy - my : plus ? qy - py : okm ? py - my : fy;
    *tz = central ? qz - mz : plus ? qz - pz : okm ? pz - mz : fz;
}

// The normal of pixel (column ray rxc, row ray ryc) with depth z and its four
// neighbours' depths (+inf outside / no fluid); rxl, rxr: the rays of the
// columns left and right, ryu, ryd: of the rows above and below. (0,0,0) where
// z is not fluid.
inline void normalAt(float z, float zl, float zr, float zu, float zd, float rxc, float rxl, float rxr, float ryc,
                     float ryu, float ryd, float jump, float* nxOut, float* nyOut, float* nzOut) {
    const float px = z * rxc, py = z * ryc, pz = -z;
    // Unit view ray, for the fallback tangents and the orientation.
    // (Reciprocals times components rather than three divisions: divisions
    // dominate this loop; the difference is an ulp.)
    const float invLen = 1.0f / std::sqrt(px * px + py * py + pz * pz);
    const float ux = px * invLen, uy = py * invLen, uz = pz * invLen;
    float tx, ty, tz, sx, sy, sz;  // along +x (right), toward the row above (+y view)
    axisTangent(px, py, pz, z, zl * rxl, zl * ryc, -zl, zl, zr * rxr, zr * ryc, -zr, zr, jump, 1.0f - ux * ux,
                0.0f - ux * uy, 0.0f - ux * uz, &tx, &ty, &tz);
    axisTangent(px, py, pz, z, zd * rxc, zd * ryd, -zd, zd, zu * rxc, zu * ryu, -zu, zu, jump, 0.0f - uy * ux,
                1.0f - uy * uy, 0.0f - uy * uz, &sx, &sy, &sz);
    // n = t × s
    float nx = ty * sz - sy * tz, ny = tz * sx - sz * tx, nz = tx * sy - sx * ty;
    const float nlen = std::sqrt(nx * nx + ny * ny + nz * nz);
    const bool ok = nlen > 0.0f;  // degenerate tangents: face the camera
    const float invN = 1.0f / nlen;
    nx = ok ? nx * invN : -ux;
    ny = ok ? ny * invN : -uy;
    nz = ok ? nz * invN : -uz;
    const bool flip = ok & (nx * ux + ny * uy + nz * uz > 0.0f);  // toward the eye
    nx = flip ? -nx : nx;
    ny = flip ? -ny : ny;
    nz = flip ? -nz : nz;
    const bool fluid = z < INFINITY;
    *nxOut = fluid ? nx : 0.0f;
    *nyOut = fluid ? ny : 0.0f;
    *nzOut = fluid ? nz : 0.0f;
}

// One row. up / down: the neighbouring rows (an all-+inf row at the border).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void normalsRow(const float* row, const float* up, const float* down, const float* rx, float ryc, float ryu,
                float ryd, int w, float jump, float* dst) {
    constexpr float kInf = INFINITY;
    // Only the span from the first to the last fluid pixel of the row: the rest
    // stays (0,0,0) from the zero-filled output (most of a frame is background).
    int first = 0, last = w - 1;
    while (first < w && !(row[first] < kInf)) ++first;
    if (first == w) return;
    while (!(row[last] < kInf)) --last;
    // rx[x + 1] is the ray of column x (rx[0], rx[w + 1]: the columns outside).
    for (int x = std::max(first, 1); x <= std::min(last, w - 2); ++x)
        normalAt(row[x], row[x - 1], row[x + 1], up[x], down[x], rx[x + 1], rx[x], rx[x + 2], ryc, ryu, ryd, jump,
                 &dst[3 * x], &dst[3 * x + 1], &dst[3 * x + 2]);
    // The two end columns: their outer neighbour is outside the image.
    if (first == 0)
        normalAt(row[0], kInf, w > 1 ? row[1] : kInf, up[0], down[0], rx[1], rx[0], rx[2], ryc, ryu, ryd, jump,
                 &dst[0], &dst[1], &dst[2]);
    if (w > 1 && last == w - 1) {
        const int x = w - 1;
        normalAt(row[x], row[x - 1], kInf, up[x], down[x], rx[x + 1], rx[x], rx[x + 2], ryc, ryu, ryd, jump,
                 &dst[3 * x], &dst[3 * x + 1], &dst[3 * x + 2]);
    }
}

}  // namespace

Image<glm::vec3> computeNormals(const Image<float>& depth, const Camera& camera, float radius, float jumpRadii) {
    const int w = depth.width, h = depth.height;
    if (w <= 0 || h <= 0) return Image<glm::vec3>(w, h);
    Image<glm::vec3> out;  // every pixel is written below
    out.width = w;
    out.height = h;
    resizeFresh(out.pixels, std::size_t(w) * std::size_t(h));

    // Ray components per column / row, computed exactly as Camera::pixelRay does,
    // so P(x, y) = z * (rx[x], ry[y], -1) equals camera.unproject(x+0.5, y+0.5, z).
    const float f = camera.focalPx();
    std::vector<float> rx(std::size_t(w) + 2), ry(std::size_t(h) + 2);
    for (int x = -1; x <= w; ++x) rx[std::size_t(x + 1)] = (float(x) + 0.5f - 0.5f * float(w)) / f;
    for (int y = -1; y <= h; ++y) ry[std::size_t(y + 1)] = -(float(y) + 0.5f - 0.5f * float(h)) / f;
    const float jump = jumpRadii * radius;
    const std::vector<float> infRow(std::size_t(w), INFINITY);
    static_assert(sizeof(glm::vec3) == 3 * sizeof(float));

    forEachRow(h, [&](int y) {
        const float* row = &depth.pixels[std::size_t(y) * std::size_t(w)];
        const float* up = y > 0 ? row - w : infRow.data();
        const float* down = y + 1 < h ? row + w : infRow.data();
        float* dst = &out.pixels[std::size_t(y) * std::size_t(w)].x;
        normalsRow(row, up, down, rx.data(), ry[std::size_t(y + 1)], ry[std::size_t(y)], ry[std::size_t(y + 2)], w,
                   jump, dst);
    });
    return out;
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runNormals(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    c.vec3(io.at.normal) = computeNormals(c.scalar(io.at.depth), s.camera, s.radius, defaults::kDepthJumpRadii);
}

}  // namespace

extern const StageDriver kNormalsStage = {nullptr, runNormals};

}  // namespace meniscus::cpu
