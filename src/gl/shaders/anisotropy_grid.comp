#version 430 core
#extension GL_GOOGLE_include_directive : require
// The anisotropic kernels' neighbour grid (anisotropy_grid.glsl) built on the
// GPU by a counting sort of the particles by bucket, one pass per uPass:
//  0 count:   each particle's bucket (bucketOf), counted with atomicAdd;
//  1 chunks:  the counts summed per chunk of kChunk buckets;
//  2 scan:    one invocation: the chunks' sums made exclusive prefix sums;
//  3 starts:  each bucket's first slot (starts, uBuckets + 1 of them), and
//             the scatter's cursor (counts, reused);
//  4 scatter: each particle's index into a slot of its bucket (atomicAdd on
//             the cursor: in any order);
//  5 order:   each slot's particle moved to its rank by index within its
//             bucket, with its position (sorted: xyz, index bits in w), so
//             the walk of anisotropy.comp sums in one fixed order whatever
//             order the scatter ran in.
// Every loop of an invocation stays under llvmpipe's 65,535 iterations for
// up to 2^25 buckets (kChunk x 65,535), and a bucket's rank loop for up to
// 65,535 particles in one bucket.
#include "anisotropy_grid.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { float positions[]; };  // world xyz, packed
layout(std430, binding = 1) coherent buffer Counts { uint counts[]; };          // uBuckets
layout(std430, binding = 2) buffer Starts { uint starts[]; };                   // uBuckets + 1
layout(std430, binding = 3) buffer Chunks { uint chunkSums[]; };
layout(std430, binding = 4) buffer Unsorted { uint unsorted[]; };               // uCount particle indices
layout(std430, binding = 5) writeonly buffer Sorted { vec4 sorted[]; };         // uCount
layout(std430, binding = 6) buffer BucketOf { uint bucketOf[]; };               // uCount

layout(location = 3) uniform int uPass;

const uint kChunk = 512u;

vec3 positionOf(uint i) { return vec3(positions[3u * i], positions[3u * i + 1u], positions[3u * i + 2u]); }

void main() {
    const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    const uint chunks = (uBuckets + kChunk - 1u) / kChunk;
    if (uPass == 0) {
        for (uint i = gl_GlobalInvocationID.x; i < uCount; i += stride) {
            const uint b = anisotropyBucket(anisotropyCell(positionOf(i)));
            bucketOf[i] = b;
            atomicAdd(counts[b], 1u);
        }
    } else if (uPass == 1) {
        for (uint c = gl_GlobalInvocationID.x; c < chunks; c += stride) {
            uint sum = 0u;
            const uint end = min(uBuckets, (c + 1u) * kChunk);
            for (uint k = c * kChunk; k < end; ++k) sum += counts[k];
            chunkSums[c] = sum;
        }
    } else if (uPass == 2) {
        if (gl_GlobalInvocationID.x != 0u) return;
        uint run = 0u;
        for (uint c = 0u; c < chunks; ++c) {
            const uint sum = chunkSums[c];
            chunkSums[c] = run;
            run += sum;
        }
        starts[uBuckets] = run;
    } else if (uPass == 3) {
        for (uint c = gl_GlobalInvocationID.x; c < chunks; c += stride) {
            uint run = chunkSums[c];
            const uint end = min(uBuckets, (c + 1u) * kChunk);
            for (uint k = c * kChunk; k < end; ++k) {
                const uint n = counts[k];
                starts[k] = run;
                counts[k] = run;
                run += n;
            }
        }
    } else if (uPass == 4) {
        for (uint i = gl_GlobalInvocationID.x; i < uCount; i += stride)
            unsorted[atomicAdd(counts[bucketOf[i]], 1u)] = i;
    } else {
        for (uint s = gl_GlobalInvocationID.x; s < uCount; s += stride) {
            const uint i = unsorted[s];
            const uint b = bucketOf[i];
            const uint begin = starts[b], end = starts[b + 1u];
            uint rank = 0u;
            for (uint t = begin; t < end; ++t) rank += unsorted[t] < i ? 1u : 0u;
            sorted[begin + rank] = vec4(positionOf(i), uintBitsToFloat(i));
        }
    }
}
