// Screen-space curvature flow's formulas: van der Laan, Green & Sainz, "Screen
// Space Fluid Rendering with Curvature Flow", I3D 2009 (NVIDIA patent US
// 8,947,430, eqs. 3-12), as restated in docs/pipeline.md#curvature-flow;
// written once for C++ and GLSL like hole_fill.h: src/cpu/filter_curvature_flow.cpp
// and shaders/filter_curvature_flow.comp both take one Jacobi step of a pixel
// with curvatureFlowStep, so they give the same bits (`precise` in GLSL: no
// FMA contraction or reassociation).
//
// With Cx = Cy = C = 1/f (f: the focal length in pixels) and central pixel
// differences z_x, z_y, z_xx, z_yy, z_xy of the eye depth z (metres):
//   D  = Cy² z_x² + Cx² z_y² + Cx² Cy² z²
//   Ex = ½ z_x ∂D/∂x − z_xx D,   Ey = ½ z_y ∂D/∂y − z_yy D
//   2H = (Cy Ex + Cx Ey) / D^{3/2}
//   z ← z − Δt·H,   Δt = alpha·z/f   (per pixel)
// z is positive eye depth here; the papers use negative view z and write "+".
// Linearised, H ≈ −(f/2z)(z_xx + z_yy), so the update is z += (alpha/2)·∇²z:
// explicit Euler is stable for alpha ≤ 0.5 (0.4 default; 0.55 diverges).
//
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
//    neighbours are within the jump threshold of the centre (a +inf neighbour
//    never is); likewise y; z_xy is zero unless both of those hold and all
//    four diagonal neighbours are within the threshold too, so separate
//    patches never blend and silhouettes neither shrink nor grow.
//  - The normal behind D, (−Cy z_x, −Cx z_y, Cx Cy z), drops the terms that carry
//    the pixel's ray direction, so a tilted plane has a tiny H ~ C·slope²: it
//    drifts by ~1e-5 of its depth in 40 iterations (see the plane test).
// Branch-free (differences computed, then selected), so the CPU's span loop
// vectorises.
#ifndef MENISCUS_SHARED_CURVATURE_FLOW_H
#define MENISCUS_SHARED_CURVATURE_FLOW_H

#ifdef __cplusplus
#include <cmath>
namespace meniscus::shared {
using std::abs;
using std::sqrt;
#define MENISCUS_CF_INLINE inline
#define MENISCUS_CF_EXACT const
// Both tests evaluated, `&` on bools: GCC if-converts them and vectorises the
// CPU's loop, which it does not with the mixed masks `&&` leaves.
#define MENISCUS_CF_AND(a, b) ((a) & (b))
#else
#define MENISCUS_CF_INLINE
#define MENISCUS_CF_EXACT precise
#define MENISCUS_CF_AND(a, b) ((a) && (b))
#endif

// Whether the neighbour depth a continues the surface of the centre depth z:
// |a − z| <= thr, false for a +inf neighbour and for a +inf centre (NaN).
MENISCUS_CF_INLINE bool curvatureFlowNear(float a, float z, float thr) {
    MENISCUS_CF_EXACT float e = abs(a - z);
    return e <= thr;
}

// One explicit Euler step of the pixel of depth z (finite) from its 3×3
// neighbourhood (l, r: left and right; u, d: the rows above and below; ul,
// ur, dl, dr the corners): z − Δt·H. C = 1/f, thr: the jump threshold in
// metres, alpha: the time-step factor.
MENISCUS_CF_INLINE float curvatureFlowStep(float z, float zl, float zr, float zu, float zd, float zul, float zur,
                                           float zdl, float zdr, float C, float thr, float alpha) {
    const bool vx = MENISCUS_CF_AND(curvatureFlowNear(zl, z, thr), curvatureFlowNear(zr, z, thr));
    const bool vy = MENISCUS_CF_AND(curvatureFlowNear(zu, z, thr), curvatureFlowNear(zd, z, thr));
    const bool up = MENISCUS_CF_AND(curvatureFlowNear(zul, z, thr), curvatureFlowNear(zur, z, thr));
    const bool down = MENISCUS_CF_AND(curvatureFlowNear(zdl, z, thr), curvatureFlowNear(zdr, z, thr));
    const bool corners = MENISCUS_CF_AND(up, down);
    const bool vxy = MENISCUS_CF_AND(MENISCUS_CF_AND(vx, vy), corners);
    // Differences are computed unconditionally, then selected (branch-free).
    MENISCUS_CF_EXACT float px = vx ? 0.5f * (zr - zl) : 0.0f;
    MENISCUS_CF_EXACT float pxx = vx ? (zr + zl - 2.0f * z) : 0.0f;
    MENISCUS_CF_EXACT float py = vy ? 0.5f * (zd - zu) : 0.0f;
    MENISCUS_CF_EXACT float pyy = vy ? (zd + zu - 2.0f * z) : 0.0f;
    MENISCUS_CF_EXACT float pxy = vxy ? 0.25f * ((zdr - zdl) - (zur - zul)) : 0.0f;
    MENISCUS_CF_EXACT float w = C * z;
    MENISCUS_CF_EXACT float G = px * px + py * py + w * w;
    MENISCUS_CF_EXACT float Gx = 2.0f * (px * pxx + py * pxy + C * w * px);
    MENISCUS_CF_EXACT float Gy = 2.0f * (px * pxy + py * pyy + C * w * py);
    MENISCUS_CF_EXACT float num = 0.5f * (px * Gx + py * Gy) - (pxx + pyy) * G;  // 2H = num / G^{3/2}
    // z − Δt·H with Δt = alpha·w and H = num / (2 G^{3/2}).
    MENISCUS_CF_EXACT float halfAlpha = 0.5f * alpha;
    MENISCUS_CF_EXACT float zNew = z - halfAlpha * w * num / (G * sqrt(G));
    return zNew;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_CF_INLINE
#undef MENISCUS_CF_EXACT
#undef MENISCUS_CF_AND

#endif  // MENISCUS_SHARED_CURVATURE_FLOW_H
