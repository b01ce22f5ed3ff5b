// Screen-space curvature flow: van der Laan, Green & Sainz, "Screen Space Fluid
// Rendering with Curvature Flow", I3D 2009 (NVIDIA patent US 8,947,430, eqs.
// 3-12), exactly as restated in docs/pipeline.md#curvature-flow. The formula
// of one step (D = C²G with G = z_x² + z_y² + (Cz)², analytic ∂D,
// z ← z − Δt·H, Δt = alpha·z/f) and its discontinuity rules are
// src/shared/curvature_flow.h, which the GL twin calls too; this file runs
// them over the image.
//
// Parameters (CurvatureFlowParams): iterations (count), alpha (dimensionless
// time-step factor), jumpRadii (discontinuity threshold in particle radii r).
//
// Choices:
//  - The image border counts as "no fluid" (a +inf frame around a padded
//    copy), so the stencil needs no bounds tests. +inf pixels stay +inf.
//  - Jacobi iterations (double-buffered), each output pixel a pure function of
//    the previous buffer: bit-identical for any thread count. Only runs of
//    fluid pixels are visited (the fluid set never changes); the inner loop is
//    branch-free so the compiler can vectorise it, compiled twice (GCC
//    target_clones: AVX2 and the SSE2 baseline, chosen at run time; the same
//    IEEE operations, no FMA, so the same output on every x86-64 machine).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "cpu/filter_util.h"
#include "cpu/filters.h"
#include "shared/curvature_flow.h"

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
        const float zNew = shared::curvatureFlowStep(z, zl, zr, zu, zd, zul, zur, zdl, zdr, C, thr, alpha);
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
