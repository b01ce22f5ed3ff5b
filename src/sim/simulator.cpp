// The simulator's driver: scene -> particles and boundaries, then each step
// the method's own file (dfsph_bender2015.cpp, sph_muller2003.cpp,
// mass_points.cpp) followed by the common part here: positions, the guard,
// emitters, drains, lifetimes and the periodic z-order re-sort.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "meniscus/io.h"
#include "meniscus/memory_budget.h"
#include "sim/state.h"
#include "sim/timer.h"
#include "shared/finite.h"

namespace meniscus::sim {

namespace {

constexpr std::size_t kMaxParticles = std::size_t(1) << 28;  // memory bound, ~60 GB of state
constexpr double kMaxGridCells = double(1 << 27);            // 512 MB of cell starts
constexpr double kInitialDtS = 0.001;                        // s, SPlisHSPlasH's first step

std::string vecStr(const glm::vec3& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%g, %g, %g)", double(v.x), double(v.y), double(v.z));
    return buf;
}


bool boxOk(const Box& b) { return finite3(b.min) && finite3(b.max) && glm::all(glm::lessThan(b.min, b.max)); }

bool inside(const Box& outer, const Box& inner) {
    return glm::all(glm::lessThanEqual(outer.min, inner.min)) && glm::all(glm::lessThanEqual(inner.max, outer.max));
}

// The lattice of a block on one axis: SPlisHSPlasH's rule, the first and last
// particle 2r inside the block's faces (a 1 m block at r = 0.01 m holds 49
// particles per axis, 49^3 = 117,649), except on a face that lies on a wall
// of the domain, where the first particle is r from the wall (its cube
// touches the wall; 2r would leave a gap the fluid first falls into).
struct AxisLattice {
    int count;
    float start;
};
AxisLattice axisLattice(float lo, float hi, float wallLo, float wallHi, float r) {
    const float spacing = 2.0f * r, eps = 1e-5f * std::max(1.0f, std::abs(hi - lo));
    const float inLo = std::abs(lo - wallLo) <= eps ? r : spacing, inHi = std::abs(hi - wallHi) <= eps ? r : spacing;
    const float span = hi - lo - inLo - inHi;
    // In double and capped: a huge block must reach the particle-count check, not overflow.
    const double steps = std::floor(double(span) / double(spacing) + 1e-4);
    const int count = span < 0.0f ? 1 : int(std::min(steps, 1e9)) + 1;
    const float start = span < 0.0f ? 0.5f * (lo + hi) : lo + inLo + 0.5f * (span - float(count - 1) * spacing);
    return {count, start};
}

// 1 / sum of W over a simple cubic lattice of spacing 2r around a particle:
// the volume that makes the rest lattice exactly rho0.
// Also counts the lattice neighbours within h (self excluded).
template <class W>
float restVolume(float r, float h, W&& w, float* neighbours) {
    const float s = 2.0f * r;
    const int reach = int(std::ceil(h / s));
    double sum = 0.0;
    int count = 0;
    for (int z = -reach; z <= reach; ++z)
        for (int y = -reach; y <= reach; ++y)
            for (int x = -reach; x <= reach; ++x) {
                const float d = s * std::sqrt(float(x * x + y * y + z * z));
                if (d < h) sum += double(w(d)), count += (x || y || z);
            }
    *neighbours = float(count);
    return float(1.0 / sum);
}

// Particles one layer of emitter e holds (emitLayer's count): `rate` per
// second over a layer's 2r of outflow, or the disc's pi R^2 / (2r)^2.
double layerParticles(const Emitter& e, float r) {
    const double spacing = 2.0 * double(r);
    if (e.rate > 0.0f) return std::max(1.0, std::round(double(e.rate) * spacing / double(e.speed)));
    const double radius = e.radius > 0.0f ? double(e.radius) : 4.0 * double(r);
    return std::max(1.0, std::round(3.14159265358979 * radius * radius / (spacing * spacing)));
}

Status validate(const Scene& sc) {
    const std::string file = sc.file.string();
    // The scene's values are wrong: the settings' error (Error::usage), not the data's.
    auto bad = [&](const std::string& m) -> Status { return makeUsageError(file, m); };
    const SimParams& p = sc.params;
    if (!(p.radius >= 1e-6f && p.radius <= 10.0f)) {
        char radius[32];
        std::snprintf(radius, sizeof radius, "%g", double(p.radius));
        return bad("radius " + std::string(radius) + " m is not in [1e-6, 10] m");
    }
    if (!boxOk(sc.domain)) return bad("the domain box " + vecStr(sc.domain.min) + " - " + vecStr(sc.domain.max) + " is empty or not finite");
    if (glm::any(glm::lessThan(sc.domain.max - sc.domain.min, glm::vec3(8.0f * p.radius))))
        return bad("the domain is narrower than 8 particle radii (twice the kernel support) on some axis");
    {
        // The neighbour grid is dense over the domain (cells of 4r): bound its memory.
        const glm::dvec3 cells = glm::ceil(glm::dvec3(sc.domain.max - sc.domain.min) / (4.0 * double(p.radius))) + 2.0;
        if (cells.x * cells.y * cells.z > double(kMaxGridCells))
            return bad("the domain is " + std::to_string(long(cells.x)) + " x " + std::to_string(long(cells.y)) + " x " +
                       std::to_string(long(cells.z)) + " grid cells of 4 r; at most 2^27: use a larger radius or a smaller domain");
    }
    if (!(p.restDensity > 0.0f) || !std::isfinite(p.restDensity)) return bad("rest_density must be positive");
    if (!(p.cfl > 0.0f) || !(p.minDt > 0.0f) || !(p.maxDt >= p.minDt)) return bad("need cfl > 0 and 0 < min_dt <= max_dt");
    if (!(p.densityTolerance > 0.0f) || !(p.divergenceTolerance > 0.0f) || p.maxIterations < 2)
        return bad("need positive tolerances and max_iterations >= 2");
    if (!finite3(p.gravity) || !(p.viscosity >= 0.0f) || !(p.surfaceTension >= 0.0f) || !(p.stiffness > 0.0f))
        return bad("gravity must be finite, viscosity and surface_tension >= 0, stiffness > 0");
    for (std::size_t i = 0; i < sc.fluid.size(); ++i) {
        if (!boxOk(sc.fluid[i].box)) return bad("fluid[" + std::to_string(i) + "]: the box is empty or not finite");
        if (!inside(sc.domain, sc.fluid[i].box)) return bad("fluid[" + std::to_string(i) + "]: the box is not inside the domain");
        if (!finite3(sc.fluid[i].velocity)) return bad("fluid[" + std::to_string(i) + "]: velocity is not finite");
    }
    for (std::size_t i = 0; i < sc.emitters.size(); ++i) {
        const Emitter& e = sc.emitters[i];
        const Box point{e.position, e.position};
        if (!finite3(e.position) || !inside(sc.domain, point)) return bad("emitters[" + std::to_string(i) + "]: the position is not inside the domain");
        if (!finite3(e.direction) || glm::length(e.direction) < 1e-6f) return bad("emitters[" + std::to_string(i) + "]: the direction is zero");
        if (!(e.speed > 0.0f) || !(e.radius >= 0.0f) || !(e.rate >= 0.0f) || !(e.end >= e.start))
            return bad("emitters[" + std::to_string(i) + "]: need speed > 0, radius >= 0, rate >= 0, end >= start");
        // One layer (every 2r / speed) holds rate * 2r / speed particles, or the disc's pi R^2 / (2r)^2.
        if (!(layerParticles(e, p.radius) <= 1e7))
            return bad("emitters[" + std::to_string(i) + "]: more than 10^7 particles per layer; lower the rate or radius");
    }
    for (std::size_t i = 0; i < sc.colliders.size(); ++i) {
        const Collider& c = sc.colliders[i];
        const std::string at = "colliders[" + std::to_string(i) + "]: ";
        if (c.kind == Collider::Kind::Box && !boxOk(c.box)) return bad(at + "the box is empty or not finite");
        if (c.kind == Collider::Kind::Sphere && !(c.radius > 0.0f && finite3(c.center))) return bad(at + "the sphere needs a positive radius");
        if (c.kind == Collider::Kind::Plane && !(finite3(c.normal) && glm::length(c.normal) > 1e-6f && finite3(c.point)))
            return bad(at + "the plane needs a non-zero normal");
    }
    if (!(sc.duration >= 0.0) || !(sc.fps > 0.0)) return bad("need duration >= 0 s and fps > 0");
    return okStatus();
}

// The most particles the emitters can hold at once: every layer from start
// to the end of the run, or with a lifetime those of the last `lifetime`
// seconds (drains are not foreseen); never more than the domain holds at the
// rest spacing (an incompressible fluid cannot be packed closer).
double emittedBound(const Scene& sc) {
    const float r = sc.params.radius;
    double total = 0.0;
    for (const Emitter& e : sc.emitters) {
        const double period = 2.0 * double(r) / double(e.speed);
        double span = std::min(double(e.end), sc.duration) - double(e.start);
        if (span < 0.0) continue;
        if (sc.params.lifetime > 0.0f) span = std::min(span, double(sc.params.lifetime));
        total += (std::floor(span / period) + 1.0) * layerParticles(e, r);
    }
    const glm::dvec3 size = glm::dvec3(sc.domain.max - sc.domain.min) / (2.0 * double(r));
    return std::min(total, size.x * size.y * size.z);
}

}  // namespace

