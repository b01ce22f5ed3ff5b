// relativeDensity and classifySpray (spray.h).
#include "core/spray.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "core/hash_grid.h"

namespace meniscus {

namespace {

// The cubic spline's sum at a point of a simple cubic lattice of spacing 2r,
// support 4r, times the rest volume (2r)^3: the SPH estimate's value in the bulk.
double latticeSum(double r) {
    const double H = 4.0 * r, s = 2.0 * r;
    double sum = 0.0;
    for (int i = -2; i <= 2; ++i)
        for (int j = -2; j <= 2; ++j)
            for (int k = -2; k <= 2; ++k)
                sum += detail::cubicKernel(s * std::sqrt(double(i * i + j * j + k * k)), H);
    return sum * s * s * s;
}

}  // namespace

std::vector<float> relativeDensity(const ParticleView& particles, float radiusM, float restDensityKgM3) {
    const std::size_t n = particles.size();
    std::vector<float> rel(n, 0.0f);
    if (n == 0) return rel;
    if (particles.density.present() && particles.density.count == n) {
        double rest = restDensityKgM3;
        if (!(rest > 0.0)) {
            std::vector<float> d(n);
            for (std::size_t i = 0; i < n; ++i) d[i] = particles.density[i];
            std::nth_element(d.begin(), d.begin() + std::ptrdiff_t(n / 2), d.end());
            rest = d[n / 2];
        }
        if (!(rest > 0.0) || !std::isfinite(rest)) return std::vector<float>(n, 1.0f);  // no usable scale: no spray
        for (std::size_t i = 0; i < n; ++i) rel[i] = float(double(particles.density[i]) / rest);
        return rel;
    }
    // The SPH estimate over the neighbours within H = 4 r.
    std::vector<glm::vec3> pts(n);
    for (std::size_t i = 0; i < n; ++i) pts[i] = particles.positions[i];
    const double r = radiusM, H = 4.0 * r, vol = 8.0 * r * r * r, norm = 1.0 / latticeSum(r);
    const float H2 = float(H * H);
    const detail::HashGrid grid(pts, H, glm::dvec3(pts[0]));
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        double sum = 0.0;
        grid.forNear(pts[i], H2, [&](float d2) { sum += detail::cubicKernel(std::sqrt(double(d2)), H); });
        rel[i] = float(sum * vol * norm);
    });
    return rel;
}

std::vector<std::uint8_t> classifySpray(const ParticleView& particles, float radiusM, const SprayParams& params) {
    const std::vector<float> rel = relativeDensity(particles, radiusM, params.restDensityKgM3);
    std::vector<std::uint8_t> spray(rel.size());
    for (std::size_t i = 0; i < rel.size(); ++i) spray[i] = rel[i] < params.sprayDensity;
    return spray;
}

}  // namespace meniscus
