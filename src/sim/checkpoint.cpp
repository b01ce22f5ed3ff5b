// The simulator's checkpoint (Simulator::saveCheckpoint, loadCheckpoint):
// everything a step reads from the steps before it, so that a run resumed
// from it computes the same bits as one never stopped. The particle frames
// hold positions, velocities, densities, pressures and ids, but not:
//   - DFSPH's warm start (Bender & Koschier 2015, §4.1 / 2017 Alg. 2): each
//     particle's stiffness sums of the last step, kappaWarm and kappaVWarm;
//   - the accelerations a (the CFL rule reads v + a dt of the last step);
//   - the particles' order (z-order re-sorts every resortEvery steps; the
//     neighbour lists, hence every sum's rounding, follow it) and the step
//     count that times the re-sorts;
//   - the ages (lifetimes), the next id, the adaptive step dt and the exact
//     time t (the frames' k / fps is not the sum of the steps);
//   - when each emitter's next layer is due.
// Nothing in src/sim draws random numbers (the whitewater's hashes are not
// part of a step). The grid, neighbour lists and the solvers' scratch are
// rebuilt by every step from the above.
//
// The file, little-endian throughout:
//   header  "MNSCKPT1" (8 bytes), u32 version, u32 header bytes,
//           u64 scene fingerprint, i64 frame, f64 t, f64 dt, i64 next id,
//           u64 particles n, u64 emitters E,
//           8 x u64 and 6 x f64 of the totals
//   body    E x f64 emitter next-layer times;
//           n x: 3 f32 x, 3 f32 v, 3 f32 a, f32 density, f32 pressure,
//           i64 id, f32 age, f32 kappaWarm, f32 kappaVWarm (as arrays)
//   trailer u64 FNV-1a of every byte before it
// The counts are checked against the file's size before anything is
// allocated, and the state is replaced only once the whole file has parsed.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "meniscus/io.h"  // PendingFile: write-then-rename
#include "sim/state.h"
#include "shared/finite.h"

