#version 430 core
#extension GL_GOOGLE_include_directive : require
// Geometry and glass stages (docs/geometry.md#how-it-is-drawn) on the GPU: the
// GL twin of src/cpu/geometry.cpp's shadeRaster. One object's rasterised depth
// and view-space normal (the mesh path's rasteriser, drawn against `depth`)
// shaded where nearer: opaque (uMode 0) by shared::geometryRadiance, colour
// and depth written; glass (uMode 1) by shared::glassRadiance over the colour
// there, the depth kept, and with uLimit only in front of the liquid's depth
// too (the glass stage's front faces). The view ray is built operation for
// operation as the CPU's, `precise`.
#include "frame_params.h"
#include "sky.h"
#include "studio_shade.h"

// The HDR environment map (src/shared/environment.h, gl/environment.h): its
// texels, size (width 0: none, the procedural sky), rotation and intensity.
layout(std430, binding = 7) readonly buffer EnvironmentTexels { float environmentTexels[]; };
layout(location = 7) uniform ivec2 uEnvSize;
layout(location = 8) uniform vec2 uEnvParams;  // rotation (turns), intensity
layout(location = 9) uniform vec3 uEnvIrradiance[9];  // its irradiance (9 locations, 9-17)
#include "geometry_shade.h"
// The object's base colour map (src/shared/texture.h): its texels, size
// (width 0: none) and the rasterised texture coordinates.
layout(std430, binding = 8) readonly buffer TextureTexels { float textureTexels[]; };
layout(std430, binding = 6) readonly buffer ObjectUv { float objectUv[]; };  // W*H*2, with a texture
layout(location = 20) uniform ivec2 uTexSize;
#include "texture.h"

layout(local_size_x = 64) in;

layout(std430, binding = 1) readonly buffer ObjectDepth { float objectDepth[]; };     // W*H, +inf = none
layout(std430, binding = 2) readonly buffer ObjectNormal { float objectNormal[]; };   // W*H*3, view space
layout(std430, binding = 3) buffer Color { vec4 color[]; };                           // W*H linear RGBA
layout(std430, binding = 4) buffer Depth { float depth[]; };                          // W*H eye depth
layout(std430, binding = 5) readonly buffer Limit { float limitDepth[]; };            // W*H, with uLimit

layout(location = 0) uniform vec3 uLight;      // unit, world, toward the key light (sunDirection)
layout(location = 1) uniform vec3 uBase;       // base colour, linear RGB
layout(location = 2) uniform vec2 uMaterial;   // roughness, metalness
layout(location = 3) uniform int uMode;        // 0 opaque, 1 glass
layout(location = 4) uniform vec3 uTint;       // glass: transmittance of 1 cm
layout(location = 5) uniform vec2 uGlass;      // glass: ior, wall thickness (m)
layout(location = 6) uniform int uLimit;       // 1: also in front of limitDepth

void main() {
    const int W = P.size.x, H = P.size.y;
    const int x = int(gl_GlobalInvocationID.x), y = int(gl_GlobalInvocationID.y);
    if (x >= W || y >= H) return;
    const int i = y * W + x;
    const float z = objectDepth[i];
    if (!(z < depth[i])) return;
    if (uLimit != 0 && !(z < limitDepth[i])) return;
    const vec3 right = P.right.xyz, up = P.up.xyz, back = P.back.xyz;
    const float invF = P.up.w;
    precise float halfW = 0.5 * float(W), halfH = 0.5 * float(H);
    precise float ry = -((float(y) + 0.5) - halfH) * invF;
    precise vec3 rowDir = ry * up - back;
    precise float vx = ((float(x) + 0.5) - halfW) * invF;
    precise vec3 d = rowDir + vx * right;
    precise float invLen = 1.0 / sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    precise vec3 v = -d * invLen;
    const vec3 nv = vec3(objectNormal[3 * i], objectNormal[3 * i + 1], objectNormal[3 * i + 2]);
    precise vec3 n = nv.x * right + nv.y * up + nv.z * back;
    const EnvironmentMap env = EnvironmentMap(uEnvSize.x, uEnvSize.y, uEnvParams.x, uEnvParams.y, uEnvIrradiance);
    if (uMode == 0) {
        precise vec3 base = uBase;
        if (uTexSize.x > 0)
            base = uBase * textureSample(TextureMap(uTexSize.x, uTexSize.y), objectUv[2 * i], objectUv[2 * i + 1]);
        color[i] = vec4(geometryRadiance(n, v, uLight, base, uMaterial.x, uMaterial.y, env), 1.0);
        depth[i] = z;
    } else {
        const vec4 c = color[i];
        precise vec3 below = c.rgb * c.a;
        color[i] = vec4(glassRadiance(below, n, v, uLight, uGlass.x, uTint, uGlass.y, env), 1.0);
    }
}
