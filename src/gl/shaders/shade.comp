#version 430 core
#extension GL_GOOGLE_include_directive : require
// Shading and compositing (docs/pipeline.md#shading) on the GPU: the GL twin of
// src/cpu/shading.cpp. After van der Laan, Green & Sainz 2009 (US 8,947,430,
// eqs. 18-20) with the reflection/refraction of Cords & Staadt 2008 ("Instant
// Liquids" §3):
//   a     = lerp(C_fluid, S(refracted ray), exp(-k_rgb T))   (eq. 18)
//   C_out = a (1 - F) + b F + k_s (n·h)^alpha                 (eq. 20)
// with b the sky (src/shared/sky.h) along reflect(-v, n) in world space (below the
// horizon a itself: reflectionRadiance), F
// Schlick's Fresnel term, S the background where the refracted view ray (Snell's
// law, src/shared/refraction.h: the screen-space march after McGuire & Mara 2014)
// meets the scene's depth, sampled bilinearly with premultiplied alpha and the sky filling what the
// scene leaves transparent; opaque materials mix toward a Lambert-lit fluid
// colour and fade the mirror reflection. With the surface noise on (
// docs/pipeline.md#noise-and-foam, the patent's foam tint by |N|), foam of cover
// noiseFoamCover(N) is laid over the result (src/shared/surface_noise.h), as the
// CPU's step 6; with the velocity whitening on (docs/pipeline.md#noise-and-foam,
// Instant Liquids §4), then white water of cover strength * map, lit the same way,
// as the CPU's step 7.
// Every operation follows the CPU's shadeBatch in the same order, `precise`
// (no FMA contraction or reassociation). The one deliberate difference: exp
// and log are the driver's built-ins where the CPU uses Cephes polynomials
// (both ~1e-7 relative); the (n·h)^120 highlight and s^64 sun glow amplify
// that, which the parity test's colour tolerance covers.
// Work: only the 8-pixel row segments that hold fluid (fluid_segments.glsl,
// listed from the fluid depth); every other pixel already holds the scene
// colour (copied by the driver before the dispatch).
#include "fluids.h"
#include "frame_params.h"
#include "hole_fill.h"
#include "shading.h"
#include "sky.h"
#include "surface_noise.h"

layout(local_size_x = 64) in;

// The HDR environment map (src/shared/environment.h, gl/environment.h): its
// texels, size (width 0: none, the procedural sky), rotation and intensity.
// A storage buffer (read lane by lane on llvmpipe), but only with a map.
layout(std430, binding = 7) readonly buffer EnvironmentTexels { float environmentTexels[]; };
layout(location = 12) uniform ivec2 uEnvSize;
layout(location = 13) uniform vec2 uEnvParams;  // rotation (turns), intensity
layout(location = 16) uniform vec3 uEnvIrradiance[9];  // its irradiance (9 locations, 16-24)
#include "environment.h"

// Reads through buffer textures, the write through an image buffer: llvmpipe
// gathers and scatters those in SIMD but runs storage-buffer accesses lane by
// lane (about 5x slower per read).
layout(binding = 0) uniform samplerBuffer sceneColor;  // W*H linear RGBA (RGBA32F)
layout(binding = 1) uniform samplerBuffer sceneDepth;  // W*H, +inf = sky
layout(binding = 2) uniform samplerBuffer depth;       // W*H fluid eye depth, +inf = none
layout(binding = 3) uniform samplerBuffer normals;     // W*H*3 view space (R32F)
layout(binding = 4) uniform samplerBuffer thickness;   // W*H metres
layout(binding = 5) uniform isamplerBuffer uSegments;  // the fluid segments (fluid_segments.glsl)
layout(binding = 6) uniform samplerBuffer noise;       // W*H surface noise N (when uFoam != 0)
layout(binding = 7) uniform samplerBuffer whitening;   // W*H velocity whitening map (when uWhite != 0)
#include "fluid_segments.glsl"
layout(rgba32f, binding = 0) writeonly uniform imageBuffer color;  // W*H linear RGBA
// Several fluids (shared/fluids.h), when uLayer != 0: the split C = E + T S.
layout(rgba32f, binding = 1) writeonly uniform imageBuffer emission;  // W*H: E, a = 1
layout(rgba32f, binding = 2) writeonly uniform imageBuffer transmit;  // W*H: T, a = 0

