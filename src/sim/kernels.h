// SPH smoothing kernels, all with compact support h (the neighbour radius).
//  - CubicSpline: Monaghan 1992, in the normalisation of Koschier et al.'s SPH
//    tutorial (Eurographics 2019) and SPlisHSPlasH, from shared/sph_kernels.h
//    (the renderer and the mesher evaluate the same functions); DFSPH and PBF
//    use it.
//  - Poly6, Spiky (gradient), Viscosity (Laplacian): Muller, Charypar & Gross
//    2003, §3.5 and §4; the SPH solver uses them.
// Each kernel integrates to 1 over its support (tests/sim_kernels_test.cpp).
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "shared/sph_kernels.h"
#include "sim/packed.h"

namespace meniscus::sim {

inline constexpr float kPi = 3.14159265358979323846f;

// The cubic spline of shared/sph_kernels.h at support h: W(r) = sigma w(r/h),
// grad W(d) = sigma / h^2 g(r/h) d.
class CubicSpline {
public:
    explicit CubicSpline(float h)
        : h_(h), invH_(1.0f / h), k_(shared::sphKernelSigma(h)), g_(shared::sphKernelSigma(h) / (h * h)) {}
    float support() const { return h_; }
    float W(float r) const {
        const float q = r * invH_;
        return q < 1.0f ? k_ * shared::sphKernel(q) : 0.0f;
    }
    // grad W of the offset d = x_i - x_j (|d| = r) is gradFactor(r) * d.
    float gradFactor(float r) const {
        const float q = r * invH_;
        if (q >= 1.0f || r < 1e-9f * h_) return 0.0f;
        return g_ * shared::sphKernelGradient(q);
    }
    glm::vec3 gradW(const glm::vec3& d, float r) const { return gradFactor(r) * d; }
    // W and gradFactor of four distances at once (the neighbour build's),
    // shared::sphKernel and sphKernelGradient lane by lane, the same
    // operations in the same order as the two above: equal bit for bit.
    void evaluate4(F4 r, F4& w, F4& g) const {
        const F4 q = r * splat(invH_), a = splat(1.0f) - q, one = splat(1.0f);
        const F4 inside = less(q, one), inner = lessEq(q, splat(0.5f));
        const F4 wIn = ((splat(6.0f) * q) * q) * (q - one) + one;
        const F4 wOut = ((splat(2.0f) * a) * a) * a;
        w = select(inside, splat(k_) * select(inner, wIn, wOut), zero4());
        const F4 gIn = splat(18.0f) * q - splat(12.0f);
        const F4 gOut = ((splat(-6.0f) * a) * a) / select(inner, one, q);
        g = select(both(inside, lessEq(splat(1e-9f * h_), r)), splat(g_) * select(inner, gIn, gOut), zero4());
    }

private:
    float h_, invH_, k_, g_;
};

class MullerKernels {
public:
    explicit MullerKernels(float h)
        : h_(h), h2_(h * h), poly6_(315.0f / (64.0f * kPi * std::pow(h, 9.0f))),
          poly6Grad_(-945.0f / (32.0f * kPi * std::pow(h, 9.0f))),
          spiky_(15.0f / (kPi * std::pow(h, 6.0f))), spikyGrad_(-45.0f / (kPi * std::pow(h, 6.0f))),
          viscosity_(15.0f / (2.0f * kPi * h * h * h)), viscosityLap_(45.0f / (kPi * std::pow(h, 6.0f))) {}
    float support() const { return h_; }

    // Density kernel, eq. (20).
    float poly6(float r2) const {
        if (r2 >= h2_) return 0.0f;
        const float a = h2_ - r2;
        return poly6_ * a * a * a;
    }
    // Its gradient and Laplacian (the colour field of §4.4).
    glm::vec3 poly6Grad(const glm::vec3& d, float r2) const {
        if (r2 >= h2_) return glm::vec3(0.0f);
        const float a = h2_ - r2;
        return (poly6Grad_ * a * a) * d;
    }
    float poly6Lap(float r2) const {
        if (r2 >= h2_) return 0.0f;
        const float a = h2_ - r2;
        return poly6Grad_ * a * (3.0f * h2_ - 7.0f * r2);
    }
    // Pressure kernel, eq. (21): W itself (for the integral test) and its gradient.
    float spiky(float r) const {
        if (r >= h_) return 0.0f;
        const float a = h_ - r;
        return spiky_ * a * a * a;
    }
    // Its gradient at the offset d (|d| = r) is spikyGradFactor(r) * d.
    float spikyGradFactor(float r) const {
        if (r >= h_ || r < 1e-9f * h_) return 0.0f;
        const float a = h_ - r;
        return spikyGrad_ * a * a / r;
    }
    glm::vec3 spikyGrad(const glm::vec3& d, float r) const { return spikyGradFactor(r) * d; }
    // spiky and spikyGradFactor of four distances at once, equal bit for bit.
    void spiky4(F4 r, F4& w, F4& g) const {
        const F4 a = splat(h_) - r, inside = less(r, splat(h_));
        w = select(inside, ((splat(spiky_) * a) * a) * a, zero4());
        g = select(both(inside, lessEq(splat(1e-9f * h_), r)), ((splat(spikyGrad_) * a) * a) / r, zero4());
    }
    // Viscosity kernel, eq. (22), and its Laplacian.
    float viscosity(float r) const {
        if (r >= h_ || r < 1e-9f * h_) return 0.0f;
        const float q = r / h_;
        return viscosity_ * (-0.5f * q * q * q + q * q + 0.5f / q - 1.0f);
    }
    float viscosityLap(float r) const { return r >= h_ ? 0.0f : viscosityLap_ * (h_ - r); }

private:
    float h_, h2_, poly6_, poly6Grad_, spiky_, spikyGrad_, viscosity_, viscosityLap_;
};

}  // namespace meniscus::sim
