// GL thickness at reduced resolution (docs/pipeline.md#thickness; ThicknessParams::
// resolutionDivisor 2 or 4): the GPU twin of the low-resolution path of
// cpu::splatDepthAndThickness (lowResThickness in src/cpu/thickness.cpp).
// Needs a current GL 4.3 context and the frame's parameter block bound.
#pragma once

#include "gl/filter_separable.h"
#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "gl/splat.h"
#include "meniscus/result.h"

namespace meniscus::gl {

class LowResThickness {
public:
    // Compiles the shader; an error carries the driver's log.
    static Result<LowResThickness> create();

    // Chords through the centres of divisor x divisor blocks (splat), blurred
    // on that grid with sigma projected by each block's nearest raw depth and
    // focal length f / divisor (blur), bilinearly upsampled onto the fluid
    // pixels of rawDepth (0 elsewhere) into `thickness` (W x H). The splat's
    // particles must be uploaded. Asynchronous.
    void run(const FrameParams& frame, Splat& splat, SeparableFilters& blur, const GpuImage* sceneDepth,
             const GpuImage& rawDepth, int divisor, GpuImage& thickness);

    // run() in halves, for sort-last (meniscus/sort_last.h): the chords as
    // fixed-point sums on the block grid (cpu::splatPartial's), then a
    // (combined) grid of sums resolved in place, blurred with rawDepth and
    // upsampled onto its fluid pixels (cpu::resolveThickness). run() is the
    // two in a row.
    void chords(const FrameParams& frame, Splat& splat, const GpuImage* sceneDepth, int divisor, GpuImage& chords);
    void resolve(const FrameParams& frame, Splat& splat, SeparableFilters& blur, const GpuImage& rawDepth,
                 int divisor, GpuImage& chords, GpuImage& thickness);

private:
    // The nearest depth of each divisor x divisor block of `full` into `low`.
    void nearestPerBlock(const FrameParams& frame, int divisor, const GpuImage& full, GpuImage& low);

    Program program_;
    GpuImage low_, lowDepth_, lowScene_;  // chords, nearest raw depth, nearest scene depth per block
};

}  // namespace meniscus::gl
