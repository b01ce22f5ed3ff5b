// The built-in SPH simulator (docs/simulation.md; thesis ch. 2-3; Instant Liquids §4):
// liquid from a scene description alone. One file per method under src/sim/,
// named after its paper; no rendering code. Units: SI throughout (metres,
// seconds, kilograms, kg/m^3, m/s, m/s^2, Pa).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/params.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus::sim {

enum class Solver {
    Dfsph,      // Bender & Koschier 2015: divergence-free + constant-density solvers (default)
    Sph,        // Muller, Charypar & Gross 2003: state equation k(rho - rho0), spiky/viscosity/poly6 kernels
    Ballistic,  // Instant Liquids §4: mass points under gravity, colliders only, no pressure solve
    Pbf,        // Macklin & Muller 2013: position-based fluids (density constraints, XSPH)
};
bool solverFromName(const std::string& name, Solver* out);  // "dfsph", "sph", "ballistic", "pbf"
const char* solverName(Solver s);
// Which compilation of the solvers' loops runs on this CPU: "avx2+fma" (x86-64
// CPUs since 2013) or "baseline (sse2)"; MENISCUS_SIM_SIMD=baseline in the
// environment picks the latter. The two give frames that differ in the last
// bits (fused multiply-adds); each gives the same frames for any thread count.
const char* vectorPath();

struct Box {
    glm::vec3 min{0.0f};  // metres
    glm::vec3 max{0.0f};  // metres
};

// A static obstacle the fluid cannot enter. Box and sphere are solid volumes;
// a plane keeps the fluid on the side its normal points to; a mesh (OBJ or
// PLY, closed) is a solid volume after its scale and translation.
struct Collider {
    enum class Kind { Box, Sphere, Plane, Mesh } kind = Kind::Box;
    Box box;                       // Kind::Box
    glm::vec3 center{0.0f};        // Kind::Sphere, metres
    float radius = 0.0f;           // Kind::Sphere, metres
    glm::vec3 point{0.0f};         // Kind::Plane: a point on it, metres
    glm::vec3 normal{0, 1, 0};     // Kind::Plane: toward the fluid side (normalised on use)
    std::filesystem::path mesh;    // Kind::Mesh: the file (relative to the scene file's folder)
    glm::vec3 scale{1.0f};         // Kind::Mesh
    glm::vec3 translate{0.0f};     // Kind::Mesh, metres
    // How it is drawn (render scene.json, simulate --render, view --simulate):
    // the JSON text of its "material" object, as scene geometry's
    // (docs/geometry.md; e.g. {"glass": true}); empty: the default. The
    // simulator itself does not read it.
    std::string material;
};

// A block of fluid filled with particles on a cubic lattice of spacing 2r:
// a box, or a ball (`center`, `radius`). For a ball the scene parser sets
// `box` to its bounding box, so a sampler walks the lattice over `box` and
// keeps the points within `radius` of `center`.
struct FluidBlock {
    enum class Shape { Box, Sphere } shape = Shape::Box;
    Box box;                   // Shape::Box; Shape::Sphere: its bounding box
    glm::vec3 center{0.0f};    // Shape::Sphere, metres
    float radius = 0.0f;       // Shape::Sphere, metres
    glm::vec3 velocity{0.0f};  // initial, m/s
};

// A nozzle: a disc of radius `radius` at `position` facing `direction`,
// emitting `rate` particles per second at `speed`, from `start` to `end`.
struct Emitter {
    glm::vec3 position{0.0f};      // metres
    glm::vec3 direction{0, -1, 0}; // normalised on use
    float radius = 0.0f;           // metres; 0: about 4 particle radii
    float speed = 1.0f;            // m/s
    float rate = 0.0f;             // particles per second; 0: fill the disc at `speed`
    float start = 0.0f;            // s
    float end = 1e30f;             // s
};

// Particles entering the box are removed.
struct Drain {
    Box box;
};

struct SimParams {
    Solver solver = Solver::Dfsph;
    float radius = defaults::kSimRadiusM;                   // particle radius r, metres; spacing 2r, support 4r
    float restDensity = defaults::kSimRestDensity;          // rho0, kg/m^3
    // A particle's volume V = m / rho0 as a fraction of (2r)^3; 0: the rest
    // lattice's own (the fluid starts at rho0). SPlisHSPlasH uses 0.8: its
    // lattice starts at 0.8 rho0 and compacts as it falls.
    float particleVolume = 0.0f;
    glm::vec3 gravity{0.0f, -defaults::kSimGravity, 0.0f};  // m/s^2
    float viscosity = defaults::kSimViscosity;              // DFSPH: kinematic nu, m^2/s; SPH: dynamic mu, Pa s; ballistic: unused
    float surfaceTension = 0.0f;                            // SPH: sigma of the colour-field force, N/m; DFSPH: 0 (none)
    float stiffness = defaults::kSimSphStiffness;           // SPH: k of p = k (rho - rho0), m^2/s^2
    float cfl = defaults::kSimCfl;                          // CFL factor (1 as SPlisHSPlasH)
    float minDt = defaults::kSimMinDtS;                     // s
    float maxDt = defaults::kSimMaxDtS;                     // s
    float densityTolerance = defaults::kSimDensityTolerance;      // DFSPH: mean density error, fraction of rho0
    float divergenceTolerance = defaults::kSimDivergenceTolerance; // DFSPH: mean d(rho)/dt times dt, fraction of rho0 (SPlisHSPlasH's maxErrorV)
    int maxIterations = defaults::kSimMaxIterations;        // DFSPH: per solver per step
    float lifetime = 0.0f;                                  // s; 0 = particles live for ever
    int resortEvery = defaults::kSimResortEvery;            // steps between z-order re-sorts of the particles
};

