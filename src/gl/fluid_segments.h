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
    // Segments one invocation of a pass walks, at most (fluid_segments.glsl's
    // uSegmentRounds): more per work group means fewer work groups, which
    // llvmpipe charges for (~0.65 us each), and 16 still leaves many groups for
    // the threads. A pass whose loops run long per pixel asks for fewer (see
    // build), as gallivm stops an invocation's loops after 65,535 iterations in
    // all.
    static constexpr int kMaxRounds = 16;
    // The loop iterations a pass may plan for one invocation (below that cap,
    // leaving room for the round loop itself).
    static constexpr int kLoopBudget = 60000;

    static Result<FluidSegments> create();

    // Lists the segments of `depth` (W x H x 1) with a depth < +inf, and finds
    // its nearest depth (nearestDepthBits); nothing waits for the GPU. Ends
    // with the barriers the passes need. The passes will walk `rounds`
    // segments per invocation, clamped to [1, kMaxRounds].
    void build(const GpuImage& depth, int rounds = kMaxRounds);

    // Binds the list to texture unit `unit` as the pass's isamplerBuffer.
    void bindList(GLuint unit) const;
    // Runs the compute program in use over the listed segments (an indirect
    // dispatch), setting its uSegmentRounds (uniform location 15).
    void dispatch() const;
    // One uint: the float bits of the nearest depth (+inf bits: no fluid).
    const Buffer& nearestDepthBits() const { return zMin_; }

    // The most segments per invocation on the renderer current at create():
    // kMaxRounds on llvmpipe; on a hardware GPU, which has no per-work-group
    // cost to save and many more lanes than 8-pixel segments to fill,
    // kHardwareRounds. MENISCUS_GL_SEGMENT_ROUNDS=1..16 overrides either
    // (A/B timing; what a pixel gets does not depend on it).
    static constexpr int kHardwareRounds = 1;
    int roundsCap() const { return cap_; }

private:
    Program program_;
    int cap_ = kMaxRounds;
    Buffer list_, args_, zMin_;
    Texture listTex_, depthTex_;
    int rounds_ = kMaxRounds;
};

}  // namespace meniscus::gl