std::uint64_t simulatorBytesPerParticle(Solver solver, float neighbours) {
    const std::uint64_t fixed = 64 + 68 + 32 + 24 + 80 + (solver == Solver::Pbf ? 24 : 0);
    return fixed + std::uint64_t(std::ceil(1.5 * double(neighbours) * double(sizeof(Neighbour))));
}

std::uint64_t simulatorGridBytes(const Box& domain, float h) {
    const glm::dvec3 cells = glm::ceil(glm::dvec3(domain.max - domain.min) / double(h)) + 2.0;
    return std::uint64_t(cells.x * cells.y * cells.z) * sizeof(std::uint32_t);
}

// ---------------------------------------------------------------- Impl

void Simulator::Impl::resizeScratch() {
    const std::size_t count = n();
    alpha.resize(count), kappa.resize(count), rhoAdv.resize(count), kernelSum.resize(count);
}

void Simulator::Impl::permute(const std::vector<std::uint32_t>& order) {
    auto apply = [&](auto& vec) {
        using V = std::decay_t<decltype(vec)>;
        V out(order.size());
        for (std::size_t k = 0; k < order.size(); ++k) out[k] = vec[order[k]];
        vec.swap(out);
    };
    apply(x), apply(v), apply(a), apply(density), apply(pressure), apply(id), apply(age), apply(kappaWarm), apply(kappaVWarm);
    resizeScratch();
}

