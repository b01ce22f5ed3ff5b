// Diffuse particles from a fluid sequence: Ihmsen, Akinci, Akinci & Teschner,
// "Unified spray, foam and air bubbles for particle-based fluids", The Visual
// Computer 28 (CGI 2012). Section and equation numbers below are the paper's.
// Where the paper leaves a choice open we follow SPlisHSPlasH's FoamGenerator
// (Bender et al.'s implementation of the same paper), the peer:
//  - the potentials' kernel is the paper's W~(r) = 1 - r/h; the normals, the
//    densities and the advection's averaging use the cubic spline (support h);
//  - normals only for particles with at most `bubbleAbove` neighbours (the
//    surface; the curvature sums over those alone, see potentialsOf), new
//    diffuse particles only from fluid particles with at least
//    15 neighbours (an isolated drop's potentials are noise);
//  - automatic limits: 0.1 and 1 times the mean of the frames' maxima;
//  - the diffuse particles made from frame k move first at frame k + 1.
// Ours: the kinetic energy is per unit mass (|v|^2 / 2, J/kg), so limits do
// not depend on the particles' mass; the count per particle is rounded
// stochastically (floor + 1 with the fraction's probability) rather than to
// the nearest, so a potential of 0.4 particles per frame still makes some;
// every random number is a hash of (seed, frame, particle, index), so the
// output is the same for any thread count.
#include "meniscus/whitewater.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <new>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sim/kernels.h"
#include "sim/neighbour_search.h"

