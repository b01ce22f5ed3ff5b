#version 430 core
// Several fluids (docs/pipeline.md#several-fluids; Instant Liquids §5): the
// fluids, each shaded on its own, composited front to back per pixel
// (shared/fluids.h). The GL twin of cpu::compositeFluids, operation for
// operation.
#extension GL_GOOGLE_include_directive : require
#include "fluids.h"

layout(local_size_x = 64) in;

layout(binding = 0) uniform samplerBuffer sceneColor;  // W*H linear RGBA
layout(binding = 1) uniform samplerBuffer sceneDepth;  // W*H, +inf = sky
// Per layer (units 2 + kMaxFluids * image + layer): depth, normal (3 per
// pixel), thickness, colour over the scene, emission E, transmittance T.
layout(binding = 2) uniform samplerBuffer layerDepth[kMaxFluids];
layout(binding = 6) uniform samplerBuffer layerNormal[kMaxFluids];
layout(binding = 10) uniform samplerBuffer layerThickness[kMaxFluids];
layout(binding = 14) uniform samplerBuffer layerColor[kMaxFluids];
layout(binding = 18) uniform samplerBuffer layerEmission[kMaxFluids];
layout(binding = 22) uniform samplerBuffer layerTransmit[kMaxFluids];

// Written through image buffers: llvmpipe scatters those in SIMD but runs
// storage-buffer accesses lane by lane.
layout(rgba32f, binding = 0) writeonly uniform imageBuffer outColor;    // W*H linear RGBA
layout(r32f, binding = 1) writeonly uniform imageBuffer outDepth;       // W*H
layout(r32f, binding = 2) writeonly uniform imageBuffer outNormal;      // W*H*3
layout(r32f, binding = 3) writeonly uniform imageBuffer outThickness;   // W*H
layout(r32f, binding = 4) writeonly uniform imageBuffer outFluid;       // W*H

layout(location = 0) uniform ivec2 uSize;   // W, H
layout(location = 1) uniform int uLayers;   // layers composited, 1 .. kMaxFluids
layout(location = 2) uniform ivec4 uFluid;  // each layer's fluid index
layout(location = 3) uniform ivec2 uHas;    // scene colour, scene depth bound (image-sized)

#define kInf uintBitsToFloat(0x7f800000u)

void main() {
    const uint pixels = uint(uSize.x) * uint(uSize.y);
    for (uint p = gl_GlobalInvocationID.x; p < pixels; p += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        const int i = int(p);
        const float sceneZ = uHas.y != 0 ? texelFetch(sceneDepth, i).x : kInf;
        // Fetched here, not in the no-fluid branch below: llvmpipe (Mesa 22.3)
        // returned other pixels' texels for a fetch in that branch.
        const vec4 scene = texelFetch(sceneColor, i);
        // Every layer is read with a constant index (the macro below; llvmpipe
        // runs fetches through a sampler array indexed by a variable, and
        // private arrays indexed per pixel, lane by lane): its depth, whether
        // it is drawn here, and then its rank in the stable nearest-first
        // order of the CPU's insertion sort (ties: the lower layer first).
        float z[kMaxFluids];
        bool drawn[kMaxFluids];
        int rank[kMaxFluids];
        for (int k = 0; k < kMaxFluids; ++k) {
            z[k] = kInf;
            drawn[k] = false;
            rank[k] = 0;
        }
#define READ_DEPTH(k)                                       \
        if (k < uLayers) {                                  \
            z[k] = texelFetch(layerDepth[k], i).x;          \
            drawn[k] = fluidInFront(z[k], sceneZ);          \
        }
        READ_DEPTH(0)
        READ_DEPTH(1)
        READ_DEPTH(2)
        READ_DEPTH(3)
        int m = 0;
        for (int k = 0; k < kMaxFluids; ++k) {
            m += drawn[k] ? 1 : 0;
            for (int q = 0; q < kMaxFluids; ++q)
                rank[k] += drawn[q] && (z[q] < z[k] || (z[q] == z[k] && q < k)) ? 1 : 0;
        }
        if (m == 0) {
            imageStore(outColor, i, uHas.x != 0 ? scene : vec4(0.0));
            imageStore(outDepth, i, vec4(kInf));
            for (int c = 0; c < 3; ++c) imageStore(outNormal, 3 * i + c, vec4(0.0));
            imageStore(outThickness, i, vec4(0.0));
            imageStore(outFluid, i, vec4(-1.0));
            continue;
        }
        // Back to front: the farthest layer's own colour, then each nearer
        // one's E + T * (what is behind), as the CPU's loop; the thickness
        // summed in layer order; the nearest layer's depth, normal and index.
        vec3 e[kMaxFluids], t[kMaxFluids], c[kMaxFluids];
        precise float thickness = 0.0;
        float frontZ = kInf, frontFluid = -1.0;
        vec3 frontNormal = vec3(0.0);
#define READ_LAYER(k)                                                                                      \
        if (drawn[k]) {                                                                                    \
            thickness = thickness + texelFetch(layerThickness[k], i).x;                                    \
            e[k] = texelFetch(layerEmission[k], i).rgb;                                                    \
            t[k] = texelFetch(layerTransmit[k], i).rgb;                                                    \
            c[k] = texelFetch(layerColor[k], i).rgb;                                                       \
            if (rank[k] == 0) {                                                                            \
                frontZ = z[k];                                                                             \
                frontFluid = float(uFluid[k]);                                                             \
                frontNormal = vec3(texelFetch(layerNormal[k], 3 * i).x, texelFetch(layerNormal[k], 3 * i + 1).x, \
                                   texelFetch(layerNormal[k], 3 * i + 2).x);                               \
            }                                                                                              \
        }
        READ_LAYER(0)
        READ_LAYER(1)
        READ_LAYER(2)
        READ_LAYER(3)
        vec3 acc = vec3(0.0);
        for (int r = kMaxFluids - 1; r >= 0; --r)
            for (int k = 0; k < kMaxFluids; ++k)
                if (drawn[k] && rank[k] == r) acc = r == m - 1 ? c[k] : fluidOver(e[k], t[k], acc);
        imageStore(outColor, i, vec4(acc, 1.0));
        imageStore(outDepth, i, vec4(frontZ));
        imageStore(outNormal, 3 * i, vec4(frontNormal.x));
        imageStore(outNormal, 3 * i + 1, vec4(frontNormal.y));
        imageStore(outNormal, 3 * i + 2, vec4(frontNormal.z));
        imageStore(outThickness, i, vec4(thickness));
        imageStore(outFluid, i, vec4(frontFluid));
    }
}
