#version 430 core
// Silhouette reduction (Cords & Staadt 2008, "Instant Liquids" §3;
// docs/pipeline.md#silhouette-reduction) on the GPU, first pass: the row prefix
// sums of the fluid mask into the summed-area table, one invocation per image
// row, as the row loop of cpu::fluidSummedArea. Entry (x + 1, y + 1) of the
// (W + 1) x (H + 1) table gets the fluid pixels of row y in [0, x]; column 0
// gets 0 (row 0 is the host's fill). A row is at most kMaxImageSizePx = 16384
// pixels, under llvmpipe's 65,535 loop iterations. Integers: exact in any
// order.

layout(local_size_x = 16) in;

// Buffer textures and image buffers: llvmpipe gathers and scatters those in
// SIMD but runs storage-buffer accesses lane by lane.
layout(binding = 0) uniform samplerBuffer depth;               // W*H eye depth, +inf = none
layout(r32ui, binding = 0) writeonly uniform uimageBuffer sat;  // (W+1)*(H+1) counts

layout(location = 0) uniform ivec2 uSize;  // W, H

#define kInf uintBitsToFloat(0x7f800000u)

void main() {
    const int W = uSize.x, H = uSize.y;
    const int y = int(gl_GlobalInvocationID.x);
    if (y >= H) return;
    const int row = (y + 1) * (W + 1);
    imageStore(sat, row, uvec4(0u));
    uint run = 0u;
    for (int x = 0; x < W; ++x) {
        run += texelFetch(depth, y * W + x).x < kInf ? 1u : 0u;  // NaN counts as no fluid, as on the CPU
        imageStore(sat, row + x + 1, uvec4(run));
    }
}
