#include "core/sph_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <tbb/parallel_for.h>

#include "core/lanes.h"
#include "shared/sph_surface.h"

namespace meniscus {

namespace {

// SphField::quiet: per cell, the bound sum_j W(dist(x_j, box) / h) over the
// particles of the 27 cells around it, stopped as soon as it reaches iso.
void markQuietCells(SphField& out) {
    const detail::DenseGrid& g = out.grid;
    const glm::ivec3 dims = g.dims();
    const float cell = 1.0f / g.invCell(), invH = 1.0f / out.support, limit = out.isoRaw * (1.0f - 1e-4f);
    const std::vector<glm::vec3>& pts = g.points();
    std::vector<std::uint8_t> quiet(g.cellCount(), 0);
    tbb::parallel_for(0, dims.z, [&](int z) {
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x) {
                const glm::ivec3 c(x, y, z);
                glm::vec3 lo = g.lo() + glm::vec3(c) * cell, hi = lo + cell;
                for (int a = 0; a < 3; ++a) {  // the boundary cells hold everything beyond the box
                    if (c[a] == 0) lo[a] = -std::numeric_limits<float>::infinity();
                    if (c[a] == dims[a] - 1) hi[a] = std::numeric_limits<float>::infinity();
                }
                float bound = 0.0f;
                g.forRowsNear(c, 1, [&](std::uint32_t b, std::uint32_t e) {
                    for (std::uint32_t i = b; i < e && bound < limit; ++i) {
                        const glm::vec3 d = glm::max(glm::vec3(0.0f), glm::max(lo - pts[i], pts[i] - hi));
                        const float q = std::sqrt((d.x * d.x + d.y * d.y) + d.z * d.z) * invH;
                        if (q < 1.0f) bound += shared::sphKernel(q);
                    }
                });
                quiet[(std::size_t(z) * dims.y + y) * dims.x + x] = bound < limit;
            }
    });
    out.quiet.assign((quiet.size() + 31) / 32, 0u);
    for (std::size_t c = 0; c < quiet.size(); ++c) out.quiet[c >> 5] |= std::uint32_t(quiet[c]) << (c & 31);
}

}  // namespace

bool sphFieldQuiet(const SphField& field, const glm::vec3& p) {
    const glm::ivec3 c = field.grid.cellOf(p);
    const glm::ivec3 dims = field.grid.dims();
    const std::size_t i = (std::size_t(c.z) * dims.y + c.y) * dims.x + c.x;
    return (field.quiet[i >> 5] >> (i & 31)) & 1u;
}

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
    markQuietCells(out);
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

void evaluateSphField(const SphField& field, const glm::vec3& p, float& f, glm::vec3& grad) {
    using lanes::FloatV;
    using lanes::IntV;
    const float h2 = field.support * field.support, invH = 1.0f / field.support;
    const float *xs = field.xs.data(), *ys = field.ys.data(), *zs = field.zs.data();
    FloatV sum{}, gx{}, gy{}, gz{};
    const FloatV one = FloatV{} + 1.0f, lane = FloatV{0.0f, 1.0f, 2.0f, 3.0f};
    field.grid.forRowsNear(field.grid.cellOf(p), 1, [&](std::uint32_t b, std::uint32_t e) {
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
}

}  // namespace meniscus
