// Particle-set queries: bounds, the default radius (the volume-equivalent
// radius of the bulk number density, see docs/radius.md), attribute
// statistics, NaN removal.
#include "meniscus/particles.h"

#include "core/hash_grid.h"
#include "meniscus/particle_view.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

namespace meniscus {

Bounds computeBounds(std::span<const glm::vec3> positions) {
    Bounds b;
    for (const auto& p : positions) b.extend(p);
    return b;
}

namespace {

using detail::cubicKernel;
using detail::HashGrid;

// The q-quantile (0..1, nearest rank) of v; v is reordered.
template <class T>
T quantileOf(std::vector<T>& v, double q) {
    const std::size_t k = std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return v[k];
}


// Queries per pass: every particle up to this many, else an even stride (a
// median and a quantile need no more; it keeps 1 M particles under a second).
constexpr std::size_t kMaxQueries = std::size_t(1) << 16;
// The kernel's support in median nearest-neighbour distances (about two mean
// spacings in a liquid, where the nearest neighbour sits at ~0.8 spacings).
constexpr double kSupportNN = 2.5;
// The bulk is the densest part: this quantile of the per-particle densities.
constexpr double kBulkQuantile = 0.75;
// Below this many neighbours within the support at the 90th percentile there
// is no bulk to measure (a single sheet, a spray): nearest-neighbour method.
constexpr std::uint32_t kMinBulkNeighbours = 24;

bool usablePosition(const glm::vec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) &&
           std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) <= kMaxCoordinateM;
}

}  // namespace

