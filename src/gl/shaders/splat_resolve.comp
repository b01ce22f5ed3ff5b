#version 430 core
// Before and after the splat (SPEC §3.3, §3.4; splat.comp), one invocation per
// pixel. Mode 0 (clear): the depth bits start at the scene depth where a scene
// is given, else +inf, so the atomic min keeps only hits strictly in front of
// the scene, as the CPU does by starting its min there; the chord sums start
// at 0. Mode 1 (resolve): a pixel still at its start value holds no fluid:
// +inf; the fixed-point chord sums become thickness in metres, times the
// calibration weight w (cpu::thicknessWeight). Scene depths that are not
// positive (or NaN) start at 0, so that nothing beats them, and resolve to
// +inf, as on the CPU.
#extension GL_GOOGLE_include_directive : require
#include "frame_params.h"
#include "splat_common.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 1) buffer Depth { uint depthBits[]; };
layout(std430, binding = 2) readonly buffer Scene { float sceneDepth[]; };
layout(std430, binding = 3) buffer Chords { uint chordFixed[]; };  // float thickness after mode 1

layout(location = 0) uniform uint uPixels;     // W * H
layout(location = 1) uniform int uHasScene;    // 0: no scene depth buffer bound
layout(location = 2) uniform int uMode;        // 0 clear, 1 resolve
layout(location = 3) uniform int uThickness;   // the chord buffer is bound

const uint kInfBits = 0x7f800000u;

void main() {
    const float toMetres = P.radius / kChordScale;
    // Grid-stride loop: any image size with a bounded dispatch size.
    for (uint k = gl_GlobalInvocationID.x; k < uPixels; k += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        uint start = kInfBits;
        if (uHasScene != 0) {
            const float s = sceneDepth[k];
            start = s > 0.0 ? floatBitsToUint(s) : 0u;
        }
        if (uMode == 0) {
            depthBits[k] = start;
            if (uThickness != 0) chordFixed[k] = 0u;
        } else {
            if (depthBits[k] == start) depthBits[k] = kInfBits;
            if (uThickness != 0) chordFixed[k] = floatBitsToUint((float(chordFixed[k]) * toMetres) * P.thicknessWeight);
        }
    }
}