namespace meniscus::sim {

namespace {

constexpr int kMinGeneratingNeighbours = 15;  // FoamGenerator's
constexpr float kWaveCrestAlignment = 0.6f;   // eq. 7: v^ . n^ from which a crest counts
constexpr float kMovingMps = 0.05f;           // estimateFrameInterval: particles slower than this are left out

bool within(float v, float lo, float hi) { return v >= lo && v <= hi; }  // false for NaN

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Eq. 1: the potential I clamped to [lo, hi] and mapped to [0, 1].
float clampAndNormalise(float I, float lo, float hi) { return (std::min(I, hi) - std::min(I, lo)) / (hi - lo); }

// A uniform number in [0, 1) from its coordinates (splitmix64's finaliser
// over a combination of them): the same for any thread count or order.
float uniform01(std::uint64_t seed, std::int64_t frame, std::size_t particle, std::size_t k, unsigned channel) {
    std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL ^ std::uint64_t(frame) * 0xD1B54A32D192ED03ULL ^
                      std::uint64_t(particle) * 0xABC98388FB8FAC03ULL ^ std::uint64_t(k) * 0x8CB92BA72F3D8DD7ULL ^
                      std::uint64_t(channel) * 0x94D049BB133111EBULL;
    z += 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return float(z >> 40) * (1.0f / 16777216.0f);  // 24 bits: exactly representable, < 1
}

// Two unit vectors orthogonal to the unit vector v and to each other.
void orthogonalPair(const glm::vec3& v, glm::vec3& e1, glm::vec3& e2) {
    const glm::vec3 a = std::abs(v.x) > 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    e1 = glm::normalize(glm::cross(v, a));
    e2 = glm::cross(v, e1);
}

// The fluid's neighbour lists (cubic spline of support h) over a grid of its bounds.
struct FluidNeighbours {
    CellGrid grid;
    NeighbourLists lists;
    std::vector<float> wSum;  // sum of W over each list (self excluded)
};

Box boxOf(std::span<const glm::vec3> x) {
    Box b{glm::vec3(0.0f), glm::vec3(0.0f)};
    if (x.empty()) return b;
    b.min = b.max = x[0];
    for (const glm::vec3& p : x) b.min = glm::min(b.min, p), b.max = glm::max(b.max, p);
    return b;
}

void findFluidNeighbours(std::span<const glm::vec3> x, float h, FluidNeighbours& out) {
    out.grid.configure(boxOf(x), h);
    out.grid.build(x);
    const CubicSpline K(h);
    auto kernel = [&K](F4 r, F4& w, F4& g) { K.evaluate4(r, w, g); };
    out.wSum.resize(x.size());
    buildNeighbourLists(x, out.grid, h, true, kernel, out.lists, out.wSum);
}

std::vector<glm::vec3> copyOf(const StridedView<glm::vec3>& v) {
    std::vector<glm::vec3> out(v.count);
    for (std::size_t i = 0; i < v.count; ++i) out[i] = v[i];
    return out;
}

Status checkFluid(const ParticleView& fluid, float radiusM) {
    if (auto st = fluid.validate(); !st) return st;
    if (!fluid.velocity.present() && fluid.size() > 0)
        return makeError("", "the fluid has no velocity attribute: whitewater needs the particles' velocities");
    if (!(radiusM > 0.0f) || !std::isfinite(radiusM)) return makeError("", "the particle radius must be positive");
    return okStatus();
}

// The potentials (§4) of particles x with velocities v, over precomputed neighbours.
Potentials potentialsOf(std::span<const glm::vec3> x, std::span<const glm::vec3> v, const FluidNeighbours& nb,
                        float h, const WhitewaterParams& p) {
    const std::size_t n = x.size();
    const CubicSpline K(h);
    const float self = K.W(0.0f);
    Potentials out;
    out.trappedAir.assign(n, 0.0f);
    out.waveCrest.assign(n, 0.0f);
    out.energy.assign(n, 0.0f);
    out.neighbours.assign(n, 0u);
    // Normals from the colour field, n = -sum_j V_j grad W_ij with V_j = 1 /
    // (number density)_j (the mass cancels), only at the surface.
    std::vector<glm::vec3> normal(n, glm::vec3(0.0f));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            out.neighbours[i] = nb.lists.count(i);
            if (int(nb.lists.count(i)) > p.bubbleAbove) continue;
            glm::vec3 g(0.0f);
            for (const Neighbour& e : nb.lists.of(i)) g -= (e.g / (self + nb.wSum[e.j])) * (x[i] - x[e.j]);
            const float len = glm::length(g);
            if (len > 0.0f) normal[i] = g / len;
        }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            const glm::vec3 vi = v[i], ni = normal[i];
            float ta = 0.0f, kappa = 0.0f;
            for (const Neighbour& e : nb.lists.of(i)) {
                const glm::vec3 d = x[i] - x[e.j];
                const float r2 = glm::dot(d, d);
                if (!(r2 > 0.0f)) continue;
                const float rij = std::sqrt(r2);
                const float w = 1.0f - rij / h;  // W~, the paper's radially symmetric weight
                const glm::vec3 xhat = d / rij;
                // Eq. 2: relative speed, weighted by how much the two approach.
                const glm::vec3 vij = vi - v[e.j];
                const float speed = glm::length(vij);
                if (speed > 1e-6f) ta += speed * (1.0f - glm::dot(vij / speed, xhat)) * w;
                // Eq. 4-5: curvature from the surface neighbours behind it
                // (x^_ji . n_i < 0). Interior neighbours (no normal) are left
                // out: counted as 1 - n_i . 0 = 1 (as FoamGenerator does), they
                // would make every flat surface a crest.
                const glm::vec3 nj = normal[e.j];
                if (-glm::dot(xhat, ni) < 0.0f && nj != glm::vec3(0.0f)) kappa += (1.0f - glm::dot(ni, nj)) * w;
            }
            const float speed = glm::length(vi);
            // Eq. 6-7: only where the particle moves along its normal (a crest).
            const bool alongNormal = speed > 0.0f && glm::dot(vi / speed, ni) >= kWaveCrestAlignment;
            out.trappedAir[i] = ta;
            out.waveCrest[i] = alongNormal ? kappa : 0.0f;
            out.energy[i] = 0.5f * glm::dot(vi, vi);
        }
    });
    return out;
}

}  // namespace

