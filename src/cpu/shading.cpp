// CPU shading and compositing, docs/pipeline.md#shading. After van der Laan,
// Green & Sainz 2009 (US 8,947,430, eqs. 18-20) with the reflection/refraction
// of Cords & Staadt 2008 ("Instant Liquids" §3):
//   a     = lerp(C_fluid, S(refracted ray), exp(-k_rgb T))   (eq. 18)
//   C_out = a (1 - F) + b F + k_s (n·h)^alpha                 (eq. 20)
// with b the sky (environment map) along reflect(-v, n) in world space and F
// Schlick's Fresnel term. Below the horizon b is a itself, what the liquid
// shows through at that pixel (shared::reflectionRadiance says why).
//
// Choices:
//  - Refraction follows the refracted view ray (Snell's law, src/shared/
//    refraction.h, which the GL twin shares): inside the liquid down to the
//    depth of its back, then parallel to the view ray, intersected with the
//    scene's depth by a screen-space march (McGuire & Mara 2014). The
//    background point found is sampled; Material::refraction scales the bend.
//    The earlier offset refraction * T * f / z along the normal grew without
//    bound with the thickness (a starburst of the floor behind thick water).
//  - The background is sampled bilinearly with premultiplied alpha and the sky
//    along the view ray fills what the scene leaves transparent, so a missing
//    background blends smoothly into sky.
//  - Opaque materials (sand, milk, lava): opacity mixes the transmitted colour
//    toward a Lambert-lit fluid colour and fades the mirror reflection (a rough
//    opaque surface reflects diffusely, not like glass); the highlight stays.
//  - Speed: the output starts as a copy of the scene colour (what every
//    non-fluid pixel keeps), made row by row in parallel. Per row the fluid
//    pixels are gathered into short structure-of-arrays batches and shaded by
//    branch-free loops that GCC vectorises (target_clones: AVX2 or the SSE2
//    baseline; no FMA in either, so both give the same bits), the refracted
//    ray's march too (lane by lane; see marchBatch); only the scene-depth and
//    background texel reads stay scalar. exp and pow use the Cephes single-precision
//    polynomials (relative error ~2e-7, vs libm's correctly rounded ~6e-8) so
//    they vectorise; see fastExp/fastLog. The sky along the view ray is only
//    evaluated for batches with a transparent background, the highlight only
//    for batches that have one. On the real dam-break frame the output is
//    within 1.1e-5 of the libm / per-pixel version (the s^64 sun glow and the
//    (n.h)^120 highlight amplify ulp differences).
#include "cpu/shading.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "cpu/filter_util.h"
#include "cpu/sky.h"
#include "shared/environment.h"
#include "shared/fluids.h"
#include "shared/hole_fill.h"
#include "shared/refraction.h"
#include "shared/shading.h"
#include "shared/surface_noise.h"

