#version 430 core
// Buffer fills and copies on the shader cores (gl/buffer_fill.h): on NVIDIA's
// driver glClearBufferSubData and glCopyBufferSubData run on a copy engine at
// tens of GB/s (a 24 MB clear took 0.8 ms on an H200), a compute pass at the
// memory's speed. One 32-bit word per invocation; the same bits either way.
// Mode 2 writes a padded copy of a W x H image in one pass: an image of
// (W + 2 pad) x (H + 2 pad) words, the source inside and uBits in the frame
// (gl/padded_passes.cpp; by the driver that took a clear and H row copies).
layout(local_size_x = 256) in;

layout(std430, binding = 0) writeonly buffer Dst { uint dst[]; };
layout(std430, binding = 1) readonly buffer Src { uint src[]; };

layout(location = 0) uniform uint uBits;   // the fill pattern (mode 0)
layout(location = 1) uniform uint uWords;  // words to write
layout(location = 2) uniform int uMode;    // 0: fill with uBits, 1: copy src, 2: padded copy of src
layout(location = 3) uniform ivec3 uPadded;  // mode 2: W, H, pad of the source image

void main() {
    const uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 256u;
    if (i >= uWords) return;
    if (uMode == 2) {
        const int W = uPadded.x, H = uPadded.y, pad = uPadded.z, PW = W + 2 * pad;
        const int x = int(i % uint(PW)) - pad, y = int(i / uint(PW)) - pad;
        dst[i] = x >= 0 && x < W && y >= 0 && y < H ? src[y * W + x] : uBits;
        return;
    }
    dst[i] = uMode == 1 ? src[i] : uBits;
}
