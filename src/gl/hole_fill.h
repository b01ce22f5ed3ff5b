// GL hole filling (docs/pipeline.md#hole-filling): the GPU twin of
// meniscus::cpu::fillHoles. Needs a current GL 4.3 context on the calling
// thread.
#pragma once

#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "gl/uniforms.h"
#include "meniscus/params.h"
#include "meniscus/result.h"

namespace meniscus::gl {

// Owns the program and its output images; reuse one across frames.
class HoleFill {
public:
    static Result<HoleFill> create();

    // GL twin of cpu::fillHoles(camera, P.radius, params, sceneDepth, depth,
    // thickness): fills `depth` and `thickness` (P.size; a thickness of
    // another size is left as it is) in place, by swapping in the stage's
    // outputs. `sceneDepth` null or of another size: no scene. Asynchronous.
    void run(const FrameParams& frame, const HoleFillParams& params, const GpuImage* sceneDepth, GpuImage& depth,
             GpuImage& thickness);

private:
    Program program_, sweep_;
    Texture depthTex_, thicknessTex_, sceneTex_;
    GpuImage depthOut_, thicknessOut_;
    GpuImage rowSteps_, columnSteps_;  // hole_fill_sweep.comp's steps (uint bits)
};

}  // namespace meniscus::gl
