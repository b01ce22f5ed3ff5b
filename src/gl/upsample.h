// GL reduced-resolution processing (docs/pipeline.md#reduced-resolution): the
// GPU twins of cpu::reduceSceneDepth, cpu::upsampleSurface and
// cpu::blendFluidEdges (shaders/upsample_reduce.comp, upsample.comp,
// upsample_edges.comp; the formulas in src/shared/upsample.h), bit for bit.
// Needs a current GL 4.3 context on the calling thread.
#pragma once

#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "meniscus/result.h"

namespace meniscus::gl {

class Upsampling {
public:
    static Result<Upsampling> create();

    // `low` (resized to lw x lh x 1): the farthest depth of `full` (W x H x 1)
    // under each low pixel, for divisor d.
    void reduceSceneDepth(const GpuImage& full, int lw, int lh, int d, GpuImage& low);

    // The low surface (lowDepth's size) at W x H for divisor d: depth, normal,
    // thickness, noise (only when lowNoise is given) and coverage resized and
    // written everywhere, hidden where not in front of `sceneDepth` (W x H x 1;
    // null or another size: nothing hides it). Low images of another size
    // than lowDepth are left out, as on the CPU.
    void upsample(const GpuImage& lowDepth, const GpuImage& lowNormal, const GpuImage& lowThickness,
                  const GpuImage* lowNoise, const GpuImage* sceneDepth, int W, int H, int d, float jumpM,
                  GpuImage& depth, GpuImage& normal, GpuImage& thickness, GpuImage* noise, GpuImage& coverage);

    // Each fluid pixel of `depth` with coverage c < 1 blended into `behind` by
    // c, in `color` (all W x H; other sizes: unchanged).
    // With `emission` and `transmit` (several fluids), their split too, as
    // cpu::blendFluidEdges.
    void blendEdges(const GpuImage& depth, const GpuImage& coverage, const GpuImage& behind, GpuImage& color,
                    GpuImage* emission = nullptr, GpuImage* transmit = nullptr);

private:
    Program reduce_, upsample_, edges_;
    Texture tex_[5];
    Buffer dummy_;  // a binding for the inputs and outputs that are left out
};

}  // namespace meniscus::gl