void Simulator::Impl::findNeighbours(std::span<const glm::vec3> at) {
    grid.build(at);
    resizeScratch();
    if (p.solver == Solver::Sph) {
        const MullerKernels& K = muller;
        auto kernel = [&K](F4 r, F4& w, F4& g) { K.spiky4(r, w, g); };
        buildNeighbourLists(at, grid, h, true, kernel, fluidNb, kernelSum);
    } else {
        const CubicSpline& K = cubic;
        auto kernel = [&K](F4 r, F4& w, F4& g) { K.evaluate4(r, w, g); };
        buildNeighbourLists(at, grid, h, true, kernel, fluidNb, kernelSum);
    }
    wall.resize(n());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n(), 512), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) wall[i] = wallTerm(scene, meshes, h, at[i], walls);
    });
}

void Simulator::Impl::computeDensities() {
    const float self = p.solver == Solver::Sph ? muller.spiky(0.0f) : cubic.W(0.0f);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n(), 512), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            density[i] = p.restDensity * (volume * (self + kernelSum[i]) + wall[i].density);
        }
    });
}

void Simulator::Impl::nonPressureAccelerations() {
    a.resize(n());
    const bool viscous = p.solver == Solver::Dfsph && p.viscosity > 0.0f;
    forAll(n(), [&](std::size_t i) { a[i] = viscous ? p.gravity + viscousAcceleration(i) : p.gravity; });
}

