#version 430 core
#extension GL_GOOGLE_include_directive : require
// Scene stage (docs/pipeline.md#scene) on the GPU: the GL twin of
// src/cpu/scene.cpp. The default studio (checker floor, two back walls forming
// the inside corner of a box around the particles, or the floor alone) ray-cast
// per pixel into colour and eye depth, with the procedural sky
// (src/shared/sky.h), or the HDR environment map (src/shared/environment.h),
// wherever no plane is hit. Rendering the opaque scene first
// and splatting fluid against its depth is the compositing order of van der
// Laan et al. 2009 (US 8,947,430) and Instant Liquids (Cords & Staadt 2008,
// §3).
// Every operation follows castRow in the same order, `precise` (no FMA
// contraction or reassociation), so the two agree to the rounding of division
// and sqrt. Camera from the frame block P; the studio from plain uniforms
// (lighting per plane and the sun computed on the host by shared::studioShading,
// as the CPU does once per image); colours and per-pixel formulas from
// src/shared/studio_shade.h.
// Work: one invocation per column and uRows rows (llvmpipe pays per work group).
#include "frame_params.h"
#include "sky.h"
#include "studio_shade.h"

// The HDR environment map (src/shared/environment.h, gl/environment.h): its
// texels, size (width 0: none, the procedural sky), rotation and intensity.
layout(std430, binding = 7) readonly buffer EnvironmentTexels { float environmentTexels[]; };
layout(location = 7) uniform ivec2 uEnvSize;
layout(location = 8) uniform vec2 uEnvParams;  // rotation (turns), intensity
layout(location = 9) uniform vec3 uEnvIrradiance[9];  // its irradiance (9 locations, 9-17)
#include "environment.h"

layout(local_size_x = 64) in;

layout(std430, binding = 1) writeonly buffer Color { vec4 color[]; };  // W*H linear RGBA
layout(std430, binding = 2) writeonly buffer Depth { float depth[]; };  // W*H, +inf = sky

layout(location = 0) uniform vec4 uPlanes;   // floorY, wallX, wallZ, wallTopY
layout(location = 1) uniform vec2 uNormals;  // wallXNormal, wallZNormal (+1 / -1)
layout(location = 2) uniform vec4 uChecker;  // 1/checkerM, corner darkening scale, fade start, 1/fade length
layout(location = 18) uniform vec3 uLit[3];  // flat lighting of floor, wall x, wall z, per colour (18-20)
layout(location = 4) uniform int uRows;      // rows per invocation
layout(location = 5) uniform vec3 uSun;      // the sky's sun, unit world (studio.lightDirWorld)
// 0: the floor alone (studio.walls false): uPlanes.yz is the box's centre, the
// origin of the checker and of the radial fade; no walls, no corner darkening.
layout(location = 6) uniform int uWalls;

#define kInf uintBitsToFloat(0x7f800000u)

