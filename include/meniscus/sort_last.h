// Sort-last rendering over several processes: each process splats its own share
// of the particles, the partial images are combined exactly (nearest depth
// wins, thickness chords add), and the rest of the pipeline runs once, on the
// root, on the combined image. The combination is exact and order-independent
// (a min of floats and a wrapping sum of fixed-point integers), so the picture
// does not depend on how the particles were split.
//
// The library knows no transport: a SplatCompositor is handed in through
// RenderSettings::compositor. The MPI one is meniscus_mpi's
// (include/meniscus/mpi.h); tests use in-process ones.
#pragma once

#include <cstdint>

#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus {

// One process's depth splat and thickness chords before the thickness is
// resolved (calibrated, blurred, upsampled).
struct SplatPartial {
    // Eye depth of the nearest hit per pixel (metres), +inf where none;
    // combined by min. The splat camera's size (the low camera's with
    // RenderSettings::fluidScale < 1).
    Image<float> depth;
    // Per pixel of the thickness grid (the splat camera's pixels, or one per
    // d x d block with ThicknessParams::resolutionDivisor d > 1): the summed
    // chord lengths of its ray inside the spheres, in fixed point (one unit =
    // radius / shared::kChordScale, each chord rounded to the nearest unit);
    // combined by a wrapping (mod 2^32) sum.
    Image<std::uint32_t> chords;
};

class SplatCompositor {
public:
    virtual ~SplatCompositor() = default;
    // Called by every process once per splat (per surface of a frame), in the
    // same order on all: replaces `partial` by the combination over all
    // processes on the root; on the others what is left in it is unspecified.
    // An error (a failed transfer) ends the frame with it.
    virtual Status composite(SplatPartial& partial) = 0;
    // Whether this process is the one that finishes the frame: render()
    // returns the picture there, and empty Aovs (every image 0 x 0) on the
    // others, which stop after the composite.
    virtual bool root() const = 0;
};

}  // namespace meniscus
