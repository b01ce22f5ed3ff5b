// Which particles are spray (docs/pipeline.md#classification; the NVIDIA SSFR
// patent): those whose density is below SprayParams::sprayDensity times the
// rest density. Used by the Renderer to take them out of the surface and draw
// them as drops.
#pragma once

#include <cstdint>
#include <vector>

#include "meniscus/params.h"
#include "meniscus/particle_view.h"

namespace meniscus {

// Each particle's density over the rest density. From the `density`
// attribute over restDensityKgM3 (0: the attribute's median, the bulk being
// at rest density) when the view has one; else an SPH estimate, the sum of
// the cubic spline (support 4 r, as the isosurface path's field and refsurf)
// over the neighbours times the rest volume (2r)^3 per particle, over the same
// sum inside a simple cubic lattice of spacing 2r: 1 in the bulk of a
// SPlisHSPlasH-like sampling, 0.85 on a flat free surface (0.72 at an edge,
// 0.61 at a corner), 0.32 for a lone drop (its own kernel's peak). Deterministic and the same for any thread count.
std::vector<float> relativeDensity(const ParticleView& particles, float radiusM, float restDensityKgM3);

// 1 where relativeDensity < sprayDensity, else 0.
std::vector<std::uint8_t> classifySpray(const ParticleView& particles, float radiusM, const SprayParams& params);

}  // namespace meniscus