Status checkCoordinates(std::span<const glm::vec3> positions, const std::string& name) {
    float largest = 0.0f;
    for (const glm::vec3& p : positions)
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
            largest = std::max({largest, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    if (largest <= kMaxCoordinateM) return okStatus();
    char msg[200];
    std::snprintf(msg, sizeof msg,
                  "coordinates reach %.3g m, beyond the %.0e m single-precision rendering can handle "
                  "(squared distances overflow); rescale the data",
                  double(largest), double(kMaxCoordinateM));
    return makeError(name, msg);
}

Status checkRadius(float radiusM) {
    if (radiusM >= kMinRadiusM && radiusM <= kMaxRadiusM) return okStatus();
    char msg[160];
    std::snprintf(msg, sizeof msg, "particle radius %.3g m is out of range: it must be between %.0e and %.0e metres",
                  double(radiusM), double(kMinRadiusM), double(kMaxRadiusM));
    return makeError("", msg);
}

std::string RadiusEstimate::describe() const {
    char head[64];
    std::snprintf(head, sizeof head, "%.4g m (", double(radius));
    char body[256];
    switch (method) {
        case RadiusMethod::FileAttribute:
            std::snprintf(body, sizeof body, "the file's '%s' attribute, median)", attribute.c_str());
            break;
        case RadiusMethod::BulkDensity:
            std::snprintf(body, sizeof body, "half the spacing at the bulk number density %.4g /m^3", bulkNumberDensity);
            break;
        case RadiusMethod::NearestNeighbour:
            std::snprintf(body, sizeof body, "half the median nearest-neighbour distance; too few neighbours for a density");
            break;
        case RadiusMethod::Fallback:
            std::snprintf(body, sizeof body, "1%% of the bounds diagonal; too few particles to estimate, set --radius)");
            break;
    }
    std::string s = std::string(head) + body;
    if (method == RadiusMethod::BulkDensity || method == RadiusMethod::NearestNeighbour) {
        if (isolated > 0) s += "; " + std::to_string(isolated) + " isolated particles ignored";
        s += ")";
    }
    return s;
}

RadiusEstimate estimateRadius(std::span<const glm::vec3> positions) {
    RadiusEstimate est;
    std::vector<glm::vec3> pts;
    pts.reserve(positions.size());
    for (const glm::vec3& p : positions)
        if (usablePosition(p)) pts.push_back(p);
    const Bounds b = computeBounds(pts);
    const double diag = b.empty() ? 0.0 : glm::length(glm::dvec3(b.extent()));
    const auto fallback = [&] {
        est.method = RadiusMethod::Fallback;
        est.fallback = true;
        est.radius = diag > 0.0 ? float(0.01 * diag) : 0.01f;
        return est;
    };
    if (pts.size() < 2 || !(diag > 0.0)) return fallback();

    // Queries: every particle, or an even stride of them for very large sets.
    const std::size_t n = pts.size();
    const std::size_t stride = std::max<std::size_t>(1, (n + kMaxQueries - 1) / kMaxQueries);
    const std::size_t queries = (n + stride - 1) / stride;
    const auto query = [&](std::size_t q) { return pts[q * stride]; };

    // First cell size: the mean spacing if the points inside the central 98%
    // of each axis filled their box (outliers cannot inflate it), in double so
    // a tiny extent cannot underflow. Too small a cell only costs a retry.
    std::array<std::vector<float>, 3> axis;
    for (int a = 0; a < 3; ++a) {
        axis[a].resize(queries);
        for (std::size_t q = 0; q < queries; ++q) axis[a][q] = query(q)[a];
    }
    glm::dvec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
        lo[a] = quantileOf(axis[a], 0.01);
        hi[a] = quantileOf(axis[a], 0.99);
    }
    glm::dvec3 ext = hi - lo;
    if (!(std::max({ext.x, ext.y, ext.z}) > 0.0)) ext = glm::dvec3(b.extent());
    const double longest = std::max({ext.x, ext.y, ext.z});
    ext = glm::max(ext, glm::dvec3(1e-3 * longest));
    double cell = std::cbrt(ext.x * ext.y * ext.z / double(n));
    const glm::dvec3 origin(b.min);

    // Nearest neighbours: median over the queries, isolated ones (nothing
    // within two rings of cells) counting as long without being measured.
    const float minDist = float(1e-7 * longest);  // closer than this counts as the same point
    std::vector<float> nn(queries);
    for (int attempt = 0; attempt < 64 && !(est.medianNeighbourDistance > 0.0f); ++attempt, cell *= 2.0) {
        if (!(cell > 0.0) || !std::isfinite(cell)) break;
        const HashGrid grid(pts, cell, origin);
        const auto& local = grid.points();
        tbb::parallel_for(std::size_t(0), queries,
                          [&](std::size_t q) { nn[q] = grid.nearest(local[q * stride], minDist, 2); });
        std::vector<float> found;
        found.reserve(queries);
        for (float d : nn)
            if (std::isfinite(d)) found.push_back(d);
        const std::size_t mid = (queries - 1) / 2;
        if (mid < found.size()) {
            std::nth_element(found.begin(), found.begin() + std::ptrdiff_t(mid), found.end());
            est.medianNeighbourDistance = found[mid];
        }
    }
    if (!(est.medianNeighbourDistance > 0.0f)) return fallback();
    est.method = RadiusMethod::NearestNeighbour;
    est.radius = 0.5f * est.medianNeighbourDistance;

    // SPH number density around each query with the kernel's support H.
    const double H = kSupportNN * double(est.medianNeighbourDistance);
    const float H2 = float(H * H);
    const HashGrid grid(pts, H, origin);
    std::vector<double> density(queries);
    std::vector<std::uint32_t> neighbours(queries);
    tbb::parallel_for(std::size_t(0), queries, [&](std::size_t q) {
        double sum = 0.0;
        std::uint32_t count = 0;
        grid.forNear(grid.points()[q * stride], H2, [&](float d2) {
            sum += cubicKernel(std::sqrt(double(d2)), H);
            ++count;
        });
        density[q] = sum;
        neighbours[q] = count - 1;  // not itself
    });
    std::vector<double> bulk;
    std::vector<std::uint32_t> bulkNeighbours;
    for (std::size_t q = 0; q < queries; ++q) {
        if (neighbours[q] == 0) continue;
        bulk.push_back(density[q]);
        bulkNeighbours.push_back(neighbours[q]);
    }
    // Isolated particles (nothing else within H), counted over the whole set:
    // most find a neighbour in their own cell at once.
    std::vector<std::uint8_t> alone(n);
    const auto& all = grid.points();
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        const glm::vec3& p = all[i];  // by reference: itself is told apart by address
        const HashGrid::Key c = grid.cellOf(p);
        bool found = false;
        for (int k = 0; k < 27 && !found; ++k)
            grid.forCell({c[0] + k % 3 - 1, c[1] + k / 3 % 3 - 1, c[2] + k / 9 - 1}, [&](const glm::vec3& o) {
                const glm::vec3 d = o - p;
                const float d2 = glm::dot(d, d);
                found = found || (d2 < H2 && (d2 > 0.0f || &o != &p));
            });
        alone[i] = !found;
    });
    for (std::uint8_t a : alone) est.isolated += a;
    if (bulk.empty() || quantileOf(bulkNeighbours, 0.9) < kMinBulkNeighbours) return est;
    est.bulkNumberDensity = quantileOf(bulk, kBulkQuantile);
    est.radius = float(0.5 / std::cbrt(est.bulkNumberDensity));
    est.method = RadiusMethod::BulkDensity;
    return est;
}