namespace meniscus::cpu {

namespace {

using shared::kOpaqueAmbient;

// Fluid pixels shaded together: small enough for the batch to stay in L1.
constexpr int kBatch = 64;

// e^x for x <= 88 (Cephes expf: x = n ln2 + r, |r| <= ln2/2, degree-6
// polynomial, times 2^n built in the exponent bits). Relative error < 2e-7;
// x below -87 gives e^-87 ~ 1.6e-38 instead of underflowing to 0. exp(0) = 1
// exactly. Branch-free so loops calling it vectorise.
inline float fastExp(float x) {
    x = std::clamp(x, -87.0f, 88.0f);
    // n = round(x / ln2) by the 1.5 * 2^23 trick (no floor: SSE2 has no vector round).
    constexpr float kRound = 12582912.0f;
    const float n = (x * 1.44269504088896341f + kRound) - kRound;
    const float r = (x - n * 0.693359375f) - n * -2.12194440e-4f;
    float p = 1.9875691500e-4f;
    p = p * r + 1.3981999507e-3f;
    p = p * r + 8.3334519073e-3f;
    p = p * r + 4.1665795894e-2f;
    p = p * r + 1.6666665459e-1f;
    p = p * r + 5.0000001201e-1f;
    const float e = p * (r * r) + r + 1.0f;
    const std::int32_t bits = (static_cast<std::int32_t>(n) + 127) << 23;
    return e * std::bit_cast<float>(bits);
}

// ln x for normal x > 0 (Cephes logf: x = m 2^e with m in [sqrt(1/2), sqrt(2)),
// degree-8 polynomial in m - 1). Absolute error < 1e-7 near x = 1, where the
// highlight needs it. Branch-free.
inline float fastLog(float x) {
    const std::int32_t bits = std::bit_cast<std::int32_t>(x);
    float e = static_cast<float>((bits >> 23) - 126);
    float m = std::bit_cast<float>((bits & 0x007fffff) | 0x3f000000);  // [0.5, 1)
    const bool lo = m < 0.707106781186547524f;
    e = lo ? e - 1.0f : e;
    m = lo ? m + m - 1.0f : m - 1.0f;
    const float z = m * m;
    float p = 7.0376836292e-2f;
    p = p * m - 1.1514610310e-1f;
    p = p * m + 1.1676998740e-1f;
    p = p * m - 1.2420140846e-1f;
    p = p * m + 1.4249322787e-1f;
    p = p * m - 1.6668057665e-1f;
    p = p * m + 2.0000714765e-1f;
    p = p * m - 2.4999993993e-1f;
    p = p * m + 3.3333331174e-1f;
    float y = p * m * z;
    y += e * -2.12194440e-4f;
    y += -0.5f * z;
    return (m + y) + e * 0.693359375f;
}

// Four floats in one SSE register (GCC vector extension): the bilinear fetch
// does each texel's RGBA in one operation, lane by lane the same IEEE
// operations as the scalar formula.
typedef float Float4 __attribute__((vector_size(16)));

inline Float4 load4(const glm::vec4& c) {
    Float4 v;
    std::memcpy(&v, &c, sizeof v);
    return v;
}

// Premultiplied texel: (alpha * rgb, alpha).
inline Float4 premul(Float4 c) {
    const Float4 a{c[3], c[3], c[3], 1.0f};
    return c * a;
}

// Everything per image: computed once.
struct Setup {
    const SceneLayer* scene;
    const Image<float>* depth;
    const Image<glm::vec3>* normals;
    const Image<float>* thickness;
    const Image<float>* noise;      // null: no foam
    const Image<float>* whitening;  // null: no white water
    Image<glm::vec4>* out;
    // Several fluids (shared/fluids.h): E and T of each fluid pixel, or null.
    Image<glm::vec4>* emission;
    Image<glm::vec4>* transmit;
    bool hasScene, hasNormals, hasThickness;
    float foamThreshold, foamGain;
    glm::vec3 foamColor;
    float whiteStrength;
    glm::vec3 whiteColor;
    const float* rx;  // view ray x per column (z = -1)
    const float* ry;  // view ray y per row
    float f;          // focal length, pixels
    glm::vec3 axisX, axisY, axisZ;  // camera axes in world space (view -> world)
    glm::vec3 light;                // unit, view space
    glm::vec3 sun;                  // the sky's sun: unit, world space
    shared::EnvironmentMap env;     // the HDR map in place of the sky (disabled: the sky)
    glm::vec3 fluid, negK;
    float f0, opacity, refraction, specular, shininess, nhMin;
    float eta;  // 1 / ior (Snell's law entering the liquid)
    float minThicknessRadii, radiusM;  // thin liquid: T at least minThicknessRadii * radiusM
};

// Structure-of-arrays temporaries of one batch of fluid pixels.
struct Batch {
    int x[kBatch + 1];  // + 1: the branch-free gather writes one slot past the last pixel
    float rx[kBatch];  // view ray x of the column
    float z[kBatch], T[kBatch];
    float nx[kBatch], ny[kBatch], nz[kBatch];
    float vx[kBatch], vy[kBatch], vz[kBatch];
    float invLen[kBatch];                     // 1 / |view ray|
    float ex[kBatch], ey[kBatch], wB[kBatch];  // refracted path: exit offset (px), 1 / its eye depth
    float wz[kBatch];                          // 1 / z
    float px[kBatch], py[kBatch];             // background point seen (continuous pixel coordinates)
    float ds[kBatch], lo[kBatch], hi[kBatch];  // the march: step, bracket of the crossing
    float mw[kBatch], ms[kBatch];              // the march: this step's 1/z and parameter
    int steps2[kBatch], live[kBatch], texel[kBatch];
    float zs[kBatch];                          // the scene depth at this step's texel
    int i00[kBatch], dx[kBatch], dy[kBatch];  // bilinear footprint: first texel, steps to +x / +y
    float tx[kBatch], ty[kBatch];             // bilinear weights
    float sr[kBatch], sg[kBatch], sb[kBatch], sa[kBatch];  // premultiplied background
    float kr[kBatch], kg[kBatch], kb[kBatch];  // sky along the view ray
    float nl[kBatch], nh[kBatch];
    float cr[kBatch], cg[kBatch], cb[kBatch];
    float foam[kBatch];   // foam cover (shared::noiseFoamCover), 0 without noise
    float white[kBatch];  // white-water cover (strength * the whitening map), 0 without it
    float er[kBatch], eg[kBatch], eb[kBatch];  // Beer-Lambert share exp(-k T)
    float F[kBatch];                           // Fresnel weight after the opaque mix
    float ground[kBatch];                      // the reflected direction's groundShare (layer split only)
    float lr[kBatch], lg[kBatch], lb[kBatch];  // with a map: the opaque materials' and foam's light per colour
};

// (forward) the two instances of the shading of a batch.
void shadeBatch(const Setup& S, int y, int n, Batch& B);

// The refracted ray's march (shared::refractionMarch) over a batch, lane by
// lane: every lane runs the scalar function's operations in its order (so the
// same bits as the GL shader), the steps and the bisections as branch-free
// loops over the batch, only the scene-depth texel reads scalar. The batch
// stops stepping once every lane has crossed or run out of steps.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void marchBatch(const Setup& S, int y, int n, Batch& B) {
    const int w = S.scene->depth.width, h = S.scene->depth.height;
    const float* sceneDepth = S.scene->depth.pixels.data();
    const float p0y = float(y) + 0.5f;
    int maxSteps = 0;
    for (int i = 0; i < n; ++i) {
        const int steps = shared::refractionSteps(B.ex[i], B.ey[i]);
        B.ds[i] = 1.0f / float(steps);
        B.steps2[i] = 2 * steps;
        B.lo[i] = B.hi[i] = 2.0f;  // the path's end (p0 at infinity) when nothing is crossed
        B.live[i] = 1;
        B.wz[i] = 1.0f / B.z[i];
        maxSteps = std::max(maxSteps, steps);
    }
    const auto texelsAt = [&](int i, float s) {
        float ox, oy, pw;
        shared::refractionPathAt(s, B.ex[i], B.ey[i], B.wz[i], B.wB[i], ox, oy, pw);
        int ix, iy;
        shared::refractionTexel(float(B.x[i]) + 0.5f + ox, p0y + oy, w, h, ix, iy);
        B.texel[i] = iy * w + ix;
        B.mw[i] = pw;
        B.ms[i] = s;
    };
    for (int k = 1; k <= 2 * maxSteps; ++k) {
        for (int i = 0; i < n; ++i) texelsAt(i, float(k) * B.ds[i]);
        for (int i = 0; i < n; ++i) B.zs[i] = sceneDepth[B.texel[i]];
        int live = 0;
        for (int i = 0; i < n; ++i) {
            const bool hit = (B.live[i] != 0) & (k <= B.steps2[i]) & shared::refractionIsBehind(B.mw[i], B.zs[i]);
            B.lo[i] = hit ? float(k - 1) * B.ds[i] : B.lo[i];
            B.hi[i] = hit ? B.ms[i] : B.hi[i];
            B.live[i] = hit ? 0 : B.live[i];
            live += (B.live[i] != 0) & (k < B.steps2[i]);
        }
        if (live == 0) break;
    }
    for (int j = 0; j < shared::kRefractionRefine; ++j) {
        for (int i = 0; i < n; ++i) texelsAt(i, 0.5f * (B.lo[i] + B.hi[i]));
        for (int i = 0; i < n; ++i) B.zs[i] = sceneDepth[B.texel[i]];
        for (int i = 0; i < n; ++i) {
            const bool on = B.lo[i] < B.hi[i];  // crossed: bisect its step
            const bool behind = shared::refractionIsBehind(B.mw[i], B.zs[i]);
            B.hi[i] = (on & behind) ? B.ms[i] : B.hi[i];
            B.lo[i] = (on & !behind) ? B.ms[i] : B.lo[i];
        }
    }
    for (int i = 0; i < n; ++i) {
        float ox, oy, pw;
        shared::refractionPathAt(0.5f * (B.lo[i] + B.hi[i]), B.ex[i], B.ey[i], B.wz[i], B.wB[i], ox, oy, pw);
        B.px[i] = float(B.x[i]) + 0.5f + ox;
        B.py[i] = p0y + oy;
    }
}

// Shades a batch of n fluid pixels of row y: branch-free loops over the
// arrays, vectorised, except the texel fetch of the background. Each lane is
// the scalar computation of its pixel, so results do not depend on batching.
// Env: the HDR environment map (its texel gathers do not vectorise) instead of
// the procedural sky, a separate instance so that the sky's loops stay as
// they were (shadeBatchSky / shadeBatchEnv below).
template <bool Env>
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
inline void shadeBatchImpl(const Setup& S, int y, int n, Batch& B) {
    const float ryc = S.ry[y];
    // 1. View vector, normal (the view vector where none), sanitised thickness.
    for (int i = 0; i < n; ++i) {
        const float rx = B.rx[i];
        const float invLen = 1.0f / std::sqrt(rx * rx + ryc * ryc + 1.0f);
        const float vx = -rx * invLen, vy = -ryc * invLen, vz = invLen;
        const float nx = B.nx[i], ny = B.ny[i], nz = B.nz[i];
        const bool ok = nx * nx + ny * ny + nz * nz > 0.0f;  // false for (0,0,0) and NaN
        B.nx[i] = ok ? nx : vx;
        B.ny[i] = ok ? ny : vy;
        B.nz[i] = ok ? nz : vz;
        B.vx[i] = vx;
        B.vy[i] = vy;
        B.vz[i] = vz;
        B.invLen[i] = invLen;
        const float T = B.T[i];
        B.T[i] = shared::thinLiquidThickness(T > 0.0f && T < INFINITY ? T : 0.0f, S.minThicknessRadii, S.radiusM);
    }
    // 2. Refraction: the refracted view ray (shared/refraction.h): its path
    // in screen space and its march to the scene's depth in vector lanes
    // (marchBatch); then the background there sampled bilinearly (pixel centres at
    // +0.5, clamped to the image) with premultiplied alpha. Footprints
    // computed in vector lanes, texels fetched per pixel.
    if (S.hasScene) {
        const int w = S.scene->color.width, h = S.scene->color.height;
        const float xMax = float(w - 1), yMax = float(h - 1);
        for (int i = 0; i < n; ++i)
            shared::refractionExit(B.rx[i], ryc, B.invLen[i], B.nx[i], B.ny[i], B.nz[i], B.z[i], B.T[i], S.eta,
                                   S.refraction, S.f, B.ex[i], B.ey[i], B.wB[i]);
        marchBatch(S, y, n, B);
        for (int i = 0; i < n; ++i) {
            const float fx = std::min(xMax, std::max(0.0f, B.px[i] - 0.5f));  // NaN (garbage normals) -> 0
            const float fy = std::min(yMax, std::max(0.0f, B.py[i] - 0.5f));
            const int x0 = int(fx), y0 = int(fy);
            B.tx[i] = fx - float(x0);
            B.ty[i] = fy - float(y0);
            B.i00[i] = y0 * w + x0;
            B.dx[i] = x0 + 1 < w ? 1 : 0;
            B.dy[i] = y0 + 1 < h ? w : 0;
        }
        const glm::vec4* img = S.scene->color.pixels.data();
        for (int i = 0; i < n; ++i) {
            const glm::vec4* p = img + B.i00[i];
            const Float4 c00 = premul(load4(p[0])), c10 = premul(load4(p[B.dx[i]]));
            const Float4 c01 = premul(load4(p[B.dy[i]])), c11 = premul(load4(p[B.dy[i] + B.dx[i]]));
            const float tx = B.tx[i], ty = B.ty[i];
            const Float4 top = c00 * (1.0f - tx) + c10 * tx;
            const Float4 bottom = c01 * (1.0f - tx) + c11 * tx;
            const Float4 s = top * (1.0f - ty) + bottom * ty;
            B.sr[i] = s[0];
            B.sg[i] = s[1];
            B.sb[i] = s[2];
            B.sa[i] = s[3];
        }
    } else {
        for (int i = 0; i < n; ++i) B.sr[i] = B.sg[i] = B.sb[i] = B.sa[i] = 0.0f;
    }
    // 3. What the scene leaves transparent shows the sky along the view ray;
    // skipped for batches over an opaque background (where it adds exactly 0).
    const glm::vec3 X = S.axisX, Y = S.axisY, Z = S.axisZ, L = S.light, sun = S.sun, fc = S.fluid, k = S.negK;
    float minAlpha = 1.0f;  // (reductions as min / sums so the loops vectorise)
    for (int i = 0; i < n; ++i) minAlpha = std::min(minAlpha, B.sa[i]);
    if (Env && minAlpha < 1.0f) {
        for (int i = 0; i < n; ++i) {
            const float rx = B.rx[i];
            const glm::vec3 e =
                shared::environmentMapRadiance(rx * X.x + ryc * Y.x + -1.0f * Z.x, rx * X.y + ryc * Y.y + -1.0f * Z.y,
                                               rx * X.z + ryc * Y.z + -1.0f * Z.z, S.env);
            const float ta = 1.0f - B.sa[i];
            B.sr[i] += ta * e.x;
            B.sg[i] += ta * e.y;
            B.sb[i] += ta * e.z;
        }
    } else if (minAlpha < 1.0f) {
        for (int i = 0; i < n; ++i) {
            const float rx = B.rx[i];
            skyColorRgb(rx * X.x + ryc * Y.x + -1.0f * Z.x, rx * X.y + ryc * Y.y + -1.0f * Z.y,
                        rx * X.z + ryc * Y.z + -1.0f * Z.z, sun, &B.kr[i], &B.kg[i], &B.kb[i]);
            const float ta = 1.0f - B.sa[i];
            B.sr[i] += ta * B.kr[i];
            B.sg[i] += ta * B.kg[i];
            B.sb[i] += ta * B.kb[i];
        }
    }
    // 4. Absorption, Fresnel, reflection, branch-free.
    const float f0 = S.f0, op = S.opacity, nhMin = S.nhMin;
    int nSpec = 0;
    const bool split = S.emission != nullptr;
    for (int i = 0; i < n; ++i) {
        const float nx = B.nx[i], ny = B.ny[i], nz = B.nz[i];
        const float vx = B.vx[i], vy = B.vy[i], vz = B.vz[i];
        const float T = B.T[i];
        const float nv = std::clamp(nx * vx + ny * vy + nz * vz, 0.0f, 1.0f);
        const float nl = nx * L.x + ny * L.y + nz * L.z;

        // Beer-Lambert absorption through thickness T (eq. 18).
        const float sr = B.sr[i], sg = B.sg[i], sb = B.sb[i];
        const float er = fastExp(k.x * T), eg = fastExp(k.y * T), eb = fastExp(k.z * T);
        float ar = fc.x + (sr - fc.x) * er;
        float ag = fc.y + (sg - fc.y) * eg;
        float ab = fc.z + (sb - fc.z) * eb;
        B.er[i] = er;
        B.eg[i] = eg;
        B.eb[i] = eb;
        const float m = 1.0f - nv, m2 = m * m;
        float F = f0 + (1.0f - f0) * (m2 * m2 * m);  // schlickFresnel
        // Opaque materials: toward a Lambert-lit fluid colour (op = 0: a unchanged),
        // the ambient share from the map (its E(n) / pi at the world normal) with one.
        float litR, litG, litB;
        if constexpr (Env) {
            const glm::vec3 amb = shared::environmentAmbient(nx * X.x + ny * Y.x + nz * Z.x, nx * X.y + ny * Y.y + nz * Z.y,
                                                             nx * X.z + ny * Y.z + nz * Z.z, S.env);
            const float key = (1.0f - kOpaqueAmbient) * std::max(nl, 0.0f);
            litR = amb.x + key;
            litG = amb.y + key;
            litB = amb.z + key;
            B.lr[i] = litR;
            B.lg[i] = litG;
            B.lb[i] = litB;
        } else {
            litR = litG = litB = kOpaqueAmbient + (1.0f - kOpaqueAmbient) * std::max(nl, 0.0f);
        }
        ar = op > 0.0f ? ar * (1.0f - op) + fc.x * litR * op : ar;
        ag = op > 0.0f ? ag * (1.0f - op) + fc.y * litG * op : ag;
        ab = op > 0.0f ? ab * (1.0f - op) + fc.z * litB * op : ab;
        F = op > 0.0f ? F * (1.0f - op) : F;
        B.F[i] = F;

        // Mirror reflection of the environment, reflect(-v, n) in world space;
        // below the horizon it mirrors what the liquid shows through itself.
        const float tn = 2.0f * nv;
        const float ex = tn * nx - vx, ey = tn * ny - vy, ez = tn * nz - vz;
        float br, bg, bb;
        const float wx = ex * X.x + ey * Y.x + ez * Z.x, wy = ex * X.y + ey * Y.y + ez * Z.y,
                    wz = ex * X.z + ey * Y.z + ez * Z.z;
        if constexpr (Env) {
            const glm::vec3 e = shared::environmentReflection(wx, wy, wz, S.env, glm::vec3(ar, ag, ab));
            br = e.x;
            bg = e.y;
            bb = e.z;
        } else {
            reflectionRgb(wx, wy, wz, sun, ar, ag, ab, &br, &bg, &bb);
        }
        B.ground[i] = split ? shared::groundShare(wx, wy, wz) : 0.0f;  // only the layer split needs it
        B.cr[i] = ar * (1.0f - F) + br * F;
        B.cg[i] = ag * (1.0f - F) + bg * F;
        B.cb[i] = ab * (1.0f - F) + bb * F;

        // Blinn-Phong half vector; the highlight is added below where visible.
        const float hx = L.x + vx, hy = L.y + vy, hz = L.z + vz;
        const float hInv = 1.0f / std::sqrt(hx * hx + hy * hy + hz * hz);
        const float nh = nx * (hx * hInv) + ny * (hy * hInv) + nz * (hz * hInv);
        B.nl[i] = nl;
        B.nh[i] = nh;
        nSpec += (nl > 0.0f) & (nh > nhMin);
    }
    // 5. Blinn-Phong highlight (eq. 20), only on the lit side and where it is
    // visible: (n.h)^s = exp(s ln(n.h)) for n.h in (nhMin, 1]. Most batches have none.
    if (nSpec > 0) {
        const float ks = S.specular, sh = S.shininess;
        for (int i = 0; i < n; ++i) {
            const float nh = B.nh[i];
            const bool on = (B.nl[i] > 0.0f) & (nh > nhMin);
            const float spec = on ? ks * fastExp(sh * fastLog(std::max(nh, 1e-30f))) : 0.0f;
            B.cr[i] += spec;
            B.cg[i] += spec;
            B.cb[i] += spec;
        }
    }
    // 6. Foam over the liquid where the surface noise is strong, then white
    // water where the surface is fast (docs/pipeline.md#noise-and-foam; Instant
    // Liquids §4), both lit like the opaque materials. A cover of 0 (that
    // effect off) leaves the colour exactly as it was.
    if (S.noise || S.whitening) {
        for (int i = 0; i < n; ++i) {
            glm::vec3 c(B.cr[i], B.cg[i], B.cb[i]);
            if constexpr (Env) {
                const glm::vec3 lit(B.lr[i], B.lg[i], B.lb[i]);
                c = shared::noiseWithFoamLit(c, B.foam[i], lit, S.foamColor);
                c = shared::noiseWithFoamLit(c, B.white[i], lit, S.whiteColor);
            } else {
                c = shared::noiseWithFoam(c, B.foam[i], B.nl[i], S.foamColor, kOpaqueAmbient);
                c = shared::noiseWithFoam(c, B.white[i], B.nl[i], S.whiteColor, kOpaqueAmbient);
            }
            B.cr[i] = c.x;
            B.cg[i] = c.y;
            B.cb[i] = c.z;
        }
    }
}

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void shadeBatchSky(const Setup& S, int y, int n, Batch& B) { shadeBatchImpl<false>(S, y, n, B); }

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void shadeBatchEnv(const Setup& S, int y, int n, Batch& B) { shadeBatchImpl<true>(S, y, n, B); }

void shadeBatch(const Setup& S, int y, int n, Batch& B) {
    if (S.env.enabled()) shadeBatchEnv(S, y, n, B);
    else shadeBatchSky(S, y, n, B);
}

// Several fluids (shared/fluids.h): the batch's colours split into E and T,
// the background S being the premultiplied scene plus sky the refraction read.
void splitLayer(const Setup& S, std::size_t row, int n, const Batch& B) {
    const float keepOpaque = S.opacity > 0.0f ? 1.0f - S.opacity : 1.0f;
    for (int i = 0; i < n; ++i) {
        const glm::vec3 t = shared::fluidTransmittance(glm::vec3(B.er[i], B.eg[i], B.eb[i]), keepOpaque, B.F[i],
                                                       B.ground[i], B.foam[i], B.white[i]);
        const glm::vec3 e =
            shared::fluidEmission(glm::vec3(B.cr[i], B.cg[i], B.cb[i]), t, glm::vec3(B.sr[i], B.sg[i], B.sb[i]));
        const std::size_t k = row + std::size_t(B.x[i]);
        S.emission->pixels[k] = glm::vec4(e, 1.0f);
        S.transmit->pixels[k] = glm::vec4(t, 0.0f);
    }
}

void shadeRow(const Setup& S, int y, Batch& B) {
    const int w = S.depth->width;
    const std::size_t row = std::size_t(y) * std::size_t(w);
    const float* depth = &S.depth->pixels[row];
    const float* sceneDepth = S.hasScene ? &S.scene->depth.pixels[row] : nullptr;
    glm::vec4* out = &S.out->pixels[row];
    // Non-fluid pixels are the scene colour (transparent black without a scene).
    if (S.hasScene)
        std::memcpy(out, &S.scene->color.pixels[row], std::size_t(w) * sizeof(glm::vec4));
    else
        std::fill(out, out + w, glm::vec4(0.0f));

    const std::size_t nw = S.hasNormals ? row : 0, tw = S.hasThickness ? row : 0;
    // Only the span from the first to the last fluid pixel of the row.
    int x = 0, end = w;
    while (x < end && !(depth[x] < INFINITY)) ++x;
    while (end > x && !(depth[end - 1] < INFINITY)) --end;
    while (x < end) {
        // Up to kBatch fluid pixels in front of the scene (not +inf, not hidden),
        // listed without branches: every x is written, only fluid ones kept.
        int n = 0;
        if (sceneDepth) {
            for (; x < end && n < kBatch; ++x) {
                B.x[n] = x;
                n += (depth[x] < sceneDepth[x]) & (depth[x] > 0.0f);
            }
        } else {
            for (; x < end && n < kBatch; ++x) {
                B.x[n] = x;
                n += (depth[x] < INFINITY) & (depth[x] > 0.0f);
            }
        }
        if (n == 0) break;
        for (int i = 0; i < n; ++i) {
            const int xi = B.x[i];
            B.rx[i] = S.rx[xi];
            B.z[i] = depth[xi];
            const glm::vec3 nv = S.hasNormals ? S.normals->pixels[nw + std::size_t(xi)] : glm::vec3(0.0f);
            B.nx[i] = nv.x;
            B.ny[i] = nv.y;
            B.nz[i] = nv.z;
            B.T[i] = S.hasThickness ? S.thickness->pixels[tw + std::size_t(xi)] : 0.0f;
            B.foam[i] = S.noise ? shared::noiseFoamCover(S.noise->pixels[row + std::size_t(xi)], S.foamThreshold,
                                                         S.foamGain)
                                : 0.0f;
            B.white[i] = S.whitening ? S.whiteStrength * S.whitening->pixels[row + std::size_t(xi)] : 0.0f;
        }
        shadeBatch(S, y, n, B);
        for (int i = 0; i < n; ++i) out[B.x[i]] = glm::vec4(B.cr[i], B.cg[i], B.cb[i], 1.0f);
        if (S.emission) splitLayer(S, row, n, B);
    }
}

}  // namespace

