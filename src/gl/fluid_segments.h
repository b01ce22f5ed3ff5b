// The 8-pixel row segments of a depth image that hold fluid, listed on the GPU
// (shaders/fluid_segments.comp), and indirect dispatches over them for the
// passes that only change fluid pixels (shaders/fluid_segments.glsl): the
// narrow-range filter and the thickness blur. On llvmpipe a pass over the
// whole image pays for each background pixel about as much as for a fluid one
// (every branch runs under lane masks) plus a fixed cost per work group;
// walking only these segments skips the ~70% of a typical frame that is
// background. Needs a current GL 4.3 context on the calling thread.
#pragma once

#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "meniscus/result.h"

namespace meniscus::gl {

class FluidSegments {
public:
    // Segments per work group of a pass (64 invocations, 8 per segment,
    // fluid_segments.glsl's kSegmentRounds = 4 rounds).
    static constexpr GLuint kPerGroup = 32;

    static Result<FluidSegments> create();

    // Lists the segments of `depth` (W x H x 1) with a depth < +inf, and finds
    // its nearest depth (nearestDepthBits); nothing waits for the GPU. Ends
    // with the barriers the passes need.
    void build(const GpuImage& depth);

    // Binds the list to texture unit `unit` as the pass's isamplerBuffer.
    void bindList(GLuint unit) const;
    // Runs the bound compute program over the listed segments (indirect).
    void dispatch() const;
    // One uint: the float bits of the nearest depth (+inf bits: no fluid).
    const Buffer& nearestDepthBits() const { return zMin_; }

private:
    Program program_;
    Buffer list_, args_, zMin_;
    Texture listTex_, depthTex_;
};

}  // namespace meniscus::gl
