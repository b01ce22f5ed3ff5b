// GL compositing of several fluids (docs/pipeline.md#several-fluids): the GPU twin of
// meniscus::cpu::compositeFluids (shaders/composite_fluids.comp). Needs a
// current GL 4.3 context with 2 + 6 shared::kMaxFluids texture units for a
// compute shader (32 on Mesa and NVIDIA).
#pragma once

#include <span>

#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "meniscus/result.h"
#include "shared/fluids.h"

namespace meniscus::gl {

// One fluid's images (each W x H; normal with 3 channels, colour, emission
// and transmittance with 4), as cpu::FluidLayerImages.
struct FluidLayerGpu {
    int fluid = 0;
    const GpuImage* depth = nullptr;
    const GpuImage* normal = nullptr;
    const GpuImage* thickness = nullptr;
    const GpuImage* color = nullptr;
    const GpuImage* emission = nullptr;
    const GpuImage* transmit = nullptr;
};

class FluidCompositor {
public:
    // Compiles the shader; an error when the driver has too few texture units.
    static Result<FluidCompositor> create();

    // As cpu::compositeFluids: the layers (1 .. kMaxFluids, all of the first
    // layer's depth size) over the scene, into colour, depth, normal,
    // thickness and fluid index. Asynchronous.
    void run(std::span<const FluidLayerGpu> layers, const GpuImage& sceneColor, const GpuImage& sceneDepth,
             GpuImage& color, GpuImage& depth, GpuImage& normal, GpuImage& thickness, GpuImage& fluid);

private:
    static constexpr int kUnits = 2 + 6 * shared::kMaxFluids;
    Program program_;
    static constexpr int kOutputs = 5;  // colour, depth, normal, thickness, fluid index
    Texture tex_[kUnits];
    Texture outTex_[kOutputs];  // image buffers over the outputs
    Buffer dummy_;  // read by the units of absent inputs (never used)
};

}  // namespace meniscus::gl
