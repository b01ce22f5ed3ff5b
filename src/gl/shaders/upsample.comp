#version 430 core
// Reduced-resolution processing (docs/pipeline.md#reduced-resolution): the
// low-resolution surface at full resolution by depth-aware upsampling, per full
// pixel its four nearest low pixels (shared/upsample.h). The GL twin of
// cpu::upsampleSurface, the same operations in the same order (`precise` in the
// header), so the same bits. Every output pixel is written.
#extension GL_GOOGLE_include_directive : require
#include "upsample.h"

layout(local_size_x = 64) in;

layout(binding = 0) uniform samplerBuffer lowDepth;      // lw*lh eye depth, +inf = none
layout(binding = 1) uniform samplerBuffer lowNormal;     // lw*lh*3 view-space normals
layout(binding = 2) uniform samplerBuffer lowThickness;  // lw*lh metres
layout(binding = 3) uniform samplerBuffer lowNoise;      // lw*lh noise N (uFlags bit 2)
layout(binding = 4) uniform samplerBuffer sceneDepth;    // W*H (uFlags bit 3)
layout(std430, binding = 0) writeonly buffer Depth { float depthOut[]; };
layout(std430, binding = 1) writeonly buffer Normal { float normalOut[]; };
layout(std430, binding = 2) writeonly buffer Thickness { float thicknessOut[]; };
layout(std430, binding = 3) writeonly buffer Noise { float noiseOut[]; };
layout(std430, binding = 4) writeonly buffer Coverage { float coverageOut[]; };

layout(location = 0) uniform ivec2 uFull;   // W, H
layout(location = 1) uniform ivec2 uLow;    // lw, lh
layout(location = 2) uniform int uD;        // divisor
layout(location = 3) uniform float uJump;   // metres (host float, as the CPU)
// Bit 0: low normals, 1: low thickness, 2: low noise (and the noise output), 3: a scene depth.
layout(location = 4) uniform int uFlags;

#define kInf uintBitsToFloat(0x7f800000u)

int lw;

float lowAt(int x, int y) { return texelFetch(lowDepth, y * lw + x).x; }
vec3 normalAt(int x, int y) {
    const int k = 3 * (y * lw + x);
    return vec3(texelFetch(lowNormal, k).x, texelFetch(lowNormal, k + 1).x, texelFetch(lowNormal, k + 2).x);
}

void main() {
    const int W = uFull.x, H = uFull.y, lh = uLow.y;
    lw = uLow.x;
    const bool hasNormal = (uFlags & 1) != 0, hasThickness = (uFlags & 2) != 0, hasNoise = (uFlags & 4) != 0,
               hides = (uFlags & 8) != 0;
    const uint pixels = uint(W) * uint(H);
    for (uint k = gl_GlobalInvocationID.x; k < pixels; k += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        const int x = int(k % uint(W)), y = int(k / uint(W));
        ivec2 tx, ty;
        float fx, fy;
        upsampleTaps(lowCoordinate(y, H, lh, uD), lh, ty, fy);
        upsampleTaps(lowCoordinate(x, W, lw, uD), lw, tx, fx);
        const vec4 w = upsampleWeights(fx, fy);
        const vec4 z = vec4(lowAt(tx.x, ty.x), lowAt(tx.y, ty.x), lowAt(tx.x, ty.y), lowAt(tx.y, ty.y));
        const float c = upsampleCoverage(z, w);
        float depth = kInf, thickness = 0.0, noise = 0.0;
        vec3 n = vec3(0.0);
        if (upsampleIsFluid(c)) {
            const vec4 b = upsampleBlendWeights(z, w, uJump);
            const float sum = upsampleWeightSum(b);
            const float d = upsampleDepth(z, b, sum);
            if (!hides || d < texelFetch(sceneDepth, int(k)).x) {
                depth = d;
                if (hasNormal)
                    n = upsampleNormal(normalAt(tx.x, ty.x), normalAt(tx.y, ty.x), normalAt(tx.x, ty.y),
                                       normalAt(tx.y, ty.y), b);
                if (hasThickness) {
                    const int i00 = ty.x * lw + tx.x, i10 = ty.x * lw + tx.y, i01 = ty.y * lw + tx.x,
                              i11 = ty.y * lw + tx.y;
                    thickness = upsampleLinear(vec4(texelFetch(lowThickness, i00).x, texelFetch(lowThickness, i10).x,
                                                    texelFetch(lowThickness, i01).x, texelFetch(lowThickness, i11).x),
                                               b, sum);
                }
                if (hasNoise) {
                    const int i00 = ty.x * lw + tx.x, i10 = ty.x * lw + tx.y, i01 = ty.y * lw + tx.x,
                              i11 = ty.y * lw + tx.y;
                    noise = upsampleLinear(vec4(texelFetch(lowNoise, i00).x, texelFetch(lowNoise, i10).x,
                                                texelFetch(lowNoise, i01).x, texelFetch(lowNoise, i11).x),
                                           b, sum);
                }
            }
        }
        depthOut[k] = depth;
        normalOut[3u * k] = n.x;
        normalOut[3u * k + 1u] = n.y;
        normalOut[3u * k + 2u] = n.z;
        thicknessOut[k] = thickness;
        if (hasNoise) noiseOut[k] = noise;
        coverageOut[k] = c;
    }
}