RadiusEstimate defaultRadius(const ParticleSet& set) {
    for (std::string_view name : kAttrRadiusNames) {
        const Attribute* a = set.find(name);
        if (!a || a->components != 1) continue;
        const auto stats = attributeStats(set, name);
        if (!stats || !checkRadius(float(stats->median)).ok()) continue;
        RadiusEstimate est;
        est.radius = float(stats->median);
        est.method = RadiusMethod::FileAttribute;
        est.attribute = std::string(name);
        return est;
    }
    return estimateRadius(set.positions);
}

Result<std::string> addRadiusFromSmoothingLength(ParticleSet& set, float hPerSpacing) {
    if (!(hPerSpacing > 0.0f) || !std::isfinite(hPerSpacing))
        return makeError("", "the smoothing length per particle spacing must be a positive number, not " +
                                 std::to_string(hPerSpacing));
    for (std::string_view name : kAttrRadiusNames)
        if (set.find(name)) return std::string();
    for (std::string_view name : kAttrSmoothingLengthNames) {
        const Attribute* h = set.find(name);
        if (!h || h->type != AttributeType::Float || h->components != 1 || h->floats.size() != set.size()) continue;
        const float toRadius = 1.0f / (2.0f * hPerSpacing);
        std::vector<float> radius(h->floats.size());
        for (std::size_t i = 0; i < radius.size(); ++i) radius[i] = h->floats[i] * toRadius;
        set.attributes.push_back({std::string(kAttrRadiusNames[0]), AttributeType::Float, 1, std::move(radius), {}});
        return std::string(name);
    }
    return std::string();
}

std::optional<MinMedianMax> attributeStats(const ParticleSet& set, std::string_view name, int component) {
    const Attribute* a = set.find(name);
    if (!a || component < 0 || component >= a->components || a->count() == 0) return std::nullopt;
    std::vector<double> v(a->count());
    for (std::size_t i = 0; i < v.size(); ++i) {
        const std::size_t k = i * std::size_t(a->components) + std::size_t(component);
        v[i] = a->type == AttributeType::Float ? double(a->floats[k]) : double(a->ints[k]);
    }
    MinMedianMax s;
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    s.min = *lo;
    s.max = *hi;
    // numpy's median: the middle value, or the mean of the two middle values.
    const std::size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(mid), v.end());
    s.median = v[mid];
    if (v.size() % 2 == 0) s.median = 0.5 * (s.median + *std::max_element(v.begin(), v.begin() + std::ptrdiff_t(mid)));
    return s;
}

std::size_t dropNonFinite(ParticleSet& set) {
    const std::size_t n = set.size();
    std::vector<std::size_t> keep;
    keep.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3& p = set.positions[i];
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) keep.push_back(i);
    }
    if (keep.size() == n) return 0;
    auto compact = [&](auto& values, std::size_t comps) {
        for (std::size_t j = 0; j < keep.size(); ++j)
            for (std::size_t c = 0; c < comps; ++c) values[j * comps + c] = values[keep[j] * comps + c];
        values.resize(keep.size() * comps);
    };
    compact(set.positions, 1);
    for (Attribute& a : set.attributes) {
        if (a.type == AttributeType::Float)
            compact(a.floats, std::size_t(a.components));
        else
            compact(a.ints, std::size_t(a.components));
    }
    return n - keep.size();
}

}  // namespace meniscus
