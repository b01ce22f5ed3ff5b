#version 430 core
// Silhouette reduction (Cords & Staadt 2008, "Instant Liquids" §3;
// docs/pipeline.md#silhouette-reduction) on the GPU, second pass after
// silhouette_rows.comp: the column prefix sums that complete the summed-area
// table, one invocation per column 1..W, as the column loop of
// cpu::fluidSummedArea (entry (x, y) += entry (x, y - 1) down the column). A
// column is at most 16384 rows, under llvmpipe's loop cap; neighbouring
// invocations touch neighbouring entries. Integers: exact.

layout(local_size_x = 16) in;

layout(r32ui, binding = 0) uniform uimageBuffer sat;  // (W+1)*(H+1) counts, summed in place

layout(location = 0) uniform ivec2 uSize;  // W, H

void main() {
    const int W = uSize.x, H = uSize.y;
    const int x = int(gl_GlobalInvocationID.x) + 1;  // column 0 is all 0
    if (x > W) return;
    const int stride = W + 1;
    uint sum = 0u;  // row 0 is all 0
    for (int y = 1; y <= H; ++y) {
        const int k = y * stride + x;
        sum += imageLoad(sat, k).x;
        imageStore(sat, k, uvec4(sum));
    }
}
