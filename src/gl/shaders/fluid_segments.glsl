// Walking the 8-pixel row segments that hold fluid, as listed by
// fluid_segments.comp (gl/fluid_segments.h), in a pass dispatched with
// FluidSegments::dispatch: work groups of 64 invocations, 8 per segment (one
// SIMD vector on llvmpipe, lanes on adjacent pixels), uSegmentRounds segments
// per invocation (chosen in FluidSegments::build, set by FluidSegments::dispatch).
// The includer declares local_size_x = 64 and
//   layout(binding = N) uniform isamplerBuffer uSegments;
// ([0]: count; [1 + e]: segment y * ceil(W/8) + k) and keeps uniform location
// 15 for this.
layout(location = 15) uniform int uSegmentRounds;

// This invocation's pixel (x, y) in round k: 1 when on the image, 0 when past
// its right edge (skip it), -1 past the end of the list (stop).
int segmentPixel(int k, int W, out int x, out int y) {
    x = 0;
    y = 0;
    const int group = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);
    const int e = (group * uSegmentRounds + k) * 8 + (int(gl_LocalInvocationID.x) >> 3);
    if (e >= texelFetch(uSegments, 0).x) return -1;
    const int perRow = (W + 7) / 8, s = texelFetch(uSegments, 1 + e).x;
    y = s / perRow;
    x = (s - y * perRow) * 8 + (int(gl_LocalInvocationID.x) & 7);
    return x < W ? 1 : 0;
}
