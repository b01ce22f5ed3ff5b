// GL shading and compositing (docs/pipeline.md#shading): the GPU twin of
// meniscus::cpu::shadeAndComposite. Needs a current GL 4.3 context
// (gl::Context) on the calling thread.
#pragma once

#include "gl/fluid_segments.h"
#include "gl/environment.h"
#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "gl/uniforms.h"
#include "meniscus/params.h"
#include "meniscus/result.h"

namespace meniscus::gl {

// Owns the shading program; reuse one across frames.
class Shading {
public:
    // Compiles the shader; an error carries the driver's log.
    static Result<Shading> create();

    // GL twin of cpu::shadeAndComposite(camera, scene, depth, normals,
    // thickness, shading): W x H x 4 linear RGBA, the scene colour where there
    // is no fluid in front of it, shaded fluid (alpha 1) where there is.
    // Camera, material and light from the bound frame block (binding 0,
    // uploaded by the caller from `frame`: P.fluidColor, P.absorptionPerM,
    // P.lightDirWorld, P.specular, P.shininess). As on the CPU, a scene
    // (colour and depth), normals or thickness image of another size than
    // P.size counts as absent: transparent background, normals facing the eye,
    // zero thickness; a depth of another size means no fluid (the scene
    // alone). With `noise` (the surface noise N, P.size) and its parameters,
    // foam of cover shared::noiseFoamCover(N) is laid over the shaded fluid,
    // as cpu::shadeAndComposite's noise arguments; without (or of another
    // size), no foam. Likewise `whitening` (the velocity whitening map,
    // docs/pipeline.md#noise-and-foam; Instant Liquids §4) and its parameters
    // lay white water of cover strength * map over that, as
    // cpu::shadeAndComposite's whitening arguments. Asynchronous: nothing waits
    // for the GPU here.
    void run(const FrameParams& frame, const GpuImage& sceneColor, const GpuImage& sceneDepth, const GpuImage& depth,
             const GpuImage& normals, const GpuImage& thickness, GpuImage& color, const GpuImage* noise = nullptr,
             const NoiseParams* noiseParams = nullptr, const GpuImage* whitening = nullptr,
             const WhiteningParams* whiteningParams = nullptr, GpuImage* emission = nullptr,
             GpuImage* transmit = nullptr, const EnvironmentGpu* environment = nullptr);
    // With `emission` and `transmit`, also the split C = E + T S of several
    // fluids (shared/fluids.h), as cpu::LayerSplit: W x H x 4 each, zero where
    // this fluid is not drawn.

private:
    Program program_;
    static constexpr int kInputs = 5;     // scene colour and depth, depth, normals, thickness
    static constexpr int kNoiseUnit = 6;  // the noise: after the segment list (unit kInputs)
    static constexpr int kWhiteUnit = 7;  // the whitening map
    Buffer dummy_;                        // read in place of an absent input (never used)
    Texture inTex_[kInputs];              // buffer textures over the inputs (units 0..4)
    Texture noiseTex_;                    // over the noise (unit kNoiseUnit)
    Texture whiteTex_;                    // over the whitening map (unit kWhiteUnit)
    Texture outTex_;                      // RGBA32F image buffer over the colour
    Texture emissionTex_, transmitTex_;   // RGBA32F image buffers over E and T (several fluids)
    FluidSegments segments_;              // of the depth (unit kInputs)
};

}  // namespace meniscus::gl
