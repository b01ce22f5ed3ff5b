// How scene geometry looks (docs/geometry.md#how-it-is-drawn), written once
// for C++ and GLSL (src/shared/ is compiled by C++ and included by the GL
// shaders): cpu::drawGeometry (src/cpu/geometry.cpp) and
// shaders/geometry_shade.comp both call geometryRadiance.
//
// The lighting is the studio's own (studio_shade.h: a sky-like ambient plus
// one key light, kStudioAmbient + kStudioKey n.l; with an HDR map the ambient
// is the map's, environment.h's environmentAmbient E(n) / pi, per colour) so
// the user's objects sit in the same light as the floor and walls; on top of it the metalness /
// roughness description of real-time physically based materials (Karis 2013,
// "Real Shading in Unreal Engine 4"): the diffuse albedo is the base colour
// times (1 - metalness); the specular reflectance F0 is 0.04 for a dielectric
// and the base colour for a metal, raised toward 1 at grazing angles by
// Schlick's approximation (Schlick 1994), its grazing value capped by the
// roughness (Lagarde & de Rousiers 2014). The reflected environment
// (sky.h's environmentRadiance along the mirror direction) is weighted by the
// gloss (1 - roughness)^4, which falls off as steeply as a GGX lobe's peak (a
// rough wall shows no sharp image of the horizon); the rest of the specular lobe reflects the studio's
// light (ambient + key) diffusely; the key light's highlight is a normalised
// Blinn-Phong lobe (Blinn 1977) whose exponent 2 / alpha^2 - 2, alpha =
// roughness^2, is the usual match to the GGX width (Walter et al. 2007).
// In GLSL every intermediate is `precise`, matching the CPU's plain IEEE
// arithmetic; only pow differs between the two (by an ulp or so).
#ifndef MENISCUS_SHARED_GEOMETRY_SHADE_H
#define MENISCUS_SHARED_GEOMETRY_SHADE_H

#ifdef __cplusplus
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#endif

#include "sky.h"
#include "environment.h"
#include "studio_shade.h"

