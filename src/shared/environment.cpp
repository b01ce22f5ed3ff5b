// The host half of the environment map's irradiance (src/shared/environment.h):
// the projection of a map on the spherical harmonics of bands l <= 2 and
// their convolution with the clamped cosine, Ramamoorthi & Hanrahan 2001,
// "An Efficient Representation for Irradiance Environment Maps".
#include "shared/environment.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace meniscus::shared {

void environmentIrradianceSh(const float* texels, int width, int height, float rotation, float intensity,
                             vec3 out[9]) {
    for (int k = 0; k < 9; ++k) out[k] = vec3(0.0f);
    if (!texels || width <= 0 || height <= 0) return;
    constexpr double pi = std::numbers::pi;
    // L_lm = sum of L(d) Y_lm(d) dw over the texels, d the texel centre's
    // direction (as seen: the map turned by `rotation`, environment.h's
    // convention inverted), dw its exact solid angle, the integral of
    // sin(theta) dtheta dphi over it: (cos theta0 - cos theta1) 2 pi / W.
    double sum[9][3] = {};
    const double dphi = 2.0 * pi / double(width);
    // The columns' azimuths, once (not per texel).
    std::vector<double> sinPhi(static_cast<std::size_t>(width)), cosPhi(static_cast<std::size_t>(width));
    for (int i = 0; i < width; ++i) {
        const double u = (double(i) + 0.5) / double(width);
        const double phi = 2.0 * pi * (u - 0.5 + double(rotation));
        sinPhi[std::size_t(i)] = std::sin(phi);
        cosPhi[std::size_t(i)] = std::cos(phi);
    }
    for (int j = 0; j < height; ++j) {
        const double t0 = pi * double(j) / double(height), t1 = pi * double(j + 1) / double(height);
        const double theta = pi * (double(j) + 0.5) / double(height);
        const double dw = (std::cos(t0) - std::cos(t1)) * dphi;
        const double st = std::sin(theta), ct = std::cos(theta);
        double row[9][3] = {};
        for (int i = 0; i < width; ++i) {
            const float x = float(st * sinPhi[std::size_t(i)]), y = float(ct);
            const float z = float(-st * cosPhi[std::size_t(i)]);
            const float* t = texels + 3 * (std::size_t(j) * std::size_t(width) + std::size_t(i));
            for (int k = 0; k < 9; ++k) {
                const double b = environmentShBasis(k, x, y, z);
                row[k][0] += b * t[0];
                row[k][1] += b * t[1];
                row[k][2] += b * t[2];
            }
        }
        for (int k = 0; k < 9; ++k)
            for (int c = 0; c < 3; ++c) sum[k][c] += row[k][c] * dw;
    }
    // The clamped cosine's band factors A_l (their eq. 8-9): pi, 2 pi / 3, pi / 4.
    const double band[9] = {pi, 2.0 * pi / 3.0, 2.0 * pi / 3.0, 2.0 * pi / 3.0, pi / 4.0,
                            pi / 4.0, pi / 4.0, pi / 4.0, pi / 4.0};
    for (int k = 0; k < 9; ++k)
        out[k] = vec3(float(band[k] * sum[k][0] * intensity), float(band[k] * sum[k][1] * intensity),
                      float(band[k] * sum[k][2] * intensity));
}

}  // namespace meniscus::shared
