#version 430 core
// After the splat (docs/pipeline.md#thickness; splat.comp), one invocation per
// pixel: the fixed-point chord sums become thickness in metres, times the
// calibration weight w (shared::thicknessWeight), by shared/splat_chords.h as
// on the CPU.
#extension GL_GOOGLE_include_directive : require
#include "frame_params.h"
#include "splat_chords.h"

layout(local_size_x = 64) in;

layout(std430, binding = 3) buffer Chords { uint chordFixed[]; };  // float thickness afterwards

layout(location = 0) uniform uint uPixels;  // W * H

void main() {
    // Grid-stride loop: any image size with a bounded dispatch size.
    for (uint k = gl_GlobalInvocationID.x; k < uPixels; k += gl_NumWorkGroups.x * gl_WorkGroupSize.x)
        chordFixed[k] = floatBitsToUint(chordSumToMetres(chordFixed[k], P.radius, P.thicknessWeight));
}
