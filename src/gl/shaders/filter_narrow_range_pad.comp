#version 430 core
// Narrow-range filter (SPEC §3.5, src/cpu/filter_narrow_range.cpp) on the GPU:
// the passes around the iterations. The ping-pong buffers are the image with
// a frame of uPad pixels of −inf (filled by the host beforehand): taps there
// are "in front" and are dropped with their mirror, as on the CPU.
// Mode 0 (pad): A's interior = the input; also the nearest input depth (the
//   CPU's zMin, which bounds every kernel radius) by atomicMin on the float
//   bits (non-negative IEEE floats order like their bit patterns; +inf when no
//   fluid), the host having set it to +inf.
// Mode 1 (unpad): out pixel = A's padded pixel.
layout(local_size_x = 64) in;

layout(std430, binding = 1) readonly buffer Img { float img[]; };  // W*H, row 0 = top
layout(std430, binding = 2) buffer PadA { float padA[]; };
layout(std430, binding = 4) writeonly buffer Out { float outImg[]; };
layout(std430, binding = 5) buffer ZMin { uint zMinBits; };

layout(location = 0) uniform ivec2 uSize;  // W, H of the image
layout(location = 1) uniform int uMode;    // 0 pad, 1 unpad
layout(location = 2) uniform int uPad;     // frame width, pixels

const int kPerInvocation = 16;  // llvmpipe pays per work group: a few pixels each

void main() {
    const int W = uSize.x, H = uSize.y, PW = W + 2 * uPad;
    const int n = W * H;
    const int first = int(gl_WorkGroupID.x) * 64 * kPerInvocation + int(gl_LocalInvocationID.x);
    uint nearest = 0x7f800000u;
    for (int j = 0; j < kPerInvocation; ++j) {
        const int k = first + 64 * j;
        if (k >= n) break;
        const int x = k % W, y = k / W;
        const int p = (y + uPad) * PW + x + uPad;
        if (uMode == 0) {
            const float z = img[k];
            padA[p] = z;
            nearest = min(nearest, floatBitsToUint(z));
        } else {
            outImg[k] = padA[p];
        }
    }
    if (uMode == 0 && nearest != 0x7f800000u) atomicMin(zMinBits, nearest);
}
