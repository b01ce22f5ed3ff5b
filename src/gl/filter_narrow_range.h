// GL narrow-range filter (docs/pipeline.md#narrow-range-filter; Truong &
// Yuksel, "A Narrow-Range Filter for Screen-Space Fluid Rendering", I3D 2018):
// the GPU twin of meniscus::cpu::filterNarrowRange, 2-D and separable. Needs a
// current GL 4.3 context on the calling thread.
#pragma once

#include "gl/fluid_segments.h"
#include "gl/padded_passes.h"
#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "meniscus/result.h"
#include "shared/frame_params.h"

namespace meniscus::gl {

using shared::FrameParams;

// Owns the programs, the padded ping-pong buffers and the tap tables; reuse
// one across frames (buffers grow only when needed, tables are rebuilt only
// when the image width or the kernel cap changes).
class NarrowRange {
public:
    // Compiles the shaders; an error carries the driver's log.
    static Result<NarrowRange> create();

    // GL twin of cpu::filterNarrowRange with the parameters of the bound
    // FrameParams block (P.filterIterations, P.nrFilterSizeRadii, P.nrLambda,
    // P.nrMu, P.filterMaxKernelPx, P.nrSeparable, P.radius, P.right.w = f);
    // `frame` is the same block on the host (iterations, separable, kernel cap).
    // `in`: W x H x 1 eye depth (+inf = no fluid); `out` is resized to W x H x 1;
    // in != out. The nearest depth that bounds the kernel is found on the GPU:
    // nothing waits for the GPU here. Ends with the barriers a later shader read
    // or a download needs.
    void run(const FrameParams& frame, const GpuImage& in, GpuImage& out);

private:
    void buildTables(int cap, int paddedWidth);

    FluidSegments segments_;       // of the input; also its nearest depth
    Program filter2D_, filter1D_;
    PaddedPasses passes_;          // padded (pad = kernel cap) depth with a −inf frame
    Buffer taps_, rings_, weights_, meta_;  // tap tables (see buildTables)
    Texture tapsTex_, ringsTex_, weightsTex_, metaTex_;
    int tablesCap_ = -1, tablesWidth_ = -1;
    int tablesLoops_ = 0;          // 2-D taps + rings of the largest disc (loop iterations)
};

}  // namespace meniscus::gl