double Simulator::Impl::cflStep(double until, float soundSpeed) const {
    // max |v + a dt| over the particles (a floor of 0.1 m/s as SPlisHSPlasH).
    const double prev = dt > 0.0 ? dt : kInitialDtS;
    const float maxV2 = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n(), 4096), 0.01f,
        [&](const tbb::blocked_range<std::size_t>& r, float m) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                const glm::vec3 w = v[i] + a[i] * float(prev);
                m = std::max(m, glm::dot(w, w));
            }
            return m;
        },
        [](float l, float r) { return std::max(l, r); });
    double step = double(p.cfl) * 0.4 * (2.0 * r) / (std::sqrt(double(maxV2)) + double(soundSpeed));
    step = std::clamp(step, double(p.minDt), double(p.maxDt));
    if (until > t) {
        // End on `until` exactly, without a sliver of a last step.
        const double rest = until - t;
        if (rest <= step) step = rest;
        else if (rest < 2.0 * step) step = 0.5 * rest;
    }
    return step;
}

// ---------------------------------------------------------------- the common part of a step

namespace {

void emitLayer(Simulator::Impl& s, const Emitter& e, float shift) {
    const glm::vec3 dir = glm::normalize(e.direction);
    const glm::vec3 helper = std::abs(dir.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 u = glm::normalize(glm::cross(dir, helper)), w = glm::cross(dir, u);
    const float spacing = 2.0f * s.r;
    // Points on a Vogel spiral, one per (2r)^2 of the disc: the rate sets the
    // count per layer (layers leave every 2r / speed seconds), else the radius.
    const int count = int(layerParticles(e, s.r));
    const float radius = e.rate > 0.0f ? spacing * std::sqrt(float(count) / kPi) : e.radius > 0.0f ? e.radius : 4.0f * s.r;
    const float golden = kPi * (3.0f - std::sqrt(5.0f));
    for (int k = 0; k < count; ++k) {
        const float rr = radius * std::sqrt((float(k) + 0.5f) / float(count));
        const float phi = golden * float(k);
        glm::vec3 pos = e.position + u * (rr * std::cos(phi)) + w * (rr * std::sin(phi)) + dir * shift;
        pos = glm::clamp(pos, s.scene.domain.min + glm::vec3(0.5f * s.r), s.scene.domain.max - glm::vec3(0.5f * s.r));
        s.x.push_back(pos);
        s.v.push_back(dir * e.speed);
        s.a.push_back(glm::vec3(0.0f));
        s.density.push_back(s.p.restDensity);
        s.pressure.push_back(0.0f);
        s.id.push_back(s.nextId++);
        s.age.push_back(0.0f);
        s.kappaWarm.push_back(0.0f);
        s.kappaVWarm.push_back(0.0f);
        ++s.totals.emitted;
    }
}

void emit(Simulator::Impl& s) {
    for (std::size_t k = 0; k < s.scene.emitters.size(); ++k) {
        const Emitter& e = s.scene.emitters[k];
        const double period = 2.0 * s.r / e.speed;
        // A layer per 2r of outflow; at most a few per step (a long step does not flood).
        for (int layers = 0; layers < 4 && s.t >= s.emitterNext[k] && s.emitterNext[k] <= e.end; ++layers) {
            emitLayer(s, e, float((s.t - s.emitterNext[k]) * e.speed));
            s.emitterNext[k] += period;
        }
        if (s.t >= s.emitterNext[k]) s.emitterNext[k] = s.t + period;  // skipped layers are dropped
    }
}

// Drains and lifetimes: the survivors keep their order.
void removeParticles(Simulator::Impl& s) {
    if (s.scene.drains.empty() && !(s.p.lifetime > 0.0f)) return;
    std::vector<std::uint32_t> keep;
    keep.reserve(s.n());
    for (std::size_t i = 0; i < s.n(); ++i) {
        bool drained = false;
        for (const Drain& d : s.scene.drains)
            drained = drained || (glm::all(glm::greaterThanEqual(s.x[i], d.box.min)) && glm::all(glm::lessThanEqual(s.x[i], d.box.max)));
        const bool expired = s.p.lifetime > 0.0f && s.age[i] > s.p.lifetime;
        s.totals.drained += drained;
        s.totals.expired += expired && !drained;
        if (!drained && !expired) keep.push_back(std::uint32_t(i));
    }
    if (keep.size() != s.n()) s.permute(keep);
}

}  // namespace

// ---------------------------------------------------------------- Simulator

Simulator::Simulator(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Simulator::~Simulator() = default;

Result<std::unique_ptr<Simulator>> Simulator::create(const Scene& scene) {
    try {
        if (Status ok = validate(scene); !ok) return ok.error();
        auto s = std::make_unique<Impl>();
        s->scene = scene;
        s->p = scene.params;
        s->r = s->p.radius;
        s->h = defaults::kSphSupportRadii * s->r;
        s->cubic = CubicSpline(s->h);
        s->muller = MullerKernels(s->h);
        if (s->p.solver == Solver::Sph) {
            // Density with the kernel of the pressure force, Muller's spiky
            // (sph_muller2003.cpp says why not the paper's poly6).
            const MullerKernels& K = s->muller;
            auto W = [&](double d) { return double(K.spiky(float(d))); };
            s->volume = restVolume(s->r, s->h, [&](float d) { return K.spiky(d); }, &s->fullNeighbours);
            s->walls.density = WallTable(s->h, W);
            s->walls.domainDensity = DomainTable(s->h, W);
            s->walls.offset = wallOffset(s->r, s->h, s->walls.density, [&](float d) { return K.spiky(d); });
        } else {
            const CubicSpline& K = s->cubic;
            auto W = [&](double d) { return double(K.W(float(d))); };
            s->volume = restVolume(s->r, s->h, [&](float d) { return K.W(d); }, &s->fullNeighbours);
            s->walls.density = WallTable(s->h, W);
            s->walls.domainDensity = DomainTable(s->h, W);
            s->walls.offset = wallOffset(s->r, s->h, s->walls.density, [&](float d) { return K.W(d); });
            // Below the rest lattice's first layer (r + offset = 1.19 r), so a fluid at rest is untouched.
            s->walls.nearest = defaults::kSimWallNearestRadii * s->r;
        }
        // The scene's own particle volume (SPlisHSPlasH's convention is 0.8 (2r)^3);
        // the walls' tables above stay those of the rest lattice.
        if (s->p.particleVolume > 0.0f) s->volume = s->p.particleVolume * std::pow(2.0f * s->r, 3.0f);
        s->mass = s->p.restDensity * s->volume;

        // Mesh colliders: read, scaled, moved.
        for (const Collider& c : scene.colliders) {
            if (c.kind != Collider::Kind::Mesh) continue;
            auto mesh = readMesh(c.mesh);
            if (!mesh) return mesh.error();
            ColliderMesh cm;
            cm.mesh = std::move(mesh.value());
            if (cm.mesh.empty()) return makeError(c.mesh.string(), "the collider mesh has no triangles");
            Bounds b;
            for (glm::vec3& p : cm.mesh.positions) {
                p = p * c.scale + c.translate;
                b.extend(p);
            }
            cm.lo = b.min - glm::vec3(s->r), cm.hi = b.max + glm::vec3(s->r);
            s->meshes.push_back(std::move(cm));
        }

        // Fluid blocks on the 2r lattice.
        const float spacing = 2.0f * s->r;
        auto lattice = [&](const FluidBlock& f) {
            std::array<AxisLattice, 3> a;
            for (int k = 0; k < 3; ++k) a[std::size_t(k)] = axisLattice(f.box.min[k], f.box.max[k], scene.domain.min[k], scene.domain.max[k], s->r);
            return a;
        };
        std::size_t total = 0;
        for (const FluidBlock& f : scene.fluid) {
            const auto a = lattice(f);
            total += std::size_t(a[0].count) * std::size_t(a[1].count) * std::size_t(a[2].count);
            if (total > kMaxParticles)
                return makeError(scene.file.string(), "the fluid blocks need more than 2^28 particles at radius " +
                                                          std::to_string(s->r) + " m; use a larger radius");
        }
        // The memory of the largest the run gets, before any particle is made.
        {
            const double most = double(total) + emittedBound(scene);
            const std::uint64_t need =
                std::uint64_t(most * double(simulatorBytesPerParticle(s->p.solver, s->fullNeighbours))) +
                simulatorGridBytes(scene.domain, s->h);
            char what[160];
            std::snprintf(what, sizeof what, "simulating %.3g particles at radius %g m", most, double(s->r));
            if (auto st = checkMemory(need, what, "use a larger radius, smaller fluid blocks or fewer emitted particles");
                !st)
                return makeError(scene.file.string(), st.error().message);
        }
        for (const FluidBlock& f : scene.fluid) {
            const auto a = lattice(f);
            const glm::ivec3 c(a[0].count, a[1].count, a[2].count);
            const glm::vec3 start(a[0].start, a[1].start, a[2].start);
            for (int z = 0; z < c.z; ++z)
                for (int y = 0; y < c.y; ++y)
                    for (int x = 0; x < c.x; ++x) {
                        const glm::vec3 pos = start + glm::vec3(float(x), float(y), float(z)) * spacing;
                        // A ball keeps the lattice points within its radius.
                        if (f.shape == FluidBlock::Shape::Sphere && glm::length(pos - f.center) > f.radius) continue;
                        // Not inside a collider.
                        bool blocked = false;
                        forEachCollider(scene, s->meshes, pos, 0.0f, [&](const Collider&, const SurfacePoint& sp) {
                            blocked = blocked || sp.distance < s->r;
                        });
                        if (blocked) continue;
                        s->x.push_back(pos);
                        s->v.push_back(f.velocity);
                    }
        }
        const std::size_t n = s->x.size();
        s->a.assign(n, glm::vec3(0.0f));
        s->density.assign(n, s->p.restDensity);
        s->pressure.assign(n, 0.0f);
        s->id.resize(n);
        std::iota(s->id.begin(), s->id.end(), std::int64_t(0));
        s->nextId = std::int64_t(n);
        s->age.assign(n, 0.0f);
        s->kappaWarm.assign(n, 0.0f);
        s->kappaVWarm.assign(n, 0.0f);
        s->emitterNext.clear();
        for (const Emitter& e : scene.emitters) s->emitterNext.push_back(e.start);

        s->grid.configure(scene.domain, s->h);
        s->permute(zOrder(s->grid, s->x));
        s->dt = kInitialDtS;
        return std::unique_ptr<Simulator>(new Simulator(std::move(s)));
    } catch (const std::bad_alloc&) {
        return makeError(scene.file.string(), "out of memory while setting up the simulation");
    } catch (const std::exception& e) {
        return makeError(scene.file.string(), std::string("simulation setup failed: ") + e.what());
    }
}

Status Simulator::step(double until) {
    Impl& s = *impl_;
    try {
        switch (s.p.solver) {
            case Solver::Dfsph: stepDfsph(s, until); break;
            case Solver::Sph: stepSph(s, until); break;
            case Solver::Ballistic: stepBallistic(s, until); break;
            case Solver::Pbf: stepPbf(s, until); break;
        }
        Timer timer;
        const float dt = float(s.dt);
        const std::size_t corrected = tbb::parallel_deterministic_reduce(
            tbb::blocked_range<std::size_t>(0, s.n(), 1024), std::size_t(0),
            [&](const tbb::blocked_range<std::size_t>& r, std::size_t c) {
                for (std::size_t i = r.begin(); i < r.end(); ++i) {
                    const glm::vec3 before = s.x[i];
                    s.x[i] += dt * s.v[i];
                    s.age[i] += dt;
                    c += keepOutside(s.scene, s.meshes, s.r, s.x[i], s.v[i], before);
                }
                return c;
            },
            [](std::size_t l, std::size_t r) { return l + r; });
        for (std::size_t i = 0; i < s.n(); ++i)
            if (!finite3(s.v[i]) || !finite3(s.x[i]))
                return makeError(s.scene.file.string(), "the simulation diverged at t = " + std::to_string(s.t) +
                                                            " s (a non-finite velocity or position); try a smaller "
                                                            "max_dt or cfl");
        s.t += s.dt;
        s.totals.guardCorrections += corrected;
        emit(s);
        if (s.n() > kMaxParticles)
            return makeError(s.scene.file.string(), "the emitters made more than 2^28 particles by t = " +
                                                        std::to_string(s.t) + " s; add a drain or a lifetime");
        removeParticles(s);
        ++s.totals.steps;
        if (s.p.resortEvery > 0 && s.totals.steps % std::size_t(s.p.resortEvery) == 0) s.permute(zOrder(s.grid, s.x));
        s.last.dt = s.dt;
        s.last.msAdvect = timer.lap();
        Totals& T = s.totals;
        T.particleSteps += s.n();
        T.densityIterations += std::size_t(s.last.densityIterations);
        T.divergenceIterations += std::size_t(s.last.divergenceIterations);
        T.simulatedS = s.t;
        T.msNeighbours += s.last.msNeighbours, T.msDensity += s.last.msDensity, T.msPressure += s.last.msPressure;
        T.msForces += s.last.msForces, T.msAdvect += s.last.msAdvect;
        return okStatus();
    } catch (const std::bad_alloc&) {
        return makeError(s.scene.file.string(), "out of memory during a simulation step");
    } catch (const std::exception& e) {
        return makeError(s.scene.file.string(), std::string("simulation step failed: ") + e.what());
    }
}

Status Simulator::advanceTo(double t) {
    while (impl_->t < t) {
        if (Status ok = step(t); !ok) return ok;
    }
    return okStatus();
}

double Simulator::time() const { return impl_->t; }
std::size_t Simulator::size() const { return impl_->n(); }
const Scene& Simulator::scene() const { return impl_->scene; }
std::span<const glm::vec3> Simulator::positions() const { return impl_->x; }
std::span<const glm::vec3> Simulator::velocities() const { return impl_->v; }
std::span<const float> Simulator::densities() const { return impl_->density; }
std::span<const float> Simulator::pressures() const { return impl_->pressure; }
std::span<const std::int64_t> Simulator::ids() const { return impl_->id; }
float Simulator::particleMass() const { return impl_->mass; }
const StepStats& Simulator::lastStep() const { return impl_->last; }
const Totals& Simulator::totals() const { return impl_->totals; }

ParticleSet Simulator::particles() const {
    const Impl& s = *impl_;
    ParticleSet set;
    set.positions = s.x;
    Attribute id{std::string(kAttrId), AttributeType::Int, 1, {}, s.id};
    Attribute vel{std::string(kAttrVelocity), AttributeType::Float, 3, {}, {}};
    vel.floats.reserve(3 * s.n());
    for (const glm::vec3& v : s.v) vel.floats.insert(vel.floats.end(), {v.x, v.y, v.z});
    Attribute rho{std::string(kAttrDensity), AttributeType::Float, 1, s.density, {}};
    Attribute pressure{"pressure", AttributeType::Float, 1, s.pressure, {}};
    set.attributes = {std::move(id), std::move(vel), std::move(rho), std::move(pressure)};
    return set;
}

Status Simulator::restore(const ParticleSet& set, double time) {
    Impl& s = *impl_;
    const std::size_t n = set.size();
    const Attribute* id = set.find(kAttrId);
    const Attribute* vel = set.find(kAttrVelocity);
    if (id && (id->type != AttributeType::Int || id->components != 1 || id->count() != n))
        return makeError("", "restore: the id attribute must be one integer per particle");
    if (vel && (vel->type != AttributeType::Float || vel->components != 3 || vel->count() != n))
        return makeError("", "restore: the velocity attribute must be three floats per particle");
    if (!(time >= 0.0) || !std::isfinite(time)) return makeError("", "restore: the time must be finite and >= 0");
    for (const glm::vec3& p : set.positions)
        if (!finite3(p) || !inside(s.scene.domain, Box{p, p}))
            return makeError("", "restore: a particle at " + vecStr(p) + " is outside the domain");
    s.x = set.positions;
    s.v.assign(n, glm::vec3(0.0f));
    if (vel)
        for (std::size_t i = 0; i < n; ++i) s.v[i] = {vel->floats[3 * i], vel->floats[3 * i + 1], vel->floats[3 * i + 2]};
    s.id.resize(n);
    if (id) std::copy(id->ints.begin(), id->ints.end(), s.id.begin());
    else std::iota(s.id.begin(), s.id.end(), std::int64_t(0));
    s.nextId = n ? *std::max_element(s.id.begin(), s.id.end()) + 1 : 0;
    s.a.assign(n, glm::vec3(0.0f));
    s.density.assign(n, s.p.restDensity);
    s.pressure.assign(n, 0.0f);
    s.age.assign(n, float(time));
    s.kappaWarm.assign(n, 0.0f);
    s.kappaVWarm.assign(n, 0.0f);
    s.t = time;
    for (std::size_t k = 0; k < s.scene.emitters.size(); ++k) {
        const Emitter& e = s.scene.emitters[k];
        const double period = 2.0 * s.r / e.speed;
        s.emitterNext[k] = time <= e.start ? e.start : e.start + std::ceil((time - e.start) / period) * period;
    }
    s.permute(zOrder(s.grid, s.x));
    return okStatus();
}

}  // namespace meniscus::sim
