// Particle-set queries: bounds, radius estimate, summary statistics.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "meniscus/types.h"

namespace meniscus {

Bounds computeBounds(std::span<const glm::vec3> positions);

struct RadiusEstimate {
    float radius = 0.0f;                 // metres
    float medianNeighbourDistance = 0.0f; // metres; 0 when no pair was found
    bool fallback = false;               // true when no neighbour distance could be measured
};

// Particle radius as half the median nearest-neighbour distance (SPEC §3.3),
// found with a uniform grid (expected O(N)). Coincident particles are ignored.
// With fewer than two distinct positions it falls back to 1% of the bounds
// diagonal (or 0.01 m for a single point) and sets `fallback`.
RadiusEstimate estimateRadius(std::span<const glm::vec3> positions);

struct MinMedianMax {
    double min = 0, median = 0, max = 0;
};

// min / median / max over one component of a Float attribute (or nullopt if the
// attribute is missing or empty).
std::optional<MinMedianMax> attributeStats(const ParticleSet& set, std::string_view name, int component = 0);

// Drops particles whose position has a non-finite coordinate, in every
// attribute alike. Returns how many were dropped.
std::size_t dropNonFinite(ParticleSet& set);

}  // namespace meniscus