std::string checkWhitewaterParams(const WhitewaterParams& p) {
    if (!within(p.supportRadii, 1.0f, 16.0f)) return "supportRadii: from 1 to 16 particle radii";
    auto limits = [](float lo, float hi) { return lo >= 0.0f && hi >= 0.0f && (hi == 0.0f || lo < hi) && std::isfinite(hi); };
    if (!limits(p.trappedAirMin, p.trappedAirMax)) return "trappedAir limits: 0 <= min < max (max 0: automatic)";
    if (!limits(p.waveCrestMin, p.waveCrestMax)) return "waveCrest limits: 0 <= min < max (max 0: automatic)";
    if (!limits(p.energyMin, p.energyMax)) return "energy limits: 0 <= min < max (max 0: automatic)";
    if (!within(p.trappedAirRate, 0.0f, 1e9f)) return "trappedAirRate: from 0 to 1e9";
    if (!within(p.waveCrestRate, 0.0f, 1e9f)) return "waveCrestRate: from 0 to 1e9";
    if (!within(p.scale, 0.0f, 1e9f)) return "scale: from 0 to 1e9 particles per second";
    if (p.sprayBelow < 0 || p.bubbleAbove < p.sprayBelow || p.bubbleAbove > 100000)
        return "sprayBelow, bubbleAbove: 0 <= sprayBelow <= bubbleAbove <= 100000 neighbours";
    if (!within(p.buoyancy, 0.0f, 1e3f)) return "buoyancy: from 0 to 1000";
    if (!within(p.drag, 0.0f, 1.0f)) return "drag: from 0 to 1";
    if (!within(p.lifetimeMinS, 0.0f, 1e6f) || !within(p.lifetimeMaxS, p.lifetimeMinS, 1e6f))
        return "lifetime: 0 <= min <= max <= 1e6 s";
    for (int c = 0; c < 3; ++c)
        if (!within(p.gravity[c], -1e4f, 1e4f)) return "gravity: each component from -1e4 to 1e4 m/s^2";
    if (p.maxParticles < 1 || p.maxParticles > 1'000'000'000) return "maxParticles: from 1 to 1e9";
    return {};
}

Result<Potentials> computePotentials(const ParticleView& fluid, float radiusM, const WhitewaterParams& p) {
    try {
        if (auto st = checkFluid(fluid, radiusM); !st) return st.error();
        if (std::string bad = checkWhitewaterParams(p); !bad.empty()) return makeError("", "whitewater: " + bad);
        const std::vector<glm::vec3> x = copyOf(fluid.positions), v = copyOf(fluid.velocity);
        const float h = p.supportRadii * radiusM;
        FluidNeighbours nb;
        findFluidNeighbours(x, h, nb);
        return potentialsOf(x, v, nb, h, p);
    } catch (const std::bad_alloc&) {
        return makeError("", "out of memory computing the whitewater potentials");
    } catch (const std::exception& e) {
        return makeError("", std::string("whitewater potentials: ") + e.what());
    }
}

PotentialMaxima maximaOf(const Potentials& p) {
    PotentialMaxima m;
    for (float v : p.trappedAir) m.trappedAir = std::max(m.trappedAir, double(v));
    for (float v : p.waveCrest) m.waveCrest = std::max(m.waveCrest, double(v));
    for (float v : p.energy) m.energy = std::max(m.energy, double(v));
    return m;
}

WhitewaterParams withAutomaticLimits(const WhitewaterParams& p, const std::vector<PotentialMaxima>& frames) {
    WhitewaterParams out = p;
    PotentialMaxima mean;
    for (const PotentialMaxima& f : frames) mean.trappedAir += f.trappedAir, mean.waveCrest += f.waveCrest, mean.energy += f.energy;
    const double n = std::max<double>(1.0, double(frames.size()));
    // A potential that never rises (a fluid at rest) keeps [0.999, 1]: it
    // stays below, and makes nothing.
    auto set = [&](double sum, float& lo, float& hi) {
        if (hi != 0.0f) return;
        const float top = float(sum / n);
        hi = top > 0.0f ? top : 1.0f;
        lo = top > 0.0f ? 0.1f * top : 0.999f;
    };
    set(mean.trappedAir, out.trappedAirMin, out.trappedAirMax);
    set(mean.waveCrest, out.waveCrestMin, out.waveCrestMax);
    set(mean.energy, out.energyMin, out.energyMax);
    return out;
}

Result<double> estimateFrameInterval(const ParticleView& a, const ParticleView& b) {
    if (auto st = a.validate(); !st) return st.error();
    if (auto st = b.validate(); !st) return st.error();
    if (!a.velocity.present() || !b.velocity.present())
        return makeError("", "the frames have no velocity attribute to estimate the time between them from");
    // Pairs (index in a, index in b) of the same particle.
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    if (a.id.present() && b.id.present()) {
        std::vector<std::pair<std::int64_t, std::size_t>> ids(b.size());
        for (std::size_t k = 0; k < b.size(); ++k) ids[k] = {b.id[k], k};
        std::sort(ids.begin(), ids.end());
        for (std::size_t i = 0; i < a.size(); ++i) {
            auto it = std::lower_bound(ids.begin(), ids.end(), std::make_pair(a.id[i], std::size_t(0)));
            if (it != ids.end() && it->first == a.id[i]) pairs.emplace_back(i, it->second);
        }
    } else if (a.size() == b.size()) {
        for (std::size_t i = 0; i < a.size(); ++i) pairs.emplace_back(i, i);
    } else {
        return makeError("", "the frames have no ids and different particle counts: no particle can be matched");
    }
    std::vector<double> dts;
    for (auto [i, k] : pairs) {
        const glm::vec3 v = 0.5f * (a.velocity[i] + b.velocity[k]);
        const float v2 = glm::dot(v, v);
        if (!(v2 > kMovingMps * kMovingMps)) continue;
        const double dt = double(glm::dot(b.positions[k] - a.positions[i], v)) / double(v2);
        if (std::isfinite(dt)) dts.push_back(dt);
    }
    if (dts.empty()) return makeError("", "no particle moves faster than 0.05 m/s: the time between frames is unknown");
    std::nth_element(dts.begin(), dts.begin() + std::ptrdiff_t(dts.size() / 2), dts.end());
    const double dt = dts[dts.size() / 2];
    if (!(dt > 0.0)) return makeError("", "the particles move against their velocities: the frames are out of order");
    return dt;
}

Result<WhitewaterGenerator> WhitewaterGenerator::create(const WhitewaterParams& p, float radiusM) {
    if (std::string bad = checkWhitewaterParams(p); !bad.empty()) return makeError("", "whitewater: " + bad);
    if (p.trappedAirMax == 0.0f || p.waveCrestMax == 0.0f || p.energyMax == 0.0f)
        return makeError("", "whitewater: the limits are automatic; resolve them with withAutomaticLimits first");
    if (!(radiusM > 0.0f) || !std::isfinite(radiusM)) return makeError("", "the particle radius must be positive");
    WhitewaterGenerator g;
    g.p_ = p;
    g.radius_ = radiusM;
    return g;
}

namespace {

// Keeps the particles where keep[i], in order.
void compact(DiffuseParticles& d, const std::vector<std::uint8_t>& keep) {
    std::size_t m = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
        if (!keep[i]) continue;
        d.positions[m] = d.positions[i], d.velocities[m] = d.velocities[i], d.type[m] = d.type[i];
        d.lifetime[m] = d.lifetime[i], d.id[m] = d.id[i];
        ++m;
    }
    d.positions.resize(m), d.velocities.resize(m), d.type.resize(m), d.lifetime.resize(m), d.id.resize(m);
}

void append(DiffuseParticles& to, DiffuseParticles& from) {
    to.positions.insert(to.positions.end(), from.positions.begin(), from.positions.end());
    to.velocities.insert(to.velocities.end(), from.velocities.begin(), from.velocities.end());
    to.type.insert(to.type.end(), from.type.begin(), from.type.end());
    to.lifetime.insert(to.lifetime.end(), from.lifetime.begin(), from.lifetime.end());
    to.id.insert(to.id.end(), from.id.begin(), from.id.end());
    from = DiffuseParticles{};
}


// Classifies (§6) and advects (§7) the diffuse particles over fluid x, v
// (with its grid of cell h), then drops the dissolved ones.
void advectWithNeighbours(DiffuseParticles& d, std::span<const glm::vec3> x, std::span<const glm::vec3> v,
                          const CellGrid& grid, float h, const WhitewaterParams& p, float dt, const Bounds& keepIn,
                          bool openTop) {
    const std::size_t nd = d.size();
    std::vector<std::uint8_t> keep(nd, 0);
    if (nd > 0 && !x.empty()) {
        NeighbourLists dl;
        const CubicSpline K(h);
        auto kernel = [&K](F4 r, F4& w, F4& g) { K.evaluate4(r, w, g); };
        buildNeighbourLists(d.positions, grid, h, false, kernel, dl, std::span<float>());
        const glm::vec3 lo = keepIn.min, hi = keepIn.max;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nd, 512), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                const DiffuseType type = classifyDiffuse(int(dl.count(i)), p);
                glm::vec3& xd = d.positions[i];
                glm::vec3& vd = d.velocities[i];
                // Eq. 11: the fluid's velocity here, averaged with the cubic spline.
                glm::vec3 vf(0.0f);
                float sumK = 0.0f;
                for (const Neighbour& e : dl.of(i)) {
                    const float w = K.W(glm::length(xd - x[e.j]));
                    vf += w * v[e.j];
                    sumK += w;
                }
                if (sumK > 0.0f) vf /= sumK;
                switch (type) {
                    case DiffuseType::Spray:  // ballistic (eq. 9)
                        vd += dt * p.gravity;
                        xd += dt * vd;
                        break;
                    case DiffuseType::Foam:  // carried by the fluid (eq. 10); only foam ages
                        vd = vf;
                        xd += dt * vf;
                        d.lifetime[i] -= dt;
                        break;
                    case DiffuseType::Bubble:  // buoyancy and drag (eq. 12)
                        vd += -dt * p.buoyancy * p.gravity + p.drag * (vf - vd);
                        xd += dt * vd;
                        break;
                }
                d.type[i] = type;
                // Dissolved: foam at the end of its life, or out of the box
                // (open upward when it is the fluid's region: spray falls back).
                const bool out = xd.x < lo.x || xd.x > hi.x || xd.z < lo.z || xd.z > hi.z || xd.y < lo.y ||
                                 (!openTop && xd.y > hi.y) || !std::isfinite(xd.y);
                keep[i] = d.lifetime[i] > 0.0f && !out;
            }
        });
    }
    compact(d, keep);  // no fluid: everything dissolves
}

}  // namespace