struct Scene {
    std::string name;
    std::filesystem::path file;  // where it was read from (empty when built in code)
    SimParams params;
    Box domain;                  // the tank: particles never leave it
    std::vector<FluidBlock> fluid;
    std::vector<Collider> colliders;
    std::vector<Emitter> emitters;
    std::vector<Drain> drains;
    double duration = 1.0;       // s, in [0, kMaxDuration]
    double fps = defaults::kSimFps;  // frames written per simulated second, in (0, kMaxFps]
};

// The largest duration and frame rate a scene (or simulate's, render's
// --duration and --fps) may ask for, so the frame count, duration x fps, is
// at most 1e9 and always a whole number the loops can count to: 10^6 s is
// eleven days of simulated time, 1000 frames a second a slow motion of 40x.
inline constexpr double kMaxDuration = 1e6;  // s
inline constexpr double kMaxFps = 1000.0;    // 1/s

// JSON scene (docs/scenes.md): a malformed file is an error naming the file,
// the field and the problem.
Result<Scene> parseScene(std::string_view json, const std::string& name);
Result<Scene> readScene(const std::filesystem::path& path);

// Per-step timings and counts (the bench prints them).
struct StepStats {
    double dt = 0.0;             // s
    int densityIterations = 0;   // DFSPH constant-density solver
    int divergenceIterations = 0;
    double densityError = 0.0;   // mean, fraction of rho0, after the solve
    double msNeighbours = 0.0;   // grid, sort, neighbour lists
    double msDensity = 0.0;      // density and DFSPH factor
    double msPressure = 0.0;     // both DFSPH solvers / SPH pressure forces
    double msForces = 0.0;       // non-pressure forces (viscosity, surface tension, gravity)
    double msAdvect = 0.0;       // integration, colliders, emitters, drains
};

struct Totals {
    std::size_t steps = 0;
    std::size_t particleSteps = 0;
    std::size_t densityIterations = 0;
    std::size_t divergenceIterations = 0;
    std::size_t emitted = 0, drained = 0, expired = 0;
    std::size_t guardCorrections = 0;  // particles the collider guard had to put back (0 when the boundaries hold)
    double simulatedS = 0.0;
    double msNeighbours = 0.0, msDensity = 0.0, msPressure = 0.0, msForces = 0.0, msAdvect = 0.0;
};

class Simulator {
public:
    // Samples the fluid blocks and the boundaries; errors for a bad scene (a
    // radius out of range, an empty domain, a fluid block outside it, a mesh
    // collider that cannot be read, more particles than memory allows).
    static Result<std::unique_ptr<Simulator>> create(const Scene& scene);
    ~Simulator();

    // One time step (CFL-adaptive, never past `until` when until > time()).
    Status step(double until = 0.0);
    // Steps until time() reaches t (the last step ends exactly on t).
    Status advanceTo(double t);

    double time() const;
    std::size_t size() const;
    const Scene& scene() const;
    // The particles as a set: positions, id (Int), velocity (m/s), density (kg/m^3), pressure (Pa).
    ParticleSet particles() const;
    std::span<const glm::vec3> positions() const;
    std::span<const glm::vec3> velocities() const;
    std::span<const float> densities() const;   // kg/m^3, at the start of the last step
    std::span<const float> pressures() const;   // Pa, of the last step
    std::span<const std::int64_t> ids() const;
    float particleMass() const;  // kg
    // Restores particles (positions, velocities, ids) and the time, e.g. to
    // resume from a written frame; the boundaries stay.
    Status restore(const ParticleSet& set, double time);
    // The whole state a step reads from the steps before it (the particles in
    // their order with accelerations, ages and DFSPH's warm start; dt, t, the
    // step count, the next id, the emitters' clocks), tagged with `frame`,
    // written atomically to `path` in a small versioned binary format
    // (src/sim/checkpoint.cpp). A run loaded from it makes the same bits as
    // one never stopped.
    Status saveCheckpoint(const std::filesystem::path& path, std::int64_t frame) const;
    // Loads a checkpoint saveCheckpoint wrote for the same scene settings,
    // solver, frame rate and vector path, of a frame at most `lastFrame`;
    // returns its frame. A file cut short, damaged, of another version or
    // scene, or of a later frame is an error naming the file, and the state
    // is left as it was.
    Result<std::int64_t> loadCheckpoint(const std::filesystem::path& path, std::int64_t lastFrame);

    const StepStats& lastStep() const;
    const Totals& totals() const;

    struct Impl;

private:
    explicit Simulator(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace meniscus::sim
