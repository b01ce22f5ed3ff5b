// The two scalar fields of the isosurface path (docs/surface.md), as kernels of the
// squared distance d2 from a particle, in raw units (the rest value F0 turns
// them into the normalised field of include/meniscus/params.h: 1 = fluid at
// rest). One function per field, used by the block marcher and by the direct
// sum the tests check against, so both compute bit-identical values.
#pragma once

#include <cmath>

#include "meniscus/params.h"
#include "shared/sph_kernels.h"

namespace meniscus::surface {

struct Field {
    SurfaceField kind = SurfaceField::Sph;
    float support = 0.0f;    // Rc (thesis) or h (sph), metres
    float support2 = 0.0f;   // support^2
    float invSupport2 = 0.0f;
    float invSupport = 0.0f;
    double rest = 0.0;       // F0: raw field at an interior particle of a 2r lattice
    float isoRaw = 0.0f;     // iso * F0, what corner values are compared with

    // Raw contribution of one particle at squared distance d2 (0 at and beyond
    // the support). Branch-free forms, selects only.
    float kernel(float d2) const { return kind == SurfaceField::Thesis ? thesisKernel(d2) : sphKernel(d2); }

    // Thesis eq. 4.16 with u = (d / (sqrt2 Rc))^2 = d2 / (2 Rc^2):
    // u^2 - u + 1/4 = (u - 1/2)^2, which is how it is evaluated here.
    float thesisKernel(float d2) const {
        const float v = 0.5f * d2 * invSupport2 - 0.5f;
        return d2 < support2 ? v * v : 0.0f;
    }
    // The cubic spline w(q), q = d/h (shared/sph_kernels.h; sigma = 8/(pi h^3)
    // is left to F0). Branch-free: evaluated everywhere, selected inside h.
    float sphKernel(float d2) const {
        const float w = shared::sphKernel(std::sqrt(d2) * invSupport);
        return d2 < support2 ? w : 0.0f;
    }
};

// The field for the parameters (support and iso resolved, F0 summed over the
// lattice as refsurf, the reference ray tracer of the true SPH surface,
// does; docs/quality.md).
Field makeField(const MeshParams& params);

}  // namespace meniscus::surface