Image<glm::vec4> shadeAndComposite(const Camera& camera, const SceneLayer& scene, const Image<float>& depth,
                                   const Image<glm::vec3>& normals, const Image<float>& thickness,
                                   const ShadingParams& params, const Image<float>* noise,
                                   const NoiseParams* noiseParams, const Image<float>* whitening,
                                   const WhiteningParams* whiteningParams, const LayerSplit* split,
                                   float minThicknessRadii, float radiusM,
                                   const shared::EnvironmentMap& environment) {
    const int w = depth.width, h = depth.height;
    if (w <= 0 || h <= 0) return Image<glm::vec4>(w, h, glm::vec4(0.0f));
    // (std::vector zero-fills here; each row is then overwritten in parallel:
    // the scene colour copied, then the fluid pixels shaded.)
    Image<glm::vec4> out;
    out.width = w;
    out.height = h;
    resizeFresh(out.pixels, std::size_t(w) * std::size_t(h));

    Setup S;
    S.scene = &scene;
    S.depth = &depth;
    S.normals = &normals;
    S.thickness = &thickness;
    S.out = &out;
    S.emission = S.transmit = nullptr;
    if (split && split->emission && split->transmit) {
        *split->emission = Image<glm::vec4>(w, h, glm::vec4(0.0f));
        *split->transmit = Image<glm::vec4>(w, h, glm::vec4(0.0f));
        S.emission = split->emission;
        S.transmit = split->transmit;
    }
    // A scene layer of another size (or none) counts as a transparent background.
    S.hasScene = scene.color.width == w && scene.color.height == h && scene.depth.width == w &&
                 scene.depth.height == h;
    S.hasNormals = normals.width == w && normals.height == h;
    S.hasThickness = thickness.width == w && thickness.height == h;
    S.noise = noise && noiseParams && noise->width == w && noise->height == h ? noise : nullptr;
    S.foamThreshold = noiseParams ? noiseParams->foamThreshold : 0.0f;
    S.foamGain = noiseParams ? noiseParams->foamGain : 0.0f;
    S.foamColor = noiseParams ? noiseParams->foamColor : glm::vec3(0.0f);
    S.whitening = whitening && whiteningParams && whitening->width == w && whitening->height == h ? whitening : nullptr;
    S.whiteStrength = whiteningParams ? whiteningParams->strength : 0.0f;
    S.whiteColor = whiteningParams ? whiteningParams->color : glm::vec3(0.0f);

    const Material& m = params.material;
    S.f = camera.focalPx();
    std::vector<float> rx(static_cast<std::size_t>(w)), ry(static_cast<std::size_t>(h));
    for (int x = 0; x < w; ++x) rx[std::size_t(x)] = (float(x) + 0.5f - 0.5f * float(w)) / S.f;
    for (int y = 0; y < h; ++y) ry[std::size_t(y)] = -(float(y) + 0.5f - 0.5f * float(h)) / S.f;
    S.rx = rx.data();
    S.ry = ry.data();
    S.axisX = camera.right();
    S.axisY = camera.trueUp();
    S.axisZ = camera.back();
    glm::vec3 light(glm::dot(params.lightDirWorld, S.axisX), glm::dot(params.lightDirWorld, S.axisY),
                    glm::dot(params.lightDirWorld, S.axisZ));
    const float lightLen = glm::length(light);
    S.light = lightLen > 0.0f ? light / lightLen : glm::vec3(0.0f, 0.0f, 1.0f);
    S.sun = shared::sunDirection(params.lightDirWorld);
    S.env = environment;
    S.fluid = m.fluidColor;
    S.negK = -glm::max(m.absorptionPerM, glm::vec3(0.0f));
    S.f0 = fresnelF0(m.ior);
    S.opacity = std::clamp(m.opacity, 0.0f, 1.0f);
    S.refraction = m.refraction;
    S.eta = 1.0f / m.ior;  // refractionExit keeps the view ray where this is unusable
    S.specular = m.specular;
    S.shininess = m.shininess;
    // The highlight is skipped where it is invisible (shared with the GL twin).
    S.nhMin = shared::highlightMinNh(m.specular, m.shininess);
    S.minThicknessRadii = minThicknessRadii;
    S.radiusM = radiusM;

    forEachRow(h, [&](int y) {
        Batch B;
        shadeRow(S, y, B);
    });
    return out;
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runShade(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    const StageSlots& at = io.at;
    SceneLayer copy;
    const SceneLayer& scene = c.sceneLayer(at.sceneColor, at.sceneDepth, &copy);
    const bool split = at.emission != Slot::None;
    LayerSplit layer;
    if (split) layer = {&c.colorOut(at.emission), &c.colorOut(at.transmit)};
    c.colorOut(at.color) = shadeAndComposite(s.camera, scene, c.scalar(at.depth), c.vec3(at.normal),
                                             c.scalar(at.thickness), s.shading,
                                             s.noise.enabled ? &c.scalar(at.noise) : nullptr, &s.noise,
                                             s.whitening.enabled ? &c.scalar(at.whitening) : nullptr, &s.whitening,
                                             split ? &layer : nullptr, s.thickness.minRadii, s.radius,
                                             s.environment);
}

}  // namespace

extern const StageDriver kShadeStage = {nullptr, runShade};

}  // namespace meniscus::cpu
