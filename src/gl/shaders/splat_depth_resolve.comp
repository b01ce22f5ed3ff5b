#version 430 core
// Before and after the depth splat (SPEC §3.3; splat_depth.comp), one
// invocation per pixel. Mode 0 (clear): the depth bits start at the scene
// depth where a scene is given, else +inf, so the atomic min keeps only hits
// strictly in front of the scene, as the CPU does by starting its min there.
// Mode 1 (resolve): a pixel still at its start value holds no fluid: +inf.
// Scene depths that are not positive (or NaN) start at 0, so that nothing
// beats them, and resolve to +inf, as on the CPU.
layout(local_size_x = 64) in;

layout(std430, binding = 1) buffer Depth { uint depthBits[]; };
layout(std430, binding = 2) readonly buffer Scene { float sceneDepth[]; };

layout(location = 0) uniform uint uPixels;   // W * H
layout(location = 1) uniform int uHasScene;  // 0: no scene depth buffer bound
layout(location = 2) uniform int uMode;      // 0 clear, 1 resolve

const uint kInfBits = 0x7f800000u;

void main() {
    // Grid-stride loop: any image size with a bounded dispatch size.
    for (uint k = gl_GlobalInvocationID.x; k < uPixels; k += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        uint start = kInfBits;
        if (uHasScene != 0) {
            const float s = sceneDepth[k];
            start = s > 0.0 ? floatBitsToUint(s) : 0u;
        }
        if (uMode == 0)
            depthBits[k] = start;
        else if (depthBits[k] == start)
            depthBits[k] = kInfBits;
    }
}
