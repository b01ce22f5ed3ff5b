#version 430 core
// Reduced-resolution processing (docs/pipeline.md#reduced-resolution): each
// fluid pixel whose upsampling coverage c is under 1 blended into the scene
// colour behind it by c (shared/upsample.h: upsampleEdgeBlend), in place. The
// GL twin of cpu::blendFluidEdges.
#extension GL_GOOGLE_include_directive : require
#include "fluids.h"
#include "upsample.h"

layout(local_size_x = 64) in;

layout(binding = 0) uniform samplerBuffer depth;     // W*H eye depth, +inf = none
layout(binding = 1) uniform samplerBuffer coverage;  // W*H c
layout(binding = 2) uniform samplerBuffer behind;    // W*H linear RGBA, the scene colour
layout(std430, binding = 0) buffer Color { vec4 color[]; };
// Several fluids (shared/fluids.h), when uSplit != 0: the colour's split E, T.
layout(std430, binding = 1) buffer Emission { vec4 emission[]; };
layout(std430, binding = 2) buffer Transmit { vec4 transmit[]; };

layout(location = 0) uniform ivec2 uSize;  // W, H
layout(location = 1) uniform int uSplit;

#define kInf uintBitsToFloat(0x7f800000u)

void main() {
    const uint pixels = uint(uSize.x) * uint(uSize.y);
    for (uint k = gl_GlobalInvocationID.x; k < pixels; k += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        if (!(texelFetch(depth, int(k)).x < kInf)) continue;
        const float c = texelFetch(coverage, int(k)).x;
        if (c < 1.0) color[k] = upsampleEdgeBlend(color[k], texelFetch(behind, int(k)), c);
        if (uSplit != 0) {
            emission[k] = vec4(fluidEdgeEmission(emission[k].rgb, c), 1.0);
            transmit[k] = vec4(fluidEdgeTransmittance(transmit[k].rgb, c), 0.0);
        }
    }
}
