// Particle-set queries: bounds, radius estimate, summary statistics.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus {

Bounds computeBounds(std::span<const glm::vec3> positions);

// The range of lengths the single-precision pipeline can work with: squared
// distances (and the camera's products of them) stay finite and normal.
inline constexpr float kMaxCoordinateM = 1e18f;  // |x|, |y|, |z| of a particle
inline constexpr float kMinRadiusM = 1e-12f;
inline constexpr float kMaxRadiusM = 1e15f;

// Error (naming `name`) when a coordinate is beyond +-kMaxCoordinateM, with
// the largest one found; non-finite positions are the readers' business.
Status checkCoordinates(std::span<const glm::vec3> positions, const std::string& name);
// Error when the radius is not a number in [kMinRadiusM, kMaxRadiusM].
Status checkRadius(float radiusM);

enum class RadiusMethod {
    FileAttribute,     // the file's own per-particle radius (radius / pscale attribute)
    BulkDensity,       // volume-equivalent radius of the bulk number density
    NearestNeighbour,  // too few neighbours for a density: half the median nearest-neighbour distance
    Fallback,          // fewer than two distinct positions: 1% of the bounds diagonal
};

struct RadiusEstimate {
    float radius = 0.0f;                  // metres
    RadiusMethod method = RadiusMethod::Fallback;
    float medianNeighbourDistance = 0.0f; // metres; 0 when no pair was found
    double bulkNumberDensity = 0.0;       // particles per m^3 in the bulk; 0 when not measured
    std::size_t isolated = 0;             // particles with no neighbour within the kernel's support, left out
    std::string attribute;                // FileAttribute: which attribute
    bool fallback = false;                // method == Fallback

    // One line saying which value was used and how, e.g.
    // "0.0232 m (volume-equivalent radius of the bulk density 1.0e+04 /m^3; 3 isolated particles ignored)".
    std::string describe() const;
};

// The radius the simulation used, estimated from the positions alone:
//  - nearest neighbours through a hashed grid (cells only where particles are,
//    so one far outlier costs nothing), median distance d (coincident points ignored);
//  - the SPH number density n_i = sum_j W(|x_i - x_j|, 2.5 d) (cubic spline,
//    normalised) around each particle; its 75th percentile is the bulk (free
//    surfaces, splashes and spray are less dense), and r = 0.5 n^(-1/3), half
//    the spacing of a cubic lattice of that density;
//  - with too few neighbours for a density (sheets, sprays, tiny sets) half the
//    median nearest-neighbour distance; with fewer than two distinct
//    positions 1% of the bounds diagonal (0.01 m for a single point).
// Deterministic and independent of the thread count. Large sets are sampled
// (an even stride, at most 2^16 queries).
RadiusEstimate estimateRadius(std::span<const glm::vec3> positions);

// The default radius of a set: the median of the file's own per-particle
// radius attribute ("radius", "pscale": Houdini's, "particle_radius") when it
// has a usable one, else estimateRadius(positions).
RadiusEstimate defaultRadius(const ParticleSet& set);

// When `set` has a smoothing length (kAttrSmoothingLengthNames: one float
// per particle) and no radius attribute (kAttrRadiusNames), adds the
// attribute "radius" = h / (2 hPerSpacing) for each particle (h being
// hPerSpacing particle spacings of 2 r; defaults::kHPerSpacing) and returns
// the smoothing length's name; otherwise returns "" and changes nothing. An
// error when hPerSpacing is not a positive number; a bad h becomes a bad
// radius, which the renderer reports by particle.
Result<std::string> addRadiusFromSmoothingLength(ParticleSet& set, float hPerSpacing);

struct MinMedianMax {
    double min = 0, median = 0, max = 0;
};

// min / median / max over one component of a Float attribute (or nullopt if the
// attribute is missing or empty).
std::optional<MinMedianMax> attributeStats(const ParticleSet& set, std::string_view name, int component = 0);

// Drops particles whose position has a non-finite coordinate, in every
// attribute alike. Returns how many were dropped.
std::size_t dropNonFinite(ParticleSet& set);

// ---------------------------------------------------------------- selection (src/core/select.cpp)

// DualSPHysics' particle types as its output's Type array holds them
// (DualSPHysics v5 src/source/JSph.cpp, JSph::SaveData, and
// JDebugSphCpu::GetCodeType; PartVTK -vars:+type "Type (fixed,moving,floating,fluid)").
enum class DualSphysicsType : int { Fixed = 0, Moving = 1, Floating = 2, Fluid = 3 };

// Which particles to keep (the CLI's --select): clauses ATTR OP VALUE, all of
// which must hold:
//   selection := clause { "&&" clause }
//   clause    := operand op value
//   operand   := NAME | NAME.C | "|" NAME "|"
//   op        := == | != | < | <= | > | >=
//   value     := a number | for an attribute called Type (any case), one of
//                DualSPHysics' types: fixed (0), moving (1), floating (2),
//                bound or boundary (0 to 2: == and != only), fluid (3)
// NAME is an attribute as the file's reader names it (velocity, density, id,
// Type, Press, ...; `meniscus info` lists them), matched exactly, else in any
// case; x, y, z or position.x ... are the positions. A vector needs a component,
// NAME.x / .y / .z or NAME.0, .1, ... , or |NAME|, its length. Values are in
// the file's own units (metres, m/s, kg/m^3). Compared in the attribute's
// precision (a float attribute against the value rounded to float); a NaN
// value matches only !=.
enum class SelectOp { Equal, NotEqual, Less, LessEqual, Greater, GreaterEqual };
struct SelectClause {
    std::string text;          // the clause as written, trimmed (for messages)
    std::string attribute;     // the operand's name as written, bars removed ("velocity.y", "Type")
    bool magnitude = false;    // |NAME|
    SelectOp op = SelectOp::Equal;
    double low = 0, high = 0;  // the value; a group of types (bound) spans [low, high], else low == high
};
struct ParticleFilter {
    std::string text;                  // the whole expression as given
    std::vector<SelectClause> clauses; // none: every particle
    bool empty() const { return clauses.empty(); }
};

// Parses a selection; an empty or blank text gives an empty filter. An error
// ("--select 'TEXT': ..." naming the bad clause or token) for anything else
// than the grammar above.
Result<ParticleFilter> parseSelection(std::string_view text);

// Keeps the particles of `set` that match every clause, dropping the others
// from the positions and every attribute alike (order kept). Errors, naming
// `name` (the file): an attribute the set does not have (listing those it
// has), a vector attribute without a component or a component it lacks, an
// attribute whose value count is not particles x components, and a selection
// that leaves no particle. An empty filter changes nothing.
Status applySelection(ParticleSet& set, const ParticleFilter& filter, const std::string& name);

}  // namespace meniscus
