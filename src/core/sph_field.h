// The particles as the raycast stage (docs/pipeline.md#ray-cast-surface) reads
// them: a dense grid with cells of at least the SPH support h, so a point's
// neighbours lie in the 3x3x3 cells around its own, and the iso level in the
// field's raw units. Built on the host once per frame (per fluid) and read by
// both backends (the GL one uploads the grid's arrays), so both sum the same
// particles in the same order.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/dense_grid.h"
#include "meniscus/params.h"

namespace meniscus {

struct SphField {
    detail::DenseGrid grid;  // the particles' world positions, cells >= h
    float support = 0.0f;    // h, metres
    float isoRaw = 0.0f;     // iso times the rest value F0 (shared::sphRestField)
    // grid.points() as three arrays, padded with lanes::kLanes - 1 far
    // points, for the four-lane sum.
    std::vector<float> xs, ys, zs;
    // One bit per cell (x-fastest, 32 to a word): set when F < iso all over
    // the cell, because even the sum of W(distance of each particle near it
    // to the cell's box / h) stays below the iso level (with 1e-4 to spare
    // for rounding). Boundary cells reach to infinity on their outer sides.
    std::vector<std::uint32_t> quiet;
};

// The field of these particles for radius r (metres) and the raycast's
// support and iso; false (out untouched) when there are no particles.
bool buildSphField(std::span<const glm::vec3> positions, float radius, const RaycastParams& params, SphField& out);

// F(p) and its gradient direction (shared/sph_surface.h) summed over the
// grid's points within h of p, cell rows in grid order, into four partial
// sums (the point at offset i of its row's range into sum i mod 4, in order)
// added as (s0 + s1) + (s2 + s3): the order the GL twin
// (shaders/raycast.comp) sums in.
void evaluateSphField(const SphField& field, const glm::vec3& p, float& f, glm::vec3& grad);

// Whether p's cell is quiet (SphField::quiet).
bool sphFieldQuiet(const SphField& field, const glm::vec3& p);

// For the ray origin + t dir: a ray parameter up to which its points stay in
// the grid cell of its point at t (a thousandth of a cell short of the
// exit, against rounding); t itself when that point lies outside the grid's
// box (a clamped boundary cell). The GL twin is sphLastInCell in raycast.comp.
float sphFieldLastInCell(const SphField& field, const glm::vec3& origin, const glm::vec3& dir, float t);

// The field as shared::sphRaycast calls it.
struct SphFieldOnGrid {
    const SphField& field;
    void operator()(const glm::vec3& p, float& f, glm::vec3& grad) const { evaluateSphField(field, p, f, grad); }
    bool quiet(const glm::vec3& p) const { return sphFieldQuiet(field, p); }
    float lastInCell(const glm::vec3& origin, const glm::vec3& dir, float t) const {
        return sphFieldLastInCell(field, origin, dir, t);
    }
};

}  // namespace meniscus
