// The particles as the raycast stage (SPEC §3.5a) reads them: a dense grid
// with cells of at least the SPH support h, so a point's neighbours lie in
// the 3x3x3 cells around its own, and the iso level in the field's raw units.
// Built on the host once per frame (per fluid) and read by both backends (the
// GL one uploads the grid's arrays), so both sum the same particles in the
// same order.
#pragma once

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
};

// The field of these particles for radius r (metres) and the raycast's
// support and iso; false (out untouched) when there are no particles.
bool buildSphField(std::span<const glm::vec3> positions, float radius, const RaycastParams& params, SphField& out);

// F(p) and its gradient direction (shared/sph_surface.h) summed over the
// grid's points within h of p, cell rows in grid order, into four partial
// sums (the point at offset i of its row's range into sum i mod 4, in order)
// added as (s0 + s1) + (s2 + s3): the order the GL twin
// (shaders/raycast.comp) sums in.
// Returns true when no point lies in the cells around p's (then f = +0
// exactly, and so everywhere in p's cell).
bool evaluateSphField(const SphField& field, const glm::vec3& p, float& f, glm::vec3& grad);

// For the ray origin + t dir: a ray parameter up to which its points stay in
// the grid cell of its point at t (a thousandth of a cell short of the
// exit, against rounding); t itself when that point lies outside the grid's
// box (a clamped boundary cell). The GL twin is sphLastInCell in raycast.comp.
float sphFieldLastInCell(const SphField& field, const glm::vec3& origin, const glm::vec3& dir, float t);

// The field as shared::sphRaycast calls it.
struct SphFieldOnGrid {
    const SphField& field;
    bool operator()(const glm::vec3& p, float& f, glm::vec3& grad) const { return evaluateSphField(field, p, f, grad); }
    float lastInCell(const glm::vec3& origin, const glm::vec3& dir, float t) const {
        return sphFieldLastInCell(field, origin, dir, t);
    }
};

}  // namespace meniscus
