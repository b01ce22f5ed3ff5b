// GL silhouette reduction (Cords & Staadt 2008, "Instant Liquids" §3;
// docs/pipeline.md#silhouette-reduction): the GPU twin of
// cpu::reduceSilhouettes, the fluid mask's summed-area table, each fluid
// pixel's fluid fraction S and the liquid faded by it into the scene colour
// behind. Needs a current GL 4.3 context (gl::Context) on the calling thread.
#pragma once

#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/result.h"

namespace meniscus::gl {

// Owns the three programs and the table; reuse one across frames (the table
// grows only when needed).
class SilhouetteReduction {
public:
    // Compiles the shaders; an error carries the driver's log.
    static Result<SilhouetteReduction> create();

    // The GL twin of cpu::reduceSilhouettes, bit for bit: `color` (W x H x 4,
    // the camera's size) faded in place into `behind` (the scene colour,
    // W x H x 4) by each fluid pixel's alpha of S, where `depth` (W x H x 1,
    // +inf = none) has fluid; `silhouette` (resized to W x H x 1) gets S, 0
    // where there is no fluid. Images of another size leave the colour as it
    // is and S 0, as on the CPU. Asynchronous: nothing waits for the GPU here.
    void run(const Camera& camera, const GpuImage& depth, const GpuImage& behind, float radius,
             const SilhouetteParams& params, GpuImage& color, GpuImage& silhouette);

private:
    Program rows_, columns_, resolve_;
    Buffer sat_;          // (W+1)*(H+1) uint counts, the summed-area table
    Texture satTex_;      // R32UI buffer texture over it (image in the table passes, sampler in the resolve)
    Texture depthTex_;    // R32F buffer texture over the fluid depth
    Texture behindTex_;   // RGBA32F buffer texture over the scene colour
    Texture colorTex_;    // RGBA32F image buffer over the colour (faded in place)
    Texture silTex_;      // R32F image buffer over S
    GpuImage liquid_;     // the colour before the fade (the background pixels next to the liquid read it)
    Texture liquidTex_;   // RGBA32F buffer texture over it
};

}  // namespace meniscus::gl
