// Whitewater from any particle simulation: diffuse spray, foam and air-bubble
// particles generated from a fluid sequence, after Ihmsen, Akinci, Akinci &
// Teschner, "Unified spray, foam and air bubbles for particle-based fluids",
// The Visual Computer 28 (CGI 2012). A post-process: it reads the fluid's
// positions and velocities frame by frame and never feeds back into the
// fluid. One file, src/sim/whitewater_ihmsen2012.cpp; no rendering code.
// Units: SI (metres, seconds, m/s).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/params.h"
#include "meniscus/particle_view.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus::sim {

// The numbering of SPlisHSPlasH's FoamGenerator, so files interchange.
enum class DiffuseType : std::uint8_t { Foam = 0, Spray = 1, Bubble = 2 };
inline constexpr std::string_view kAttrDiffuseType = "type";       // Int, 1 component: DiffuseType
inline constexpr std::string_view kAttrLifetime = "lifetime";      // Float, 1 component: s of foam life left

struct DiffuseParticles {
    std::vector<glm::vec3> positions;   // metres
    std::vector<glm::vec3> velocities;  // m/s
    std::vector<DiffuseType> type;
    std::vector<float> lifetime;        // s left (only foam ages)
    std::vector<std::int64_t> id;       // unique over the sequence, in the order they were made
    std::size_t size() const { return positions.size(); }
};

// The three potentials of one fluid frame (Ihmsen §4), per particle.
struct Potentials {
    std::vector<float> trappedAir;  // v_diff (eq. 2), m/s
    std::vector<float> waveCrest;   // kappa delta_vn (eqs. 4-7)
    std::vector<float> energy;      // |v|^2 / 2, J/kg
    std::vector<std::uint32_t> neighbours;  // fluid neighbours within h (self excluded)
};
// Each potential's largest value in a frame: the automatic limits average these.
struct PotentialMaxima {
    double trappedAir = 0.0, waveCrest = 0.0, energy = 0.0;
};

// The first parameter out of range, as "field: what is allowed"; empty when all are fine.
std::string checkWhitewaterParams(const WhitewaterParams& p);

// The potentials of `fluid` (positions and velocities; radius r in metres).
// Errors: no velocity attribute, a bad radius.
Result<Potentials> computePotentials(const ParticleView& fluid, float radiusM, const WhitewaterParams& p);
PotentialMaxima maximaOf(const Potentials& p);

// The automatic limits from the mean of the frames' maxima (FoamGenerator's
// automatic mode): tau_min = 0.1 mean, tau_max = mean, for each potential
// whose limits `p` leaves at 0.
WhitewaterParams withAutomaticLimits(const WhitewaterParams& p, const std::vector<PotentialMaxima>& frames);

// The time between two frames of a sequence, s, from how far the particles
// moved along their velocity: the median over particles (matched by id, or by
// index when neither has ids and the counts agree) of (dx . v) / |v|^2, v the
// two frames' mean velocity, over particles moving faster than 0.05 m/s.
// Errors: no velocities, nothing to match, or no particle moving.
Result<double> estimateFrameInterval(const ParticleView& a, const ParticleView& b);

// §6: spray below p.sprayBelow fluid neighbours (within h), bubble above
// p.bubbleAbove, foam between.
DiffuseType classifyDiffuse(int fluidNeighbours, const WhitewaterParams& p);

// §6-7, one step of dt seconds over the fluid frame `fluid` (positions,
// velocities): each diffuse particle is classified by its fluid neighbours,
// then spray moves ballistically under p.gravity, foam moves with the fluid's
// kernel-averaged velocity and loses dt of its lifetime, bubbles feel
// buoyancy and drag toward that velocity; foam whose life ran out and
// particles outside `keepIn` are removed (order kept). The generator's own
// step (below) does the same, with the fluid's region for the box.
Status advectDiffuse(DiffuseParticles& d, const ParticleView& fluid, float radiusM, const WhitewaterParams& p,
                     double dtSeconds, const Bounds& keepIn);

struct WhitewaterStepStats {
    std::size_t generated = 0, removed = 0;
    std::size_t spray = 0, foam = 0, bubbles = 0;  // alive after the step
    double msPotentials = 0.0, msAdvect = 0.0, msGenerate = 0.0;
};

// Keeps the diffuse particles across a sequence's frames. Each step takes the
// next fluid frame (dt seconds after the previous one): the diffuse particles
// of the last step are classified by their fluid-neighbour count (§6),
// advected by type (§7: ballistic spray, foam carried by the fluid, buoyant
// bubbles with drag) and dissolved when their foam lifetime runs out or they
// leave the fluid's region; then this frame's fluid makes new ones (§5),
// which appear from the next step on (FoamGenerator's order). The same
// particles for any thread count.
class WhitewaterGenerator {
public:
    // Errors: parameters out of range (checkWhitewaterParams), limits still
    // automatic (resolve them with withAutomaticLimits first), a bad radius.
    static Result<WhitewaterGenerator> create(const WhitewaterParams& p, float radiusM);

    // Errors: the fluid has no velocities, or invalid attributes. Never throws.
    Result<WhitewaterStepStats> step(const ParticleView& fluid, double dtSeconds);

    const DiffuseParticles& particles() const { return diffuse_; }

private:
    WhitewaterParams p_;
    float radius_ = 0.0f;
    std::int64_t frame_ = 0, nextId_ = 0;
    Bounds region_;  // the fluid's region so far: the diffuse particles that leave it (not upward) dissolve
    DiffuseParticles diffuse_;
    DiffuseParticles pending_;  // made from the last fluid frame, joining at the next step
};

// The diffuse particles as a particle set (velocity, id, type, lifetime), for the writers.
ParticleSet toParticleSet(const DiffuseParticles& d);

}  // namespace meniscus::sim
