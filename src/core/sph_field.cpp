#include "core/sph_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/lanes.h"
#include "shared/sph_surface.h"

namespace meniscus {

bool buildSphField(std::span<const glm::vec3> positions, float radius, const RaycastParams& params, SphField& out) {
    out = SphField{};
    if (positions.empty()) return false;
    const float h = params.supportRadii * radius;
    // A few cells per particle at most (outliers fall into the boundary
    // cells, see DenseGrid::buildBounded), and never more than 2^24.
    const std::size_t maxCells = std::clamp<std::size_t>(4 * positions.size(), std::size_t(1) << 16, std::size_t(1) << 24);
    // Cells a hair larger than h, so that rounding in cellOf never puts two
    // points less than h apart two cells apart.
    if (!out.grid.buildBounded(positions, h * 1.0001f, maxCells)) return false;
    out.support = h;
    // Padding far beyond any query (its lanes are masked off anyway).
    const std::size_t n = out.grid.points().size();
    for (std::vector<float>* v : {&out.xs, &out.ys, &out.zs}) v->assign(n + lanes::kLanes - 1, 1e30f);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3& q = out.grid.points()[i];
        out.xs[i] = q.x, out.ys[i] = q.y, out.zs[i] = q.z;
    }
    out.isoRaw = float(double(params.iso) * shared::sphRestField(params.supportRadii));
    return true;
}

std::string checkRaycastParams(const RaycastParams& p) {
    if (!(p.iso > 0.0f && p.iso < 1.0f)) return "iso: above 0, below 1 (a fraction of the rest density)";
    if (!(p.supportRadii >= 2.0f && p.supportRadii <= 8.0f)) return "supportRadii: 2 to 8 particle radii";
    if (!(p.stepRadii >= 0.1f && p.stepRadii <= 4.0f)) return "stepRadii: 0.1 to 4 particle radii";
    if (p.maxSteps < 1 || p.maxSteps > 4096) return "maxSteps: 1 to 4096";
    if (p.newtonSteps < 0 || p.newtonSteps > 16) return "newtonSteps: 0 to 16";
    if (!(p.coverRadii >= 1.0f && p.coverRadii <= 4.0f)) return "coverRadii: 1 to 4 particle radii";
    return {};
}

float sphFieldLastInCell(const SphField& field, const glm::vec3& origin, const glm::vec3& dir, float t) {
    const detail::DenseGrid& g = field.grid;
    const glm::vec3 p = shared::sphRayPoint(origin, dir, t);
    const glm::vec3 u = (p - g.lo()) * g.invCell();
    const glm::ivec3 dims = g.dims();
    for (int a = 0; a < 3; ++a)
        if (!(u[a] >= 0.0f && u[a] < float(dims[a]))) return t;
    const float cell = 1.0f / g.invCell();
    float exit = std::numeric_limits<float>::infinity();
    for (int a = 0; a < 3; ++a) {
        const float c = std::floor(u[a]);
        if (dir[a] > 0.0f) exit = std::min(exit, (g.lo()[a] + (c + 1.0f) * cell - origin[a]) / dir[a]);
        if (dir[a] < 0.0f) exit = std::min(exit, (g.lo()[a] + c * cell - origin[a]) / dir[a]);
    }
    return exit - 1e-3f * cell / glm::length(dir);
}

bool evaluateSphField(const SphField& field, const glm::vec3& p, float& f, glm::vec3& grad) {
    bool none = true;
    using lanes::FloatV;
    using lanes::IntV;
    const float h2 = field.support * field.support, invH = 1.0f / field.support;
    const float *xs = field.xs.data(), *ys = field.ys.data(), *zs = field.zs.data();
    FloatV sum{}, gx{}, gy{}, gz{};
    const FloatV one = FloatV{} + 1.0f, lane = FloatV{0.0f, 1.0f, 2.0f, 3.0f};
    field.grid.forRowsNear(field.grid.cellOf(p), 1, [&](std::uint32_t b, std::uint32_t e) {
        none = none && b == e;
        for (std::uint32_t i = b; i < e; i += lanes::kLanes) {
            const FloatV dx = p.x - lanes::loadV(xs + i), dy = p.y - lanes::loadV(ys + i), dz = p.z - lanes::loadV(zs + i);
            const FloatV d2 = (dx * dx + dy * dy) + dz * dz;
            // In range: within h, and one of this row's points (not the next row's or the padding).
            const IntV in = (d2 < h2) & (lane < float(e - i));
            const FloatV q = lanes::sqrtV(d2) * invH;
            // shared::sphKernel and sphKernelGradient, lane by lane, the same operations.
            const FloatV a = 1.0f - q;
            const IntV near = q <= 0.5f;
            const FloatV w = near ? 6.0f * q * q * (q - 1.0f) + 1.0f : 2.0f * a * a * a;
            const FloatV g = near ? 18.0f * q - 12.0f : -6.0f * a * a / (q > 0.5f ? q : one);
            sum += lanes::selectV(in, w);
            gx += lanes::selectV(in, g * dx);
            gy += lanes::selectV(in, g * dy);
            gz += lanes::selectV(in, g * dz);
        }
    });
    f = (sum[0] + sum[1]) + (sum[2] + sum[3]);
    grad = glm::vec3((gx[0] + gx[1]) + (gx[2] + gx[3]), (gy[0] + gy[1]) + (gy[2] + gy[3]),
                     (gz[0] + gz[1]) + (gz[2] + gz[3]));
    return none;
}

}  // namespace meniscus