layout(location = 1) uniform ivec3 uHas;         // scene, normals, thickness bound (image-sized)
layout(location = 2) uniform float uNhMin;       // highlight skipped below this n·h (shared::highlightMinNh)
layout(location = 3) uniform vec3 uSun;          // the sky's sun, unit world (shared::sunDirection of the light)
layout(location = 4) uniform int uFoam;          // foam from the noise (NoiseParams' foam fields below)
layout(location = 5) uniform float uFoamThreshold;
layout(location = 6) uniform float uFoamGain;
layout(location = 7) uniform vec3 uFoamColor;
layout(location = 8) uniform int uWhite;         // white water from the whitening map (WhiteningParams below)
layout(location = 9) uniform float uWhiteStrength;
layout(location = 10) uniform vec3 uWhiteColor;
layout(location = 11) uniform int uLayer;        // write emission and transmit too

#define kInf uintBitsToFloat(0x7f800000u)

int W, H;

// The scene's eye depth at texel (x, y), for the refracted ray's march.
float refractionSceneDepth(int x, int y) { return texelFetch(sceneDepth, y * W + x).x; }
#include "refraction.h"

// Premultiplied texel k of the scene: (alpha * rgb, alpha).
vec4 premulTexel(int k) {
    const vec4 c = texelFetch(sceneColor, k);
    precise vec4 p = c * vec4(c.a, c.a, c.a, 1.0);
    return p;
}