#ifdef __cplusplus
namespace meniscus::shared {
using vec3 = glm::vec3;
using std::clamp;
using std::max;
using std::pow;
using std::sqrt;
#define MENISCUS_GEOMETRY_INLINE inline
#define MENISCUS_GEOMETRY_EXACT const
#else
#define MENISCUS_GEOMETRY_INLINE
#define MENISCUS_GEOMETRY_EXACT precise
#endif

// Dielectric specular reflectance at normal incidence (an IOR of about 1.5).
#define MENISCUS_GEOMETRY_F0 0.04f
// The narrowest highlight: roughness below this is treated as this.
#define MENISCUS_GEOMETRY_MIN_ALPHA 0.02f

// The key light's normalised Blinn-Phong lobe (s + 8) / (8 pi) (n.h)^s n.l.
// Where it cannot reach 1e-4 it is 0 and pow is skipped: (n.h)^s <=
// exp(-s (1 - n.h)) (ln x <= x - 1), below e^-14.5 once s (1 - n.h) > 14.5,
// and (s + 8) / (8 pi) < 200 for every exponent used (alpha >= 0.02).
MENISCUS_GEOMETRY_INLINE float geometryLobe(float nl, float nh, float s) {
    MENISCUS_GEOMETRY_EXACT float far = s * (1.0f - nh);
    bool lit = nl > 0.0f && nh > 0.0f && far <= 14.5f;
    return lit ? (s + 8.0f) * 0.0397887358f * pow(nh, s) * nl : 0.0f;
}

// The lobe's exponent s = 2 / alpha^2 - 2 for a roughness, alpha = roughness^2
// (at least MENISCUS_GEOMETRY_MIN_ALPHA).
MENISCUS_GEOMETRY_INLINE float geometryExponent(float roughness) {
    MENISCUS_GEOMETRY_EXACT float alpha = max(roughness * roughness, MENISCUS_GEOMETRY_MIN_ALPHA);
    MENISCUS_GEOMETRY_EXACT float s = 2.0f / (alpha * alpha) - 2.0f;
    return s;
}

// n turned toward the viewer v (the inside of a cut-away tank, a glass's far
// wall): multiplying by +-1 is exact, so n.v of the result is |n.v| bit for bit.
MENISCUS_GEOMETRY_INLINE vec3 geometryFacing(vec3 n, vec3 v) {
    MENISCUS_GEOMETRY_EXACT float nv = n.x * v.x + n.y * v.y + n.z * v.z;
    MENISCUS_GEOMETRY_EXACT float flip = nv < 0.0f ? -1.0f : 1.0f;
    return vec3(n.x * flip, n.y * flip, n.z * flip);
}

// n.h, h the unit half vector of the light and the view (Blinn 1977), >= 0.
MENISCUS_GEOMETRY_INLINE float geometryHalfway(vec3 n, vec3 v, vec3 light) {
    MENISCUS_GEOMETRY_EXACT float hx = light.x + v.x;
    MENISCUS_GEOMETRY_EXACT float hy = light.y + v.y;
    MENISCUS_GEOMETRY_EXACT float hz = light.z + v.z;
    MENISCUS_GEOMETRY_EXACT float hLen = sqrt(hx * hx + hy * hy + hz * hz);
    return hLen > 0.0f ? max((n.x * hx + n.y * hy + n.z * hz) / hLen, 0.0f) : 0.0f;
}

// n.l, the key light's cosine at the (facing) normal n, >= 0.
MENISCUS_GEOMETRY_INLINE float geometryKeyCosine(vec3 n, vec3 light) {
    MENISCUS_GEOMETRY_EXACT float nl = max(n.x * light.x + n.y * light.y + n.z * light.z, 0.0f);
    return nl;
}

// What a mirror reflects along (rx, ry, rz): the HDR map (environment.h) when
// one is given, else the procedural sky.
MENISCUS_GEOMETRY_INLINE vec3 geometryEnvironment(float rx, float ry, float rz, vec3 light, EnvironmentMap envMap) {
    return envMap.width > 0 ? environmentMapRadiance(rx, ry, rz, envMap) : skyRadiance(rx, ry, rz, light);
}

// Linear RGB radiance of a surface point. n: unit world normal (turned toward
// the viewer here when it faces away: the inside of a cut-away tank);
// v: unit world direction toward the eye; light: unit world direction toward
// the key light (the sky's sun, sunDirection); base: linear base colour;
// roughness, metalness in [0, 1]; envMap: the HDR environment map reflected
// (width 0: the procedural sky). The ambient term is the studio's
// kStudioAmbient without a map, the map's irradiance E(n) / pi with one.
// geometryRadianceWithLobe is the same with the key light's lobe given
// (geometryLobe of the facing normal's geometryKeyCosine and geometryHalfway,
// exponent geometryExponent(roughness)): the CPU evaluates the lobe's pow
// apart, for the points it can reach, and the rest in vector lanes.
MENISCUS_GEOMETRY_INLINE vec3 geometryRadianceWithLobe(vec3 n, vec3 v, vec3 light, vec3 base, float roughness,
                                                       float metalness, EnvironmentMap envMap, float lobe) {
    MENISCUS_GEOMETRY_EXACT vec3 f = geometryFacing(n, v);
    MENISCUS_GEOMETRY_EXACT float nx = f.x;
    MENISCUS_GEOMETRY_EXACT float ny = f.y;
    MENISCUS_GEOMETRY_EXACT float nz = f.z;
    MENISCUS_GEOMETRY_EXACT float nv = clamp(nx * v.x + ny * v.y + nz * v.z, 0.0f, 1.0f);
    MENISCUS_GEOMETRY_EXACT float nl = geometryKeyCosine(f, light);
    // The studio's lighting of a plane facing n, per colour: the ambient
    // (the map's E(n) / pi with one) plus the key light.
    MENISCUS_GEOMETRY_EXACT float key = kStudioKey * nl;
    MENISCUS_GEOMETRY_EXACT vec3 lit = envMap.width > 0 ? environmentAmbient(nx, ny, nz, envMap) + vec3(key, key, key)
                                                       : vec3(kStudioAmbient + key, kStudioAmbient + key,
                                                              kStudioAmbient + key);
    // Schlick's Fresnel with the metalness' F0.
    MENISCUS_GEOMETRY_EXACT float m = 1.0f - nv;
    MENISCUS_GEOMETRY_EXACT float m2 = m * m;
    MENISCUS_GEOMETRY_EXACT float m5 = m2 * m2 * m;
    MENISCUS_GEOMETRY_EXACT float diel = 1.0f - metalness;
    MENISCUS_GEOMETRY_EXACT float f0r = MENISCUS_GEOMETRY_F0 * diel + base.x * metalness;
    MENISCUS_GEOMETRY_EXACT float f0g = MENISCUS_GEOMETRY_F0 * diel + base.y * metalness;
    MENISCUS_GEOMETRY_EXACT float f0b = MENISCUS_GEOMETRY_F0 * diel + base.z * metalness;
    // A rough surface's grazing reflectance stays below 1 - roughness (the
    // roughness-aware Schlick of Lagarde & de Rousiers 2014): a rough wall
    // does not turn into a mirror of the horizon at grazing angles.
    MENISCUS_GEOMETRY_EXACT float f90 = 1.0f - roughness;
    MENISCUS_GEOMETRY_EXACT float fr = f0r + (max(f90, f0r) - f0r) * m5;
    MENISCUS_GEOMETRY_EXACT float fg = f0g + (max(f90, f0g) - f0g) * m5;
    MENISCUS_GEOMETRY_EXACT float fb = f0b + (max(f90, f0b) - f0b) * m5;
    // The mirror direction reflect(-v, n) and the environment along it.
    MENISCUS_GEOMETRY_EXACT float tn = 2.0f * nv;
    MENISCUS_GEOMETRY_EXACT float rx = tn * nx - v.x;
    MENISCUS_GEOMETRY_EXACT float ry = tn * ny - v.y;
    MENISCUS_GEOMETRY_EXACT float rz = tn * nz - v.z;
    // With an HDR map (environment.h) the map along the mirror direction.
    MENISCUS_GEOMETRY_EXACT vec3 env = geometryEnvironment(rx, ry, rz, light, envMap);
    MENISCUS_GEOMETRY_EXACT float sm = 1.0f - roughness;
    MENISCUS_GEOMETRY_EXACT float sm2 = sm * sm;
    MENISCUS_GEOMETRY_EXACT float gloss = sm2 * sm2;
    // The key light's highlight: normalised Blinn-Phong, (s + 8) / (8 pi) (n.h)^s n.l.
    MENISCUS_GEOMETRY_EXACT float highlight = kStudioKey * lobe;
    // Diffuse + specular: the glossy share mirrors the environment, the rest
    // reflects the studio's light diffusely, plus the highlight.
    MENISCUS_GEOMETRY_EXACT float rough = 1.0f - gloss;
    MENISCUS_GEOMETRY_EXACT float sr = rough * lit.x + highlight;
    MENISCUS_GEOMETRY_EXACT float sg = rough * lit.y + highlight;
    MENISCUS_GEOMETRY_EXACT float sb = rough * lit.z + highlight;
    MENISCUS_GEOMETRY_EXACT float dr = base.x * diel * lit.x;
    MENISCUS_GEOMETRY_EXACT float dg = base.y * diel * lit.y;
    MENISCUS_GEOMETRY_EXACT float db = base.z * diel * lit.z;
    return vec3(dr * (1.0f - fr) + fr * (gloss * env.x + sr), dg * (1.0f - fg) + fg * (gloss * env.y + sg),
                db * (1.0f - fb) + fb * (gloss * env.z + sb));
}
MENISCUS_GEOMETRY_INLINE vec3 geometryRadiance(vec3 n, vec3 v, vec3 light, vec3 base, float roughness,
                                               float metalness, EnvironmentMap envMap) {
    MENISCUS_GEOMETRY_EXACT vec3 f = geometryFacing(n, v);
    MENISCUS_GEOMETRY_EXACT float nl = geometryKeyCosine(f, light);
    MENISCUS_GEOMETRY_EXACT float nh = geometryHalfway(f, v, light);
    MENISCUS_GEOMETRY_EXACT float lobe = geometryLobe(nl, nh, geometryExponent(roughness));
    return geometryRadianceWithLobe(n, v, light, base, roughness, metalness, envMap, lobe);
}

// Glass (GeometryMaterial::glass): a thin transparent wall over `below`, the
// colour seen through it (the liquid, the scene behind). Fresnel reflection
// of the environment by Schlick's approximation with F0 = ((ior - 1) /
// (ior + 1))^2; what enters is absorbed along the wall's path: `tint` is the
// transmittance of one centimetre of the glass, the path the wall thickness
// over the cosine of the refracted angle (Snell: sin t = sin i / ior), so
// T = tint^(thicknessM / (0.01 cos t)) (Beer-Lambert). A thin wall shifts
// the rays it passes by less than its thickness, which is neglected (the
// colour behind is taken straight behind). The key light's highlight is the
// smooth (alpha = 0.02) lobe of geometryRadiance. n, v, light as there.
MENISCUS_GEOMETRY_INLINE vec3 glassRadiance(vec3 below, vec3 n, vec3 v, vec3 light, float ior, vec3 tint,
                                            float thicknessM, EnvironmentMap envMap) {
    MENISCUS_GEOMETRY_EXACT vec3 f = geometryFacing(n, v);
    MENISCUS_GEOMETRY_EXACT float nx = f.x;
    MENISCUS_GEOMETRY_EXACT float ny = f.y;
    MENISCUS_GEOMETRY_EXACT float nz = f.z;
    MENISCUS_GEOMETRY_EXACT float nv = clamp(nx * v.x + ny * v.y + nz * v.z, 0.0f, 1.0f);
    MENISCUS_GEOMETRY_EXACT float r0 = (ior - 1.0f) / (ior + 1.0f);
    MENISCUS_GEOMETRY_EXACT float f0 = r0 * r0;
    MENISCUS_GEOMETRY_EXACT float m = 1.0f - nv;
    MENISCUS_GEOMETRY_EXACT float m2 = m * m;
    MENISCUS_GEOMETRY_EXACT float F = f0 + (1.0f - f0) * (m2 * m2 * m);
    MENISCUS_GEOMETRY_EXACT float sin2t = (1.0f - nv * nv) / (ior * ior);
    MENISCUS_GEOMETRY_EXACT float cost = sqrt(max(1.0f - sin2t, 1.0e-4f));
    MENISCUS_GEOMETRY_EXACT float path = thicknessM / (0.01f * cost);
    MENISCUS_GEOMETRY_EXACT float tr = pow(max(tint.x, 1.0e-6f), path);
    MENISCUS_GEOMETRY_EXACT float tg = pow(max(tint.y, 1.0e-6f), path);
    MENISCUS_GEOMETRY_EXACT float tb = pow(max(tint.z, 1.0e-6f), path);
    MENISCUS_GEOMETRY_EXACT float tn = 2.0f * nv;
    MENISCUS_GEOMETRY_EXACT vec3 env = geometryEnvironment(tn * nx - v.x, tn * ny - v.y, tn * nz - v.z, light, envMap);
    MENISCUS_GEOMETRY_EXACT float nl = geometryKeyCosine(f, light);
    MENISCUS_GEOMETRY_EXACT float nh = geometryHalfway(f, v, light);
    MENISCUS_GEOMETRY_EXACT float lobe = geometryLobe(nl, nh, geometryExponent(0.0f));
    MENISCUS_GEOMETRY_EXACT float highlight = kStudioKey * F * lobe;
    MENISCUS_GEOMETRY_EXACT float keep = 1.0f - F;
    return vec3(below.x * tr * keep + F * env.x + highlight, below.y * tg * keep + F * env.y + highlight,
                below.z * tb * keep + F * env.z + highlight);
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_GEOMETRY_INLINE
#undef MENISCUS_GEOMETRY_EXACT
#undef MENISCUS_GEOMETRY_F0
#undef MENISCUS_GEOMETRY_MIN_ALPHA

#endif  // MENISCUS_SHARED_GEOMETRY_SHADE_H