namespace meniscus::sim {

namespace {

constexpr char kMagic[8] = {'M', 'N', 'S', 'C', 'K', 'P', 'T', '1'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 7 * 8 + 8 * 8 + 6 * 8;  // 184, whole 8-byte words
static_assert(kHeaderBytes % 8 == 0);
// 3 vec3 + density, pressure, age, two warm starts (f32) + id (i64).
constexpr std::size_t kParticleBytes = 9 * 4 + 5 * 4 + 8;
constexpr std::uint64_t kMaxParticles = std::uint64_t(1) << 28;  // as the simulator's own bound

// FNV-1a, 64 bits: a damaged byte anywhere changes it.
struct Fnv {
    std::uint64_t h = 14695981039346656037ull;
    void add(const std::uint8_t* p, std::size_t n) {
        for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    }
};

template <class T>
void toLittle(T& v) {
    if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
        std::uint8_t b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
        std::memcpy(&v, b, sizeof(T));
    }
}

// Buffered little-endian output with the running hash; throws on a failed write.
class Out {
public:
    explicit Out(std::FILE* f) : f_(f) {}
    template <class T>
    void put(T v) {
        toLittle(v);
        bytes(&v, sizeof v);
    }
    template <class T>
    void array(const std::vector<T>& v) {
        for (const T& e : v) {
            if constexpr (std::is_same_v<T, glm::vec3>) put(e.x), put(e.y), put(e.z);
            else put(e);
        }
    }
    void bytes(const void* p, std::size_t n) {
        const auto* b = static_cast<const std::uint8_t*>(p);
        hash_.add(b, n);
        buf_.insert(buf_.end(), b, b + n);
        if (buf_.size() >= (std::size_t(1) << 20)) flush();
    }
    void finish() {
        std::uint64_t h = hash_.h;
        toLittle(h);
        buf_.insert(buf_.end(), reinterpret_cast<std::uint8_t*>(&h), reinterpret_cast<std::uint8_t*>(&h) + 8);
        flush();
    }

private:
    void flush() {
        if (!buf_.empty() && std::fwrite(buf_.data(), 1, buf_.size(), f_) != buf_.size())
            throw std::runtime_error("could not write the checkpoint (disk full?)");
        buf_.clear();
    }
    std::FILE* f_;
    Fnv hash_;
    std::vector<std::uint8_t> buf_;
};

// Little-endian input over bytes already read; the caller has checked the sizes.
class In {
public:
    explicit In(const std::vector<std::uint8_t>& b) : b_(b) {}
    template <class T>
    T get() {
        T v;
        std::memcpy(&v, b_.data() + at_, sizeof v);
        at_ += sizeof v;
        toLittle(v);
        return v;
    }
    template <class T>
    void array(std::vector<T>& v, std::size_t n) {
        v.resize(n);
        for (T& e : v) {
            if constexpr (std::is_same_v<T, glm::vec3>) {
                e.x = get<float>(), e.y = get<float>(), e.z = get<float>();
            } else {
                e = get<T>();
            }
        }
    }

private:
    const std::vector<std::uint8_t>& b_;
    std::size_t at_ = 0;
};

// The settings that make one run's steps another's: a checkpoint of another
// scene, solver or vector path (whose frames differ in the last bits) is not
// loaded. Not the duration (a resumed run may go further), nor names, files
// or materials.
std::uint64_t fingerprint(const Simulator::Impl& s) {
    Fnv f;
    auto add = [&](auto v) {
        toLittle(v);
        f.add(reinterpret_cast<const std::uint8_t*>(&v), sizeof v);
    };
    auto vec = [&](const glm::vec3& v) { add(v.x), add(v.y), add(v.z); };
    auto text = [&](const std::string& t) {
        add(std::uint64_t(t.size()));
        f.add(reinterpret_cast<const std::uint8_t*>(t.data()), t.size());
    };
    const Scene& sc = s.scene;
    const SimParams& p = s.p;
    add(std::int32_t(p.solver)), add(p.radius), add(p.restDensity), add(p.particleVolume), vec(p.gravity);
    add(p.viscosity), add(p.surfaceTension), add(p.stiffness), add(p.cfl), add(p.minDt), add(p.maxDt);
    add(p.densityTolerance), add(p.divergenceTolerance), add(std::int32_t(p.maxIterations)), add(p.lifetime);
    add(std::int32_t(p.resortEvery));
    vec(sc.domain.min), vec(sc.domain.max);
    add(std::uint64_t(sc.fluid.size()));
    for (const FluidBlock& b : sc.fluid)
        add(std::int32_t(b.shape)), vec(b.box.min), vec(b.box.max), vec(b.center), add(b.radius), vec(b.velocity);
    add(std::uint64_t(sc.colliders.size()));
    for (const Collider& c : sc.colliders) {
        add(std::int32_t(c.kind)), vec(c.box.min), vec(c.box.max), vec(c.center), add(c.radius), vec(c.point);
        vec(c.normal), text(c.mesh.generic_string()), vec(c.scale), vec(c.translate);
    }
    add(std::uint64_t(sc.emitters.size()));
    for (const Emitter& e : sc.emitters)
        vec(e.position), vec(e.direction), add(e.radius), add(e.speed), add(e.rate), add(e.start), add(e.end);
    add(std::uint64_t(sc.drains.size()));
    for (const Drain& d : sc.drains) vec(d.box.min), vec(d.box.max);
    add(sc.fps);
    text(vectorPath());
    return f.h;
}


}  // namespace

Status Simulator::saveCheckpoint(const std::filesystem::path& path, std::int64_t frame) const {
    const Impl& s = *impl_;
    try {
        // Written whole under a hidden temporary name, then renamed: a run
        // stopped mid-write leaves the previous checkpoint, never half of one.
        auto pending = PendingFile::begin(path);
        if (!pending) return pending.error();
        std::FILE* f = std::fopen(pending->tmp().c_str(), "wb");
        if (!f) return makeError(path.string(), "cannot create the checkpoint");
        try {
            Out out(f);
            out.bytes(kMagic, 8);
            out.put(kVersion), out.put(std::uint32_t(kHeaderBytes));
            out.put(fingerprint(s)), out.put(std::int64_t(frame)), out.put(s.t), out.put(s.dt), out.put(s.nextId);
            out.put(std::uint64_t(s.n())), out.put(std::uint64_t(s.emitterNext.size()));
            const Totals& T = s.totals;
            for (std::size_t v : {T.steps, T.particleSteps, T.densityIterations, T.divergenceIterations, T.emitted,
                                  T.drained, T.expired, T.guardCorrections})
                out.put(std::uint64_t(v));
            for (double v : {T.simulatedS, T.msNeighbours, T.msDensity, T.msPressure, T.msForces, T.msAdvect})
                out.put(v);
            out.array(s.emitterNext);
            out.array(s.x), out.array(s.v), out.array(s.a), out.array(s.density), out.array(s.pressure);
            out.array(s.id), out.array(s.age), out.array(s.kappaWarm), out.array(s.kappaVWarm);
            out.finish();
        } catch (...) {
            std::fclose(f);
            throw;
        }
        if (std::fclose(f) != 0) return makeError(path.string(), "could not write the checkpoint (disk full?)");
        return pending->commit();
    } catch (const std::exception& e) {
        return makeError(path.string(), e.what());
    }
}

Result<std::int64_t> Simulator::loadCheckpoint(const std::filesystem::path& path, std::int64_t lastFrame) {
    Impl& s = *impl_;
    const std::string file = path.string();
    auto bad = [&](const std::string& m) -> Error { return makeError(file, "not a usable checkpoint: " + m); };
    try {
        std::FILE* f = std::fopen(path.c_str(), "rb");
        if (!f) return makeError(file, "cannot open the checkpoint");
        std::vector<std::uint8_t> bytes;
        auto readUpTo = [&](std::size_t want) {
            const std::size_t at = bytes.size();
            bytes.resize(at + want);
            const std::size_t got = std::fread(bytes.data() + at, 1, want, f);
            bytes.resize(at + got);
            return got == want;
        };
        const bool header = readUpTo(kHeaderBytes);
        if (!header || std::memcmp(bytes.data(), kMagic, 8) != 0) {
            std::fclose(f);
            return bad(header ? "it does not start with MNSCKPT1" : "it is shorter than its header (cut short?)");
        }
        In h(bytes);
        h.get<std::uint64_t>();  // the magic
        const auto version = h.get<std::uint32_t>(), headerBytes = h.get<std::uint32_t>();
        if (version != kVersion || headerBytes != kHeaderBytes) {
            std::fclose(f);
            return bad("version " + std::to_string(version) + " (this build reads version " + std::to_string(kVersion) + ")");
        }
        const auto print = h.get<std::uint64_t>();
        const auto frame = h.get<std::int64_t>();
        const double t = h.get<double>(), dt = h.get<double>();
        const auto nextId = h.get<std::int64_t>();
        const auto n = h.get<std::uint64_t>(), emitters = h.get<std::uint64_t>();
        if (print != fingerprint(s)) {
            std::fclose(f);
            return bad("it was written for another scene, solver, frame rate or vector path");
        }
        if (emitters != s.scene.emitters.size() || n > kMaxParticles) {
            std::fclose(f);
            return bad("its counts (" + std::to_string(n) + " particles, " + std::to_string(emitters) +
                       " emitters) do not fit the scene");
        }
        // The body's size follows from the counts: nothing is allocated for
        // bytes the file does not hold.
        const std::size_t body = std::size_t(emitters) * 8 + std::size_t(n) * kParticleBytes + 8;
        std::error_code ec;
        const auto size = std::filesystem::file_size(path, ec);
        if (ec || size != kHeaderBytes + body) {
            std::fclose(f);
            return bad("it is " + std::to_string(ec ? 0 : size) + " bytes, its counts say " +
                       std::to_string(kHeaderBytes + body) + " (cut short or damaged)");
        }
        const bool whole = readUpTo(body);
        std::fclose(f);
        if (!whole) return bad("it is shorter than its counts say (cut short?)");
        Fnv sum;
        sum.add(bytes.data(), bytes.size() - 8);
        std::uint64_t stored;
        std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
        toLittle(stored);
        if (stored != sum.h) return bad("its checksum does not match (damaged)");
        if (frame < 0 || frame > lastFrame)
            return bad("it is of frame " + std::to_string(frame) + ", after the last frame file (" +
                       std::to_string(lastFrame) + ")");
        if (!(t >= 0.0) || !std::isfinite(t) || !(dt > 0.0) || !std::isfinite(dt) || nextId < 0)
            return bad("its time or step is not valid");

        // Parsed into a copy; the simulator's state is replaced only when all is well.
        std::vector<glm::vec3> x, v, a;
        std::vector<float> density, pressure, age, kappaWarm, kappaVWarm;
        std::vector<std::int64_t> id;
        std::vector<double> emitterNext;
        In in(bytes);
        for (std::size_t k = 0; k < kHeaderBytes / 8; ++k) in.get<std::uint64_t>();
        in.array(emitterNext, emitters);
        in.array(x, n), in.array(v, n), in.array(a, n), in.array(density, n), in.array(pressure, n);
        in.array(id, n), in.array(age, n), in.array(kappaWarm, n), in.array(kappaVWarm, n);
        // Every value a step reads must be one a step could have written: a
        // NaN acceleration or warm start would spread to the positions, and
        // from there to the grid's cell indices.
        for (std::size_t i = 0; i < n; ++i) {
            if (!finite3(x[i]) || !finite3(v[i]) || !glm::all(glm::lessThanEqual(s.scene.domain.min, x[i])) ||
                !glm::all(glm::lessThanEqual(x[i], s.scene.domain.max)))
                return bad("particle " + std::to_string(i) + " is outside the domain or not finite");
            if (!finite3(a[i]) || !std::isfinite(density[i]) || !std::isfinite(pressure[i]) ||
                !(age[i] >= 0.0f) || !std::isfinite(age[i]) || !std::isfinite(kappaWarm[i]) ||
                !std::isfinite(kappaVWarm[i]) || id[i] < 0)
                return bad("particle " + std::to_string(i) + " has a value no step writes (not finite, or a negative age or id)");
        }
        // An emitter's next layer is due no earlier than its start and within
        // a layer's period of the time (emit() keeps it so): the first layer
        // after the resume is placed (t - next) * speed along the nozzle, which
        // must stay a layer's length, not run off to infinity.
        for (std::size_t k = 0; k < emitterNext.size(); ++k) {
            const Emitter& e = s.scene.emitters[k];
            const double period = 2.0 * s.r / e.speed, next = emitterNext[k];
            const double lo = std::max(double(e.start), t - period), hi = std::max(double(e.start), t + period);
            const double slack = 1e-9 * std::max(1.0, std::abs(hi));
            if (!std::isfinite(next) || next < lo - slack || next > hi + slack)
                return bad("emitter " + std::to_string(k) + "'s next layer time does not fit the checkpoint's time");
        }
        In tot(bytes);
        for (std::size_t k = 0; k < 9; ++k) tot.get<std::uint64_t>();  // magic .. emitters
        Totals T;
        for (std::size_t* v : {&T.steps, &T.particleSteps, &T.densityIterations, &T.divergenceIterations, &T.emitted,
                               &T.drained, &T.expired, &T.guardCorrections})
            *v = std::size_t(tot.get<std::uint64_t>());
        for (double* v : {&T.simulatedS, &T.msNeighbours, &T.msDensity, &T.msPressure, &T.msForces, &T.msAdvect})
            *v = tot.get<double>();

        s.x = std::move(x), s.v = std::move(v), s.a = std::move(a);
        s.density = std::move(density), s.pressure = std::move(pressure), s.id = std::move(id);
        s.age = std::move(age), s.kappaWarm = std::move(kappaWarm), s.kappaVWarm = std::move(kappaVWarm);
        s.emitterNext = std::move(emitterNext);
        s.t = t, s.dt = dt, s.nextId = nextId, s.totals = T;
        return frame;
    } catch (const std::bad_alloc&) {
        return makeError(file, "out of memory while reading the checkpoint");
    } catch (const std::exception& e) {
        return makeError(file, std::string("reading the checkpoint failed: ") + e.what());
    }
}

}  // namespace meniscus::sim
