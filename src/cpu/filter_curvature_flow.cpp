// Screen-space curvature flow: van der Laan, Green & Sainz, "Screen Space Fluid
// Rendering with Curvature Flow", I3D 2009 (NVIDIA patent US 8,947,430, eqs.
// 3-12), exactly as restated in docs/pipeline.md#curvature-flow.
//
// With Cx = Cy = C = 1/f (f = camera.focalPx(), pixels) and central pixel
// differences z_x, z_y, z_xx, z_yy, z_xy of the eye depth z (metres):
//   D  = Cy² z_x² + Cx² z_y² + Cx² Cy² z²
//   Ex = ½ z_x ∂D/∂x − z_xx D,   Ey = ½ z_y ∂D/∂y − z_yy D
//   2H = (Cy Ex + Cx Ey) / D^{3/2}
//   z ← z − Δt·H,   Δt = alpha·z/f   (per pixel)
// z is positive eye depth here; the papers use negative view z and write "+".
// Linearised, H ≈ −(f/2z)(z_xx + z_yy), so the update is z += (alpha/2)·∇²z:
// explicit Euler is stable for alpha ≤ 0.5 (0.4 default; 0.55 diverges).
//
// Parameters (CurvatureFlowParams): iterations (count), alpha (dimensionless
// time-step factor), jumpRadii (discontinuity threshold in particle radii r).
//
// Choices:
//  - ∂D/∂x, ∂D/∂y are taken ANALYTICALLY from D (product rule), which needs the
//    mixed difference z_xy = (z(+1,+1) − z(−1,+1) − z(+1,−1) + z(−1,−1))/4;
//    this keeps the stencil 3×3 (differencing D would need a 5×5 one).
//  - With Cx = Cy = C the C's cancel: D = C²·G with G = z_x² + z_y² + w²,
//    w = C·z (the pixel footprint in metres), and
//      G_x = 2(z_x z_xx + z_y z_xy + C w z_x),  G_y = 2(z_x z_xy + z_y z_yy + C w z_y),
//      2H = (½ z_x G_x + ½ z_y G_y − (z_xx + z_yy) G) / G^{3/2}.
//    Every term of G is O(w²), so nothing is lost to float cancellation (the
//    C⁴z² ≈ 1e-12 term of D never appears), one division and one sqrt per
//    pixel remain, and the formula stays homogeneous in z (scale-invariant).
//  - Discontinuities: the x derivatives (z_x, z_xx) are zero unless both x
//    neighbours are fluid and within jumpRadii·r of the centre; likewise y; z_xy
//    is zero unless both of those hold and all four diagonal neighbours are
//    within the threshold too. The image border counts as "no fluid" (a +inf
//    frame around a padded copy), so separate patches never blend and
//    silhouettes neither shrink nor grow. +inf pixels stay +inf.
//  - Jacobi iterations (double-buffered), each output pixel a pure function of
//    the previous buffer: bit-identical for any thread count. Only runs of
//    fluid pixels are visited (the fluid set never changes); the inner loop is
//    branch-free so the compiler can vectorise it, compiled twice (GCC
//    target_clones: AVX2 and the SSE2 baseline, chosen at run time; the same
//    IEEE operations, no FMA, so the same output on every x86-64 machine).
//  - The normal behind D, (−Cy z_x, −Cx z_y, Cx Cy z), drops the terms that carry
//    the pixel's ray direction, so a tilted plane has a tiny H ~ C·slope²: it
//    drifts by ~1e-5 of its depth in 40 iterations (see the plane test).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "cpu/filter_util.h"
#include "cpu/filters.h"