DiffuseType classifyDiffuse(int fluidNeighbours, const WhitewaterParams& p) {
    return fluidNeighbours < p.sprayBelow    ? DiffuseType::Spray
           : fluidNeighbours > p.bubbleAbove ? DiffuseType::Bubble
                                             : DiffuseType::Foam;
}

Status advectDiffuse(DiffuseParticles& d, const ParticleView& fluid, float radiusM, const WhitewaterParams& p,
                     double dtSeconds, const Bounds& keepIn) {
    try {
        if (auto st = checkFluid(fluid, radiusM); !st) return st;
        if (std::string bad = checkWhitewaterParams(p); !bad.empty()) return makeError("", "whitewater: " + bad);
        if (!(dtSeconds > 0.0) || !std::isfinite(dtSeconds)) return makeError("", "the time step must be positive");
        const std::size_t n = d.size();
        if (d.velocities.size() != n || d.type.size() != n || d.lifetime.size() != n || d.id.size() != n)
            return makeError("", "the diffuse particles' attributes differ in length");
        const std::vector<glm::vec3> x = copyOf(fluid.positions), v = copyOf(fluid.velocity);
        const float h = p.supportRadii * radiusM;
        CellGrid grid;
        grid.configure(boxOf(x), h);
        grid.build(x);
        advectWithNeighbours(d, x, v, grid, h, p, float(dtSeconds), keepIn, false);
        return okStatus();
    } catch (const std::bad_alloc&) {
        return makeError("", "out of memory advecting whitewater");
    } catch (const std::exception& e) {
        return makeError("", std::string("whitewater: ") + e.what());
    }
}

