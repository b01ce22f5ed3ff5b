#version 430 core
// The list of 8-pixel row segments (x0 = 8k) of a depth image that hold fluid
// (depth < +inf), for the passes that only need the fluid pixels
// (gl/fluid_segments.h): on llvmpipe a pass over the whole image pays for
// every background pixel as if it were fluid (it runs all code of a shader
// under lane masks) and a fixed cost per work group, and a typical frame is
// mostly background.
// Mode 0 (list), one invocation per segment:
//  - appends the segment's index y * ceil(W/8) + k to the list when it holds
//    fluid (depth < +inf). The order in the list depends on timing; what the
//    passes compute for each pixel does not;
//  - the nearest depth (the narrow-range filter's zMin, which bounds every
//    kernel radius) by atomicMin on the float bits (non-negative IEEE floats
//    order like their bit patterns; +inf when no fluid), the host having set
//    it to +inf.
// Mode 1 (args): the indirect work-group counts of the passes,
//   ceil(count / uPerGroup) groups as (x, y) with x <= 65535.
// llvmpipe: the depth is read through a buffer texture (vectorised);
// storage-buffer accesses run lane by lane, so only the atomics and the list
// use them.
layout(local_size_x = 64) in;

layout(binding = 0) uniform samplerBuffer depth;  // W*H, row 0 = top
layout(std430, binding = 5) buffer ZMin { uint zMinBits; };
layout(std430, binding = 6) buffer Segments { int segCount; int segments[]; };  // segment index y * ceil(W/8) + k
layout(std430, binding = 7) writeonly buffer Args { uint args[3]; };

layout(location = 0) uniform ivec2 uSize;   // W, H of the image
layout(location = 1) uniform int uMode;     // 0 list, 1 args
layout(location = 3) uniform int uPerGroup; // mode 1: segments per work group of the passes

const int kPerInvocation = 4;  // segments; llvmpipe pays per work group
#define kInf uintBitsToFloat(0x7f800000u)

void main() {
    if (uMode == 1) {
        if (gl_GlobalInvocationID.x == 0u) {
            const uint groups = (uint(segCount) + uint(uPerGroup) - 1u) / uint(uPerGroup);
            const uint gx = min(groups, 65535u);
            args[0] = gx;
            args[1] = gx == 0u ? 1u : (groups + gx - 1u) / gx;
            args[2] = 1u;
        }
        return;
    }
    const int W = uSize.x, H = uSize.y;
    const int perRow = (W + 7) / 8, n = perRow * H;
    const int stride = int(gl_NumWorkGroups.x) * 64 * kPerInvocation;
    uint nearest = 0x7f800000u;
    for (int base = int(gl_WorkGroupID.x) * 64 * kPerInvocation; base < n; base += stride) {
        for (int j = 0; j < kPerInvocation; ++j) {
            const int s = base + 64 * j + int(gl_LocalInvocationID.x);
            if (s >= n) break;
            const int y = s / perRow, x0 = (s - y * perRow) * 8;
            const int xEnd = min(x0 + 8, W);
            bool fluid = false;
            for (int x = x0; x < xEnd; ++x) {
                const float z = texelFetch(depth, y * W + x).x;
                nearest = min(nearest, floatBitsToUint(z));
                fluid = fluid || z < kInf;
            }
            if (fluid) segments[atomicAdd(segCount, 1)] = s;
        }
    }
    if (nearest != 0x7f800000u) atomicMin(zMinBits, nearest);
}
