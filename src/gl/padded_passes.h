// Ping-pong passes over a padded copy of an image, as the narrow-range filter
// and the curvature flow run them: two (W + 2 pad) x (H + 2 pad) float buffers
// with a constant frame (so a stencil needs no bounds tests), read through
// buffer textures and written through image buffers (llvmpipe vectorises
// those, not storage buffers), each pass dispatched over the fluid segments,
// the last one writing the W x H output directly. Needs a current GL 4.3
// context on the calling thread.
#pragma once

#include <functional>

#include "gl/fluid_segments.h"
#include "gl/gpu_image.h"
#include "gl/objects.h"

namespace meniscus::gl {

class PaddedPasses {
public:
    static PaddedPasses create();

    // Both buffers become the frame value `frameBits` with `in` (W x H x 1)
    // copied inside at (pad, pad): driver fills and row copies (memset and
    // memcpy on llvmpipe, cheaper than a shader's scattered stores). `out` is
    // attached as the last pass's destination.
    void load(const GpuImage& in, int pad, GLuint frameBits, const GpuImage& out);

    // Runs `passes` passes of the program in use over `segments`: source on
    // texture unit 0, destination on image unit 0 (the output in the last
    // pass). Before each, beforePass(i, last) sets the pass's uniforms.
    void run(int passes, const FluidSegments& segments, const std::function<void(int, bool)>& beforePass) const;

private:
    Buffer a_, b_;                 // the padded ping-pong buffers
    Texture texA_, texB_, outTex_; // R32F buffer textures over a_, b_ and the output
};

}  // namespace meniscus::gl