Result<WhitewaterStepStats> WhitewaterGenerator::step(const ParticleView& fluid, double dtSeconds) {
    try {
        if (auto st = checkFluid(fluid, radius_); !st) return st.error();
        if (!(dtSeconds > 0.0) || !std::isfinite(dtSeconds)) return makeError("", "the time step must be positive");
        WhitewaterStepStats stats;
        const float dt = float(dtSeconds);
        const float h = p_.supportRadii * radius_;
        const std::vector<glm::vec3> x = copyOf(fluid.positions), v = copyOf(fluid.velocity);
        for (const glm::vec3& q : x) region_.extend(q);

        auto t0 = std::chrono::steady_clock::now();
        FluidNeighbours nb;
        findFluidNeighbours(x, h, nb);
        const Potentials pot = potentialsOf(x, v, nb, h, p_);
        stats.msPotentials = msSince(t0);

        // §6-7: the diffuse particles (last step's new ones joined) classified
        // by their fluid neighbours at this frame, then advected by type.
        t0 = std::chrono::steady_clock::now();
        append(diffuse_, pending_);
        const std::size_t nd = diffuse_.size();
        const bool boxed = !p_.box.empty();
        Bounds keep = p_.box;
        if (!boxed) keep.min = region_.min - glm::vec3(h), keep.max = region_.max + glm::vec3(h);
        advectWithNeighbours(diffuse_, x, v, nb.grid, h, p_, dt, keep, !boxed);
        stats.removed = nd - diffuse_.size();
        stats.msAdvect = msSince(t0);

        // §5: this frame's new diffuse particles, n_d = I_k (k_ta I_ta + k_wc I_wc) dt
        // (times `scale`), in a cylinder along each fluid particle's velocity.
        t0 = std::chrono::steady_clock::now();
        const std::size_t n = x.size();
        std::vector<float> expected(n, 0.0f), energy(n, 0.0f);
        double total = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            if (int(pot.neighbours[i]) < kMinGeneratingNeighbours) continue;
            const float Ita = clampAndNormalise(pot.trappedAir[i], p_.trappedAirMin, p_.trappedAirMax);
            const float Iwc = clampAndNormalise(pot.waveCrest[i], p_.waveCrestMin, p_.waveCrestMax);
            energy[i] = clampAndNormalise(pot.energy[i], p_.energyMin, p_.energyMax);
            expected[i] = p_.scale * energy[i] * (p_.trappedAirRate * Ita + p_.waveCrestRate * Iwc) * dt;
            total += double(expected[i]);
        }
        // The cap: fewer made everywhere alike when the alive ones would exceed it.
        const double room = double(p_.maxParticles) - double(diffuse_.size());
        const float factor = total > room ? float(std::max(0.0, room) / total) : 1.0f;
        std::vector<std::uint32_t> start(n + 1, 0);
        for (std::size_t i = 0; i < n; ++i) {
            const float e = expected[i] * factor;
            const float whole = std::floor(e);
            start[i + 1] = start[i] + std::uint32_t(whole) + (uniform01(p_.seed, frame_, i, 0, 0) < e - whole ? 1u : 0u);
        }
        const std::size_t made = std::min<std::size_t>(start[n], std::size_t(std::max(0.0, room)));
        pending_.positions.resize(made), pending_.velocities.resize(made), pending_.type.resize(made);
        pending_.lifetime.resize(made), pending_.id.resize(made);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 512), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                if (start[i] == start[i + 1] || start[i] >= made) continue;
                const glm::vec3 vf = v[i];
                const float speed = glm::length(vf);
                const glm::vec3 axis = speed > 0.0f ? vf / speed : glm::vec3(0, 1, 0);
                glm::vec3 e1, e2;
                orthogonalPair(axis, e1, e2);
                for (std::uint32_t k = start[i]; k < start[i + 1] && k < made; ++k) {
                    const std::size_t m = k - start[i];
                    // Eq. 13-14: uniform in the cylinder of radius r around the
                    // particle's path over the frame (centred on it, as FoamGenerator).
                    const float rr = radius_ * std::sqrt(uniform01(p_.seed, frame_, i, m, 1));
                    const float theta = 6.28318530718f * uniform01(p_.seed, frame_, i, m, 2);
                    const float along = (uniform01(p_.seed, frame_, i, m, 3) - 0.5f) * dt * speed;
                    const glm::vec3 radial = rr * std::cos(theta) * e1 + rr * std::sin(theta) * e2;
                    pending_.positions[k] = x[i] + radial + along * axis;
                    // The paper's v_d = radial offset + v_f: a spread of r m/s at most.
                    pending_.velocities[k] = radial + vf;
                    pending_.lifetime[k] =
                        p_.lifetimeMinS + energy[i] * uniform01(p_.seed, frame_, i, m, 4) * (p_.lifetimeMaxS - p_.lifetimeMinS);
                    pending_.id[k] = nextId_ + std::int64_t(k);
                    pending_.type[k] = classifyDiffuse(int(pot.neighbours[i]), p_);
                }
            }
        });
        nextId_ += std::int64_t(made);
        stats.generated = made;
        stats.msGenerate = msSince(t0);
        ++frame_;
        for (DiffuseType t : diffuse_.type)
            ++(t == DiffuseType::Spray ? stats.spray : t == DiffuseType::Foam ? stats.foam : stats.bubbles);
        return stats;
    } catch (const std::bad_alloc&) {
        return makeError("", "out of memory generating whitewater");
    } catch (const std::exception& e) {
        return makeError("", std::string("whitewater: ") + e.what());
    }
}

ParticleSet toParticleSet(const DiffuseParticles& d) {
    ParticleSet set;
    set.positions = d.positions;
    Attribute vel{std::string(kAttrVelocity), AttributeType::Float, 3, {}, {}};
    vel.floats.reserve(3 * d.size());
    for (const glm::vec3& v : d.velocities) vel.floats.insert(vel.floats.end(), {v.x, v.y, v.z});
    Attribute id{std::string(kAttrId), AttributeType::Int, 1, {}, d.id};
    Attribute type{std::string(kAttrDiffuseType), AttributeType::Int, 1, {}, {}};
    type.ints.reserve(d.size());
    for (DiffuseType t : d.type) type.ints.push_back(std::int64_t(t));
    Attribute life{std::string(kAttrLifetime), AttributeType::Float, 1, d.lifetime, {}};
    set.attributes = {std::move(vel), std::move(id), std::move(type), std::move(life)};
    return set;
}

}  // namespace meniscus::sim
