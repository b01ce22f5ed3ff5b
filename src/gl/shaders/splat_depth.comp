#version 430 core
// Depth splat (SPEC §3.3) on the GPU: the exact ray-sphere nearest hit of
// src/cpu/splat.cpp (van der Laan et al. 2009; Cords & Staadt 2008 §2.1), one
// invocation per particle over its exact projected bounding box, the minimum
// kept with atomicMin on the float bits (positive IEEE floats order like their
// unsigned bit patterns). Every operation follows the CPU code, in the same
// order and marked `precise` (no FMA contraction or reassociation), so that
// the two agree to rounding of sqrt/division only.
// Depth buffer: W*H uints, row-major, row 0 = the TOP row (SPEC §2), set
// beforehand by splat_depth_resolve.comp to the scene depth bits (or +inf).
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { float positions[]; };  // world xyz, tightly packed
layout(std430, binding = 1) buffer Depth { uint depthBits[]; };

layout(location = 0) uniform uint uCount;      // particles
layout(location = 1) uniform ivec2 uSize;      // image W, H in pixels
layout(location = 2) uniform vec3 uEye;        // camera position, world
layout(location = 3) uniform vec3 uRight;      // view axes in world space
layout(location = 4) uniform vec3 uUp;
layout(location = 5) uniform vec3 uBack;
layout(location = 6) uniform float uFocalPx;   // camera.focalPx()
layout(location = 7) uniform float uInvFocal;  // 1 / focalPx, rounded on the CPU as there
layout(location = 8) uniform float uRadius;    // metres
layout(location = 9) uniform float uZNear;     // max(camera.nearM, FLT_MIN), metres

// The CPU's sphereBounds: exact projected rectangle [x0, x1) x [y0, y1) of the
// sphere (view centre c, radius r), clipped to the image; empty: x0 >= x1.
ivec4 sphereBounds(vec3 c, float r) {
    const int W = uSize.x, H = uSize.y;
    precise float depth = -c.z;
    if (depth + r <= 0.0) return ivec4(0);
    if (depth - r <= 0.0) return ivec4(0, 0, W, H);
    precise float den = depth * depth - r * r;
    precise float rootX = r * sqrt(max(c.x * c.x + den, 0.0));
    precise float rootY = r * sqrt(max(c.y * c.y + den, 0.0));
    precise vec2 sx = vec2((c.x * depth - rootX) / den, (c.x * depth + rootX) / den);
    precise vec2 sy = vec2((c.y * depth - rootY) / den, (c.y * depth + rootY) / den);
    precise float cx = 0.5 * float(W), cy = 0.5 * float(H);
    precise float xlo = cx + uFocalPx * sx.x, xhi = cx + uFocalPx * sx.y;
    precise float ylo = cy - uFocalPx * sy.y, yhi = cy - uFocalPx * sy.x;  // +y view is up, rows go down
    const float eps = 0.01;  // the CPU's slack; the exact ray test decides coverage
    ivec4 rect;
    rect.x = max(0, int(clamp(ceil(xlo - 0.5 - eps), -1.0, float(W) + 1.0)));
    rect.z = min(W, int(clamp(floor(xhi - 0.5 + eps), -1.0, float(W) + 1.0)) + 1);
    rect.y = max(0, int(clamp(ceil(ylo - 0.5 - eps), -1.0, float(H) + 1.0)));
    rect.w = min(H, int(clamp(floor(yhi - 0.5 + eps), -1.0, float(H) + 1.0)) + 1);
    return rect;
}

void main() {
    const int W = uSize.x;
    precise float halfW = 0.5 * float(uSize.x), halfH = 0.5 * float(uSize.y);
    precise float r2 = uRadius * uRadius;
    // Grid-stride loop: any particle count with a bounded dispatch size.
    for (uint i = gl_GlobalInvocationID.x; i < uCount; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        precise vec3 d = vec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]) - uEye;
        // Camera::toView with glm::dot's order: (x + y) + z.
        precise vec3 c = vec3(d.x * uRight.x + d.y * uRight.y + d.z * uRight.z,
                              d.x * uUp.x + d.y * uUp.y + d.z * uUp.z,
                              d.x * uBack.x + d.y * uBack.y + d.z * uBack.z);
        const ivec4 rect = sphereBounds(c, uRadius);
        for (int y = rect.y; y < rect.w; ++y) {
            precise float ry = -((float(y) + 0.5) - halfH) * uInvFocal;
            for (int x = rect.x; x < rect.z; ++x) {
                // raySphereEyeDepth along the unit ray u: closest approach b, squared
                // miss distance from the offset vector (precision for small, far spheres).
                precise float rx = ((float(x) + 0.5) - halfW) * uInvFocal;
                precise float len = sqrt((rx * rx + ry * ry) + 1.0);
                precise vec3 u = vec3(rx / len, ry / len, -1.0 / len);
                precise float b = u.x * c.x + u.y * c.y + u.z * c.z;
                precise vec3 o = c - b * u;
                precise float h2 = r2 - (o.x * o.x + o.y * o.y + o.z * o.z);
                if (h2 < 0.0) continue;
                precise float z = (b - sqrt(h2)) * (1.0 / len);
                // Nearest hit only: one nearer than the near plane is clipped, not
                // replaced by the exit (uZNear > 0 also rejects hits behind the eye).
                if (!(z >= uZNear)) continue;
                const uint bits = floatBitsToUint(z);
                const uint k = uint(y * W + x);
                // (A plain read before the atomic, to skip useless ones, made
                // llvmpipe slower: 22 -> 18 ms at 1280x720 without it.)
                atomicMin(depthBits[k], bits);
            }
        }
    }
}
