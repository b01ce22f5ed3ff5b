#version 430 core
// Buffer fills and copies on the shader cores (gl/buffer_fill.h): on NVIDIA's
// driver glClearBufferSubData and glCopyBufferSubData run on a copy engine at
// tens of GB/s (a 24 MB clear took 0.8 ms on an H200), a compute pass at the
// memory's speed. One 32-bit word per invocation; the same bits either way.
layout(local_size_x = 256) in;

layout(std430, binding = 0) writeonly buffer Dst { uint dst[]; };
layout(std430, binding = 1) readonly buffer Src { uint src[]; };

layout(location = 0) uniform uint uBits;   // the fill pattern (mode 0)
layout(location = 1) uniform uint uWords;  // words to write
layout(location = 2) uniform int uCopy;    // 0: fill with uBits, 1: copy src

void main() {
    const uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 256u;
    if (i >= uWords) return;
    dst[i] = uCopy != 0 ? src[i] : uBits;
}