namespace meniscus::cpu {

namespace {

// One Jacobi step on padded rows: dst[x] for x in [x0, x1) of the row `c`
// (rows `u` above and `d` below). Branch-free selects so it vectorises.
// Built with -fno-math-errno -fno-trapping-math (CMakeLists.txt) so GCC can
// if-convert the selects and use packed sqrt/div; both flags are value-safe.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void flowSpan(const float* __restrict u, const float* __restrict c, const float* __restrict d,
              float* __restrict dst, int x0, int x1, float C, float thr, float alpha) {
    for (int x = x0; x < x1; ++x) {
        const float z = c[x];
        const float zl = c[x - 1], zr = c[x + 1], zu = u[x], zd = d[x];
        const float zul = u[x - 1], zur = u[x + 1], zdl = d[x - 1], zdr = d[x + 1];
        // |a − z| <= thr is false for +inf neighbours and for a +inf centre
        // (NaN).
        auto near = [&](float a) { return std::fabs(a - z) <= thr; };
        const bool vx = near(zl) & near(zr);
        const bool vy = near(zu) & near(zd);
        const bool vxy = vx & vy & near(zul) & near(zur) & near(zdl) & near(zdr);
        // Differences are computed unconditionally, then selected (branch-free).
        const float px = vx ? 0.5f * (zr - zl) : 0.0f, pxx = vx ? (zr + zl - 2.0f * z) : 0.0f;
        const float py = vy ? 0.5f * (zd - zu) : 0.0f, pyy = vy ? (zd + zu - 2.0f * z) : 0.0f;
        const float pxy = vxy ? 0.25f * ((zdr - zdl) - (zur - zul)) : 0.0f;
        const float w = C * z;
        const float G = px * px + py * py + w * w;
        const float Gx = 2.0f * (px * pxx + py * pxy + C * w * px);
        const float Gy = 2.0f * (px * pxy + py * pyy + C * w * py);
        const float num = 0.5f * (px * Gx + py * Gy) - (pxx + pyy) * G;  // 2H = num / G^{3/2}
        // z − Δt·H with Δt = alpha·w and H = num / (2 G^{3/2}).
        const float zNew = z - (0.5f * alpha) * w * num / (G * std::sqrt(G));
        dst[x] = z < INFINITY ? zNew : z;
    }
}

}  // namespace

Image<float> filterCurvatureFlow(const Image<float>& depth, const Camera& camera, float radius,
                                 const CurvatureFlowParams& p) {
    const int W = depth.width, H = depth.height;
    if (W <= 0 || H <= 0 || p.iterations <= 0) return depth;
    const float f = camera.focalPx();
    const float thr = p.jumpRadii * radius;
    constexpr float kInf = std::numeric_limits<float>::infinity();

    // Padded copies with a one-pixel +inf frame: border neighbours are "no fluid".
    const int PW = W + 2;
    std::vector<float> a(std::size_t(PW) * (H + 2), kInf);
    // Runs of fluid pixels per row, [x0, x1) in padded columns: the fluid set
    // never changes, so only these are ever updated.
    std::vector<std::vector<std::pair<int, int>>> runs(H);
    forEachRow(H, [&](int y) {
        const float* in = &depth.pixels[std::size_t(y) * W];
        std::copy(in, in + W, &a[std::size_t(y + 1) * PW + 1]);
        for (int x = 0; x < W;) {
            if (!isFluid(in[x])) {
                ++x;
                continue;
            }
            const int x0 = x;
            while (x < W && isFluid(in[x])) ++x;
            runs[y].emplace_back(x0 + 1, x + 1);
        }
    });
    std::vector<float> b = a;

    for (int it = 0; it < p.iterations; ++it) {
        forEachRow(H, [&](int y) {
            const std::size_t row = std::size_t(y + 1) * PW;
            for (const auto& [x0, x1] : runs[y])
                flowSpan(&a[row - PW], &a[row], &a[row + PW], &b[row], x0, x1, 1.0f / f, thr, p.alpha);
        });
        std::swap(a, b);
    }

    Image<float> out(W, H);
    forEachRow(H, [&](int y) {
        const float* src = &a[std::size_t(y + 1) * PW + 1];
        std::copy(src, src + W, &out.pixels[std::size_t(y) * W]);
    });
    return out;
}

}  // namespace meniscus::cpu
