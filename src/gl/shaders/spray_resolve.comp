#version 430 core
// Spray drops (docs/pipeline.md#classification, docs/pipeline.md#noise-and-foam;
// the NVIDIA SSFR patent, US 8,947,430, draws the particles that left the body
// of water as spray particles) on the GPU, per pixel after spray_splat.comp: the
// GL twin of the compositing loop of cpu::drawSpray. Where a pixel's fixed-point
// optical depth is positive, its cover is 1 - exp(-sum) (sprayCover) and the lit
// drop colour is laid over the colour in place (sprayOver; alpha over as the
// CPU's, `precise`); elsewhere the colour is left as it is and the cover is 0.
// Formulas: src/shared/spray.h.
#extension GL_GOOGLE_include_directive : require
#include "spray.h"

layout(local_size_x = 64) in;

// Buffer textures and image buffers: llvmpipe gathers and scatters those in
// SIMD but runs storage-buffer accesses lane by lane.
layout(binding = 0) uniform isamplerBuffer sums;                // W*H fixed-point optical depths
layout(rgba32f, binding = 0) uniform imageBuffer color;         // W*H linear RGBA, composited in place
layout(r32f, binding = 1) writeonly uniform imageBuffer cover;  // W*H cover, 0 = none

layout(location = 0) uniform uint uPixels;    // W*H
layout(location = 1) uniform vec3 uDropColor;  // SprayParams::color
layout(location = 2) uniform vec3 uLit;       // shared::sprayLight (host): ambient plus key, per colour

void main() {
    for (uint k = gl_GlobalInvocationID.x; k < uPixels; k += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        const int s = texelFetch(sums, int(k)).x;
        if (s <= 0) {
            imageStore(cover, int(k), vec4(0.0));
            continue;
        }
        const float c = sprayCover(s);
        const vec4 px = imageLoad(color, int(k));
        const vec3 rgb = sprayOver(px.rgb, c, uDropColor, uLit);
        imageStore(color, int(k), vec4(rgb, sprayAlphaOver(px.a, c)));
        imageStore(cover, int(k), vec4(c));
    }
}