void main() {
    const int W = P.size.x, H = P.size.y;
    const int x = int(gl_GlobalInvocationID.x);
    const int y0 = int(gl_GlobalInvocationID.y) * uRows;
    if (x >= W) return;
    const vec3 eye = P.eye.xyz, right = P.right.xyz, up = P.up.xyz, back = P.back.xyz;
    const float invF = P.up.w, nearM = P.eye.w;
    const float floorY = uPlanes.x, wallX = uPlanes.y, wallZ = uPlanes.z, topY = uPlanes.w;
    const float nX = uNormals.x, nZ = uNormals.y;
    const float invChecker = uChecker.x, aoScale = uChecker.y, fadeStart = uChecker.z, invFade = uChecker.w;
    precise float halfW = 0.5 * float(W), halfH = 0.5 * float(H);
    precise float vx = ((float(x) + 0.5) - halfW) * invF;
    for (int y = y0; y < min(y0 + uRows, H); ++y) {
        // World ray D = dirToWorld(view ray with z = -1): eye + t D has eye depth t.
        precise float vy = -((float(y) + 0.5) - halfH) * invF;
        precise vec3 rowDir = vy * up - back;
        precise float Dx = rowDir.x + vx * right.x, Dy = rowDir.y + vx * right.y, Dz = rowDir.z + vx * right.z;
        // Each plane counts only where hit from its front, beyond the near plane
        // and inside the corner (walls above the floor and below their top,
        // everything on the camera's side of the walls).
        precise float tF = (floorY - eye.y) / Dy;
        precise float fxF = (eye.x + tF * Dx - wallX) * nX, fzF = (eye.z + tF * Dz - wallZ) * nZ;
        const bool walls = uWalls != 0;
        const bool okF = Dy < 0.0 && tF >= nearM && (!walls || (fxF >= 0.0 && fzF >= 0.0));
        precise float tX = (wallX - eye.x) / Dx;
        precise float yX = eye.y + tX * Dy;
        precise float sX = Dx * nX, fzX = (eye.z + tX * Dz - wallZ) * nZ;
        const bool okX = walls && sX < 0.0 && tX >= nearM && yX >= floorY && yX <= topY && fzX >= 0.0;
        precise float tZ = (wallZ - eye.z) / Dz;
        precise float yZ = eye.y + tZ * Dy;
        precise float sZ = Dz * nZ, fxZ = (eye.x + tZ * Dx - wallX) * nX;
        const bool okZ = walls && sZ < 0.0 && tZ >= nearM && yZ >= floorY && yZ <= topY && fxZ >= 0.0;
        // The nearest valid hit (in exact arithmetic at most one is valid).
        float t = okF ? tF : kInf;
        int plane = okF ? 0 : -1;
        plane = okX && tX < t ? 1 : plane;
        t = okX && tX < t ? tX : t;
        plane = okZ && tZ < t ? 2 : plane;
        t = okZ && tZ < t ? tZ : t;
        const uint k = uint(y) * uint(W) + uint(x);
        depth[k] = t;
        // Branch-free, as the CPU's plane pass (llvmpipe would run both sides of
        // a divergent branch anyway): the plane's colour with a finite stand-in
        // ray length where none is hit, the sky once, then a select.
        const float tt = plane >= 0 ? t : 0.0;  // keeps the arithmetic below finite
        // Plane coordinates from the corner edges, so the squares line up
        // across the corner; (a, b) are also the distances to the two other planes.
        precise float dx = (eye.x + tt * Dx - wallX) * nX;
        precise float dy = eye.y + tt * Dy - floorY;
        precise float dz = (eye.z + tt * Dz - wallZ) * nZ;
        const float a = plane == 1 ? dz : dx;
        const float b = plane == 0 ? dz : dy;
        precise float ca = a * invChecker, cb = b * invChecker;
        const bool odd = ((studioFloorInt(ca) + studioFloorInt(cb)) & 1) != 0;
        const bool onFloor = plane == 0;
        const vec3 base = odd ? (onFloor ? kStudioFloorDark : kStudioWallDark)
                              : (onFloor ? kStudioFloorLight : kStudioWallLight);
        const vec3 lit = onFloor ? uLit[0] : plane == 1 ? uLit[1] : uLit[2];
        precise float ao = walls ? 1.0 - 0.25 * (studioCornerFall(a, aoScale) + studioCornerFall(b, aoScale)) : 1.0;
        precise vec3 shade = lit * ao;
        precise vec3 c = base * shade;
        // The weight of the sky: -1 where no plane is hit; the far floor fades
        // into the sky (hides the checker's aliasing there).
        const float reach = walls ? max(a, b) : studioFloorRadius(a, b);
        precise float fade = plane >= 0 ? clamp((reach - fadeStart) * invFade, 0.0, 1.0) : -1.0;
        const EnvironmentMap env = EnvironmentMap(uEnvSize.x, uEnvSize.y, uEnvParams.x, uEnvParams.y, uEnvIrradiance);
        const vec3 sky = env.width > 0 ? environmentMapRadiance(Dx, Dy, Dz, env) : skyRadiance(Dx, Dy, Dz, uSun);
        precise vec3 blend = c * (1.0 - fade) + sky * fade;  // glm::mix's formula
        const vec3 rgb = fade == 0.0 ? c : fade < 0.0 ? sky : blend;
        color[k] = vec4(rgb, 1.0);
    }
}
