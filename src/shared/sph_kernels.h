// The cubic spline kernel of SPH, written once for C++ and GLSL: the
// renderer's ray cast and its field grid (shared/sph_surface.h,
// core/sph_field.cpp, gl/shaders/raycast.comp), the radius estimate and the
// spray's density (core/hash_grid.h), the mesher's SPH field
// (surface/field.h) and the simulator (sim/kernels.h) all evaluate these
// functions and no copy of them (docs/surface.md, docs/simulation.md).
//
// Monaghan 1992, in the normalisation of Koschier et al.'s SPH tutorial
// (Eurographics 2019) and SPlisHSPlasH, with support radius h and q = d / h:
//   w(q) = 6 q^2 (q - 1) + 1     for q <= 1/2,
//          2 (1 - q)^3           for 1/2 < q < 1, and 0 beyond;
//   W(d) = sigma w(d / h), sigma = 8 / (pi h^3), integrates to 1 over the ball;
//   g(q) = w'(q) / q = 18 q - 12 for q <= 1/2, -6 (1 - q)^2 / q beyond
//          (finite at q = 0), so grad W at the offset x = sigma / h^2 g(q) x.
// Callers test the support (q < 1) themselves: in [0, 1) the functions are
// exact to the formulas above, and the renderer's field, which needs no
// normalisation, uses w and g as they are (w(0) = 1).
//
// In C++ they are templates (float for the renderer, mesher and simulator,
// double for the radius estimate); in GLSL Real is float. The same
// operations in the same order in both languages, so the backends agree bit
// for bit (GLSL `precise` keeps the driver from fusing them).
#ifndef MENISCUS_SHARED_SPH_KERNELS_H
#define MENISCUS_SHARED_SPH_KERNELS_H

#ifdef __cplusplus
namespace meniscus::shared {
#define MENISCUS_SPH_KERNEL(ret) template <class Real> inline ret
#define MENISCUS_SPH_KERNEL_EXACT const
#else
#define Real float
#define MENISCUS_SPH_KERNEL(ret) ret
#define MENISCUS_SPH_KERNEL_EXACT precise
#endif

// w(q), q in [0, 1).
MENISCUS_SPH_KERNEL(Real) sphKernel(Real q) {
    MENISCUS_SPH_KERNEL_EXACT Real a = Real(1) - q;
    MENISCUS_SPH_KERNEL_EXACT Real inner = Real(6) * q * q * (q - Real(1)) + Real(1);
    MENISCUS_SPH_KERNEL_EXACT Real outer = Real(2) * a * a * a;
    return q <= Real(0.5) ? inner : outer;
}

// g(q) = w'(q) / q, q in [0, 1).
MENISCUS_SPH_KERNEL(Real) sphKernelGradient(Real q) {
    MENISCUS_SPH_KERNEL_EXACT Real a = Real(1) - q;
    MENISCUS_SPH_KERNEL_EXACT Real inner = Real(18) * q - Real(12);
    MENISCUS_SPH_KERNEL_EXACT Real outer = Real(-6) * a * a / (q > Real(0.5) ? q : Real(1));
    return q <= Real(0.5) ? inner : outer;
}

#ifdef __cplusplus
// sigma = 8 / (pi h^3), the factor that makes sigma w(d / h) integrate to 1.
template <class Real>
inline Real sphKernelSigma(Real h) {
    return Real(8) / (Real(3.14159265358979323846) * h * h * h);
}
}  // namespace meniscus::shared
#else
#undef Real
#endif
#undef MENISCUS_SPH_KERNEL
#undef MENISCUS_SPH_KERNEL_EXACT

#endif
