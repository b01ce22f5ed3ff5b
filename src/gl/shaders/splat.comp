#version 430 core
// Depth splat and thickness chords (SPEC §3.3, §3.4) on the GPU: the exact
// ray-sphere nearest hit of src/cpu/splat.cpp (van der Laan et al. 2009; Cords
// & Staadt 2008 §2.1), one invocation per particle over its exact projected
// bounding box.
//  - Depth: the minimum kept with atomicMin on the float bits (positive IEEE
//    floats order like their unsigned bit patterns), so it is exact and
//    order-independent. Every operation follows the CPU code, in the same order
//    and marked `precise` (no FMA contraction or reassociation), so the two
//    agree to rounding of sqrt/division only.
//  - Thickness (uThickness != 0): the chord of the pixel ray inside the sphere,
//    clipped to eye depths [near, scene), summed with atomicAdd in fixed point
//    (GL 4.3 has no float atomics): units of radius / kChordScale, so the sum
//    does not depend on the order the GPU runs the particles in.
// Depth buffer: W*H uints, row-major, row 0 = the TOP row (SPEC §2), set
// beforehand by splat_resolve.comp to the scene depth bits (or +inf).
#extension GL_GOOGLE_include_directive : require
#include "frame_params.h"
#include "splat_common.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { float positions[]; };  // world xyz, tightly packed
layout(std430, binding = 1) buffer Depth { uint depthBits[]; };
layout(std430, binding = 2) readonly buffer Scene { float sceneDepth[]; };
layout(std430, binding = 3) buffer Chords { uint chordFixed[]; };

layout(location = 0) uniform uint uCount;     // particles
layout(location = 1) uniform int uHasScene;   // sceneDepth is bound and camera-sized
layout(location = 2) uniform int uThickness;  // also sum the chords

// The CPU's sphereBounds: exact projected rectangle [x0, x1) x [y0, y1) of the
// sphere (view centre c, radius r), clipped to the image; empty: x0 >= x1.
ivec4 sphereBounds(vec3 c, float r) {
    const int W = P.size.x, H = P.size.y;
    const float f = P.right.w;
    precise float depth = -c.z;
    if (depth + r <= 0.0) return ivec4(0);
    if (depth - r <= 0.0) return ivec4(0, 0, W, H);
    precise float den = depth * depth - r * r;
    precise float rootX = r * sqrt(max(c.x * c.x + den, 0.0));
    precise float rootY = r * sqrt(max(c.y * c.y + den, 0.0));
    precise vec2 sx = vec2((c.x * depth - rootX) / den, (c.x * depth + rootX) / den);
    precise vec2 sy = vec2((c.y * depth - rootY) / den, (c.y * depth + rootY) / den);
    precise float cx = 0.5 * float(W), cy = 0.5 * float(H);
    precise float xlo = cx + f * sx.x, xhi = cx + f * sx.y;
    precise float ylo = cy - f * sy.y, yhi = cy - f * sy.x;  // +y view is up, rows go down
    const float eps = 0.01;  // the CPU's slack; the exact ray test decides coverage
    ivec4 rect;
    rect.x = max(0, int(clamp(ceil(xlo - 0.5 - eps), -1.0, float(W) + 1.0)));
    rect.z = min(W, int(clamp(floor(xhi - 0.5 + eps), -1.0, float(W) + 1.0)) + 1);
    rect.y = max(0, int(clamp(ceil(ylo - 0.5 - eps), -1.0, float(H) + 1.0)));
    rect.w = min(H, int(clamp(floor(yhi - 0.5 + eps), -1.0, float(H) + 1.0)) + 1);
    return rect;
}

void main() {
    const int W = P.size.x;
    const float invF = P.up.w, zNear = P.eye.w, r = P.radius;
    precise float halfW = 0.5 * float(P.size.x), halfH = 0.5 * float(P.size.y);
    precise float r2 = r * r;
    const float toFixed = kChordScale / r;
    // Grid-stride loop: any particle count with a bounded dispatch size.
    for (uint i = gl_GlobalInvocationID.x; i < uCount; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        precise vec3 d = vec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]) - P.eye.xyz;
        // Camera::toView with glm::dot's order: (x + y) + z.
        precise vec3 c = vec3(d.x * P.right.x + d.y * P.right.y + d.z * P.right.z,
                              d.x * P.up.x + d.y * P.up.y + d.z * P.up.z,
                              d.x * P.back.x + d.y * P.back.y + d.z * P.back.z);
        const ivec4 rect = sphereBounds(c, r);
        for (int y = rect.y; y < rect.w; ++y) {
            precise float ry = -((float(y) + 0.5) - halfH) * invF;
            for (int x = rect.x; x < rect.z; ++x) {
                // raySphereEyeDepth along the unit ray u: closest approach b, squared
                // miss distance from the offset vector (precision for small, far spheres).
                precise float rx = ((float(x) + 0.5) - halfW) * invF;
                precise float len = sqrt((rx * rx + ry * ry) + 1.0);
                precise vec3 u = vec3(rx / len, ry / len, -1.0 / len);
                precise float b = u.x * c.x + u.y * c.y + u.z * c.z;
                precise vec3 o = c - b * u;
                precise float h2 = r2 - (o.x * o.x + o.y * o.y + o.z * o.z);
                if (h2 < 0.0) continue;
                precise float h = sqrt(h2);
                precise float t0 = b - h;
                const uint k = uint(y * W + x);
                if (uThickness != 0) {
                    // The CPU's clip: [max(t0, near len), min(t1, scene len)) along the ray.
                    precise float t1 = b + h;
                    precise float tn = P.eye.w * len;
                    precise float tf = uHasScene != 0 ? sceneDepth[k] * len : 1.0 / 0.0;
                    precise float chord = (tf < t1 ? tf : t1) - (t0 < tn ? tn : t0);
                    if (chord > 0.0) atomicAdd(chordFixed[k], uint(chord * toFixed + 0.5));
                }
                precise float z = t0 * (1.0 / len);
                // Nearest hit only: one nearer than the near plane is clipped, not
                // replaced by the exit (zNear > 0 also rejects hits behind the eye).
                if (!(z >= zNear)) continue;
                // (A plain read before the atomic, to skip useless ones, made
                // llvmpipe slower: 22 -> 18 ms at 1280x720 without it.)
                atomicMin(depthBits[k], floatBitsToUint(z));
            }
        }
    }
}
