#version 430 core
#extension GL_GOOGLE_include_directive : require
// Shadows stage (docs/geometry.md#shadows) on the GPU: the GL twin of
// src/cpu/shadow.cpp's runShadows. Each scene pixel's point and normal from
// its depth and its neighbours', looked up in the key light's maps (the
// nearest texel; a shadow map, Williams 1978, "Casting curved shadows on
// curved surfaces"): behind the geometry it loses the key light's share,
// behind the liquid that share is attenuated by Beer-Lambert's law.
#include "frame_params.h"
#include "studio_shade.h"
#include "shadow.h"
layout(std430, binding = 7) readonly buffer EnvironmentTexels { float environmentTexels[]; };
layout(location = 7) uniform ivec2 uEnvSize;            // the HDR map (width 0: none)
layout(location = 8) uniform vec2 uEnvParams;           // rotation (turns), intensity
layout(location = 9) uniform vec3 uEnvIrradiance[9];    // its irradiance (9 locations, 9-17)
#include "environment.h"

layout(local_size_x = 64) in;

layout(std430, binding = 1) buffer Color { vec4 color[]; };                          // W*H linear RGBA
layout(std430, binding = 2) readonly buffer Depth { float depth[]; };                // W*H eye depth
layout(std430, binding = 3) readonly buffer LightDepth { float lightDepth[]; };      // side^2, the geometry's
layout(std430, binding = 4) readonly buffer LightRaw { float lightRaw[]; };          // side^2, the liquid's nearest
layout(std430, binding = 5) readonly buffer LightThick { float lightThickness[]; };  // side^2, the liquid's chord

layout(location = 0) uniform vec3 uLightEye;
layout(location = 1) uniform vec3 uLightRight;
layout(location = 2) uniform vec3 uLightUp;
layout(location = 3) uniform vec3 uLightBack;
layout(location = 4) uniform vec3 uLightDir;     // unit, toward the key light
layout(location = 5) uniform vec3 uAbsorption;   // 1/m per channel
layout(location = 6) uniform vec2 uLightParams;  // focal (px), texel (m)

#define kInf uintBitsToFloat(0x7f800000u)

void main() {
    const int W = P.size.x, H = P.size.y;
    const int x = int(gl_GlobalInvocationID.x), y = int(gl_GlobalInvocationID.y);
    if (x >= W || y >= H) return;
    const int i = y * W + x;
    const float z = depth[i];
    if (!(z < 3.0e38)) return;
    const float zl = x > 0 ? depth[i - 1] : kInf, zr = x + 1 < W ? depth[i + 1] : kInf;
    const float zu = y > 0 ? depth[i - W] : kInf, zd = y + 1 < H ? depth[i + W] : kInf;
    const float invF = P.up.w;
    vec3 pv, nv;
    if (!shadowSurface(x, y, z, zl, zr, zu, zd, invF, W, H, pv, nv)) return;
    const vec3 right = P.right.xyz, up = P.up.xyz, back = P.back.xyz;
    precise vec3 p = P.eye.xyz + pv.x * right + pv.y * up + pv.z * back;
    precise vec3 n = nv.x * right + nv.y * up + nv.z * back;
    precise float nl = n.x * uLightDir.x + n.y * uLightDir.y + n.z * uLightDir.z;
    if (!(nl > 0.0)) return;
    float dp = 0.0;
    const ivec3 t = shadowTexel(p, uLightEye, uLightRight, uLightUp, uLightBack, uLightParams.x, kShadowMapPx, dp);
    if (t.z == 0) return;
    const int j = t.y * kShadowMapPx + t.x;
    const float bias = shadowBias(nl, uLightParams.y);
    vec3 lit = vec3(1.0);
    if (dp > lightDepth[j] + bias) lit = vec3(0.0);
    else if (lightRaw[j] < dp - bias) lit = liquidTransmittance(uAbsorption, lightThickness[j]);
    const vec4 c = color[i];
    // With an HDR map the ambient is its irradiance E(n) / pi at the normal.
    const EnvironmentMap env = EnvironmentMap(uEnvSize.x, uEnvSize.y, uEnvParams.x, uEnvParams.y, uEnvIrradiance);
    const vec3 rgb = env.width > 0 ? shadowedColorRgb(c.rgb, environmentAmbient(n.x, n.y, n.z, env), kStudioKey, nl, lit)
                                   : shadowedColor(c.rgb, kStudioAmbient, kStudioKey, nl, lit);
    color[i] = vec4(rgb, c.a);
}