// The shaded colour of fluid pixel (x, y) with eye depth z; rx, ryc: its view
// ray. `back`: the background S it refracted; `through`: its transmittance T.
vec3 shade(int x, int y, float z, float rx, float ryc, int k, out vec3 back, out vec3 through) {
    const bool hasScene = uHas.x != 0, hasNormals = uHas.y != 0, hasThickness = uHas.z != 0;
    const vec3 X = P.right.xyz, Y = P.up.xyz, Z = P.back.xyz;
    // Per image on the CPU (Setup); cheap enough per pixel here, same operations.
    precise vec3 Lw = P.lightDirWorld.xyz;
    precise vec3 Lv = vec3(Lw.x * X.x + Lw.y * X.y + Lw.z * X.z, Lw.x * Y.x + Lw.y * Y.y + Lw.z * Y.z,
                           Lw.x * Z.x + Lw.y * Z.y + Lw.z * Z.z);
    precise float lightLen = sqrt(Lv.x * Lv.x + Lv.y * Lv.y + Lv.z * Lv.z);
    precise vec3 L = lightLen > 0.0 ? Lv / lightLen : vec3(0.0, 0.0, 1.0);
    const vec3 fc = P.fluidColor.xyz;
    const vec3 negK = -max(P.absorptionPerM.xyz, vec3(0.0));
    precise float q = (P.absorptionPerM.w - 1.0) / (P.absorptionPerM.w + 1.0);
    precise float f0 = q * q;  // Schlick F0 (cpu::fresnelF0)
    const float op = clamp(P.fluidColor.w, 0.0, 1.0);
    const float refraction = P.lightDirWorld.w, f = P.right.w;
    precise float eta = 1.0 / P.absorptionPerM.w;  // 1 / ior, as the CPU's Setup

    // 1. View vector, normal (the view vector where none), sanitised thickness.
    precise float invLen = 1.0 / sqrt(rx * rx + ryc * ryc + 1.0);
    precise vec3 v = vec3(-rx * invLen, -ryc * invLen, invLen);
    precise vec3 n = hasNormals ? vec3(texelFetch(normals, 3 * k).x, texelFetch(normals, 3 * k + 1).x,
                                       texelFetch(normals, 3 * k + 2).x)
                                : vec3(0.0);
    precise float nn = n.x * n.x + n.y * n.y + n.z * n.z;
    n = nn > 0.0 ? n : v;  // false for (0,0,0) and NaN
    float T = hasThickness ? texelFetch(thickness, k).x : 0.0;
    T = thinLiquidThickness(T > 0.0 && T < kInf ? T : 0.0, P.thicknessMinRadii, P.radius);

    // 2. Refraction: the refracted view ray (shared/refraction.h) marched to
    // the scene's depth, the background there sampled bilinearly (pixel
    // centres at +0.5, clamped to the image) with premultiplied alpha.
    precise vec4 s = vec4(0.0);
    if (hasScene) {
        precise float ex, ey, wB, px, py;
        refractionExit(rx, ryc, invLen, n.x, n.y, n.z, z, T, eta, refraction, f, ex, ey, wB);
        precise float wz = 1.0 / z;
        refractionMarch(float(x) + 0.5, float(y) + 0.5, ex, ey, wz, wB, W, H, px, py);
        // std::min(max, std::max(0, v)) with the CPU's NaN behaviour (NaN -> 0).
        precise float mx = px - 0.5, my = py - 0.5;
        float fx = 0.0 < mx ? mx : 0.0;
        float fy = 0.0 < my ? my : 0.0;
        fx = float(W - 1) < fx ? float(W - 1) : fx;
        fy = float(H - 1) < fy ? float(H - 1) : fy;
        const int x0 = int(fx), y0 = int(fy);
        precise float tx = fx - float(x0), ty = fy - float(y0);
        const int i00 = y0 * W + x0;
        const int dx = x0 + 1 < W ? 1 : 0, dy = y0 + 1 < H ? W : 0;
        const vec4 c00 = premulTexel(i00), c10 = premulTexel(i00 + dx);
        const vec4 c01 = premulTexel(i00 + dy), c11 = premulTexel(i00 + dy + dx);
        precise vec4 top = c00 * (1.0 - tx) + c10 * tx;
        precise vec4 bottom = c01 * (1.0 - tx) + c11 * tx;
        s = top * (1.0 - ty) + bottom * ty;
    }
    // 3. What the scene leaves transparent shows the sky along the view ray.
    if (s.a < 1.0) {
        precise vec3 dir = vec3(rx * X.x + ryc * Y.x + -1.0 * Z.x, rx * X.y + ryc * Y.y + -1.0 * Z.y,
                                rx * X.z + ryc * Y.z + -1.0 * Z.z);
        const EnvironmentMap env = EnvironmentMap(uEnvSize.x, uEnvSize.y, uEnvParams.x, uEnvParams.y, uEnvIrradiance);
        const vec3 sky = env.width > 0 ? environmentMapRadiance(dir.x, dir.y, dir.z, env)
                                       : skyRadiance(dir.x, dir.y, dir.z, uSun);
        precise float ta = 1.0 - s.a;
        s.rgb = s.rgb + ta * sky;
    }
    // 4. Absorption, Fresnel, reflection.
    precise float nv = clamp(n.x * v.x + n.y * v.y + n.z * v.z, 0.0, 1.0);
    precise float nl = n.x * L.x + n.y * L.y + n.z * L.z;
    // Beer-Lambert absorption through thickness T (eq. 18).
    precise vec3 absorb = exp(negK * T);
    precise vec3 a = fc + (s.rgb - fc) * absorb;
    precise float m = 1.0 - nv;
    precise float m2 = m * m;
    precise float F = f0 + (1.0 - f0) * (m2 * m2 * m);  // schlickFresnel
    // Opaque materials: toward a Lambert-lit fluid colour (op = 0: a unchanged),
    // the ambient share from the map (its E(n) / pi at the world normal) with one.
    const EnvironmentMap envMap = EnvironmentMap(uEnvSize.x, uEnvSize.y, uEnvParams.x, uEnvParams.y, uEnvIrradiance);
    precise vec3 lit;
    if (envMap.width > 0) {
        precise vec3 nw = vec3(n.x * X.x + n.y * Y.x + n.z * Z.x, n.x * X.y + n.y * Y.y + n.z * Z.y,
                               n.x * X.z + n.y * Y.z + n.z * Z.z);
        precise float key = (1.0 - kOpaqueAmbient) * max(nl, 0.0);
        lit = environmentAmbient(nw.x, nw.y, nw.z, envMap) + vec3(key);
    } else {
        lit = vec3(kOpaqueAmbient + (1.0 - kOpaqueAmbient) * max(nl, 0.0));
    }
    if (op > 0.0) {
        a = a * (1.0 - op) + fc * lit * op;
        F = F * (1.0 - op);
    }
    // Mirror reflection of the environment, reflect(-v, n) in world space.
    precise float tn = 2.0 * nv;
    precise vec3 e = tn * n - v;
    precise vec3 ew = vec3(e.x * X.x + e.y * Y.x + e.z * Z.x, e.x * X.y + e.y * Y.y + e.z * Z.y,
                           e.x * X.z + e.y * Y.z + e.z * Z.z);
    const vec3 b = envMap.width > 0 ? environmentReflection(ew.x, ew.y, ew.z, envMap, a)
                                    : reflectionRadiance(ew.x, ew.y, ew.z, uSun, a);  // below the horizon: a
    const float ground = groundShare(ew.x, ew.y, ew.z);
    precise vec3 c = a * (1.0 - F) + b * F;
    // 5. Blinn-Phong highlight (eq. 20) on the lit side where visible:
    // (n.h)^s = exp(s ln(n.h)) for n.h in (nhMin, 1].
    precise vec3 h = L + v;
    precise float hInv = 1.0 / sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
    precise float nh = n.x * (h.x * hInv) + n.y * (h.y * hInv) + n.z * (h.z * hInv);
    if (nl > 0.0 && nh > uNhMin) {
        precise float spec = P.specular * exp(P.shininess * log(max(nh, 1e-30)));
        c = c + vec3(spec);
    }
    // 6. Foam over the liquid where the surface noise is strong
    // (docs/pipeline.md#noise-and-foam).
    float foam = 0.0;
    if (uFoam != 0) {
        foam = noiseFoamCover(texelFetch(noise, k).x, uFoamThreshold, uFoamGain);
        c = envMap.width > 0 ? noiseWithFoamLit(c, foam, lit, uFoamColor)
                             : noiseWithFoam(c, foam, nl, uFoamColor, kOpaqueAmbient);
    }
    // 7. White water where the surface is fast (docs/pipeline.md#noise-and-foam,
    // Instant Liquids §4).
    precise float white = 0.0;
    if (uWhite != 0) {
        white = uWhiteStrength * texelFetch(whitening, k).x;
        c = envMap.width > 0 ? noiseWithFoamLit(c, white, lit, uWhiteColor)
                             : noiseWithFoam(c, white, nl, uWhiteColor, kOpaqueAmbient);
    }
    back = s.rgb;
    through = fluidTransmittance(absorb, op > 0.0 ? 1.0 - op : 1.0, F, ground, foam, white);
    return c;
}

void main() {
    W = P.size.x;
    H = P.size.y;
    const bool hasScene = uHas.x != 0;
    const float f = P.right.w;
    for (int k = 0; k < uSegmentRounds; ++k) {
        int px, py;
        const int on = segmentPixel(k, W, px, py);
        if (on < 0) break;
        if (on == 0) continue;
        const int i = py * W + px;
        const float z = texelFetch(depth, i).x;
        // View rays exactly as the CPU's per-column and per-row tables.
        precise float rx = ((float(px) + 0.5) - 0.5 * float(W)) / f;
        precise float ryc = -((float(py) + 0.5) - 0.5 * float(H)) / f;
        vec3 back, through;
        const vec3 c = shade(px, py, z, rx, ryc, i, back, through);
        // Fluid in front of the scene (not +inf, not hidden); the scene elsewhere.
        if (fluidInFront(z, hasScene ? texelFetch(sceneDepth, i).x : kInf)) {
            imageStore(color, i, vec4(c, 1.0));
            if (uLayer != 0) {
                imageStore(emission, i, vec4(fluidEmission(c, through, back), 1.0));
                imageStore(transmit, i, vec4(through, 0.0));
            }
        }
    }
}
