#version 430 core
// The embedding's particles from a host application's own GL buffer
// (src/gl/host_layers.cpp): each particle's three position floats, found at
// uFirstWord + i * uStrideWords 32-bit words into the host's buffer, copied
// bit for bit into the renderer's packed xyz buffer, which the anisotropic
// kernels (or the splat) then read. Grid-stride: any count in at most
// 65,535 work groups.
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer Host { uint hostWords[]; };
layout(std430, binding = 1) writeonly buffer Packed { uint packedWords[]; };

layout(location = 0) uniform uint uCount;
layout(location = 1) uniform uint uFirstWord;
layout(location = 2) uniform uint uStrideWords;

void main() {
    const uint step = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < uCount; i += step) {
        const uint w = uFirstWord + i * uStrideWords;
        packedWords[3u * i] = hostWords[w];
        packedWords[3u * i + 1u] = hostWords[w + 1u];
        packedWords[3u * i + 2u] = hostWords[w + 2u];
    }
}
