// GL screen-space curvature flow (docs/pipeline.md#curvature-flow; van der
// Laan, Green & Sainz, I3D 2009): the GPU twin of
// meniscus::cpu::filterCurvatureFlow. Needs a current GL 4.3 context on the
// calling thread.
#pragma once

#include "gl/fluid_segments.h"
#include "gl/gpu_image.h"
#include "gl/padded_passes.h"
#include "gl/objects.h"
#include "meniscus/result.h"
#include "shared/frame_params.h"

namespace meniscus::gl {

using shared::FrameParams;

// Owns the programs and the two padded ping-pong buffers; reuse one across
// frames (buffers grow only when needed).
class CurvatureFlow {
public:
    // Compiles the shaders; an error carries the driver's log.
    static Result<CurvatureFlow> create();

    // GL twin of cpu::filterCurvatureFlow with the parameters of the bound
    // FrameParams block (P.filterIterations, P.cfAlpha, P.filterJumpRadii,
    // P.radius, P.up.w = 1/f); `frame` is the same block on the host (for the
    // iteration count). `in`: W x H x 1 eye depth (+inf = no fluid); `out` is
    // resized to W x H x 1; in != out. Asynchronous (nothing waits for the GPU);
    // ends with the barriers a later shader read or a download needs.
    void run(const FrameParams& frame, const GpuImage& in, GpuImage& out);

private:
    Program step_;
    PaddedPasses passes_;     // (W + 2) x (H + 2) with a +inf frame
    FluidSegments segments_;  // of the input (the fluid never changes)
};

}  // namespace meniscus::gl
