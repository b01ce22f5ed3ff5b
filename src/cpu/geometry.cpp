// CPU geometry stage (geometry.h, docs/geometry.md#how-it-is-drawn). The
// liquid is composited into the user's scene as in van der Laan et al. 2009
// (US 8,947,430: the opaque scene first, the fluid splatted against its depth
// and refracting its colour) and Instant Liquids (Cords & Staadt 2008, §3):
// this stage adds the scene's objects to the scene layer the studio began.
// The per-pixel shading (shared::geometryRadiance) is the GL twin's too.
#include "cpu/geometry.h"
#include "cpu/cpu_backend.h"

#include "core/geometry_draw.h"
#include "cpu/filter_util.h"
#include "cpu/raster_mesh.h"
#include "shared/geometry_shade.h"
#include "shared/sky.h"
#include "shared/texture.h"

namespace meniscus::cpu {

namespace {

// How one object's raster goes into the picture.
enum class Blend {
    Opaque,  // shaded by geometryRadiance, colour and depth written
    Glass,   // glassRadiance over the colour there, the depth kept
};

// Covered pixels of a row shaded together: small enough to stay in L1.
constexpr int kBatch = 64;

// What every pixel of one opaque object's shading shares.
struct OpaqueSetup {
    glm::vec3 right, up, back, light, baseColor;
    float invF, halfW, halfH, roughness, metalness, exponent;
    int width;
    shared::TextureMap texture;  // enabled: base colour times it at the raster's uv
    const glm::vec2* uv;         // the raster's texture coordinates, or null
};

// Structure-of-arrays temporaries of one batch of covered pixels.
struct Batch {
    int x[kBatch + 1];  // + 1: the branch-free gather writes one slot past the last pixel
    float z[kBatch];
    float nx[kBatch], ny[kBatch], nz[kBatch];  // the raster's view-space normal, then the world normal
    float vx[kBatch], vy[kBatch], vz[kBatch];  // unit world direction toward the eye
    float nl[kBatch], nh[kBatch], lobe[kBatch];
    float br[kBatch], bg[kBatch], bb[kBatch];  // base colour
    float cr[kBatch], cg[kBatch], cb[kBatch];  // radiance
};

// Shades a batch of n covered pixels of row y of an opaque object: branch-free
// loops over the arrays that GCC vectorises (target_clones: AVX2 or the SSE2
// baseline, neither with FMA, so both give the bits of the scalar formulas),
// except the highlight's pow (a pass over the pixels its lobe can reach, most
// batches have none) and the texture's and the HDR map's texel reads. Each
// lane is shared::geometryRadiance of its pixel, the same operations in the
// same order, so the result does not depend on the batching. Env: with an HDR
// environment map, a separate instance; without, the map is a constant empty
// one, so the sky's branch is the only one compiled into the loops.
template <bool Env>
#if defined(__GNUC__)
__attribute__((flatten))
#endif
void shadeOpaqueImpl(const OpaqueSetup& S, const shared::EnvironmentMap& envIn, int y, int n, Batch& B) {
    const shared::EnvironmentMap env = Env ? envIn : shared::EnvironmentMap{};
    const glm::vec3 right = S.right, up = S.up, back = S.back, light = S.light;
    const float s = S.exponent;
    const glm::vec3 rowDir = (-(float(y) + 0.5f - S.halfH) * S.invF) * up - back;
    // 1. World normal, view vector, the key light's n.l and n.h.
    for (int i = 0; i < n; ++i) {
        const float ax = B.nx[i], ay = B.ny[i], az = B.nz[i];
        const glm::vec3 nw(ax * right.x + ay * up.x + az * back.x, ax * right.y + ay * up.y + az * back.y,
                           ax * right.z + ay * up.z + az * back.z);
        const float vxs = (float(B.x[i]) + 0.5f - S.halfW) * S.invF;
        const float dx = rowDir.x + vxs * right.x, dy = rowDir.y + vxs * right.y, dz = rowDir.z + vxs * right.z;
        const float invLen = 1.0f / std::sqrt(dx * dx + dy * dy + dz * dz);
        const glm::vec3 v(-dx * invLen, -dy * invLen, -dz * invLen);
        const glm::vec3 f = shared::geometryFacing(nw, v);
        const float nl = shared::geometryKeyCosine(f, light), nh = shared::geometryHalfway(f, v, light);
        B.nx[i] = nw.x;
        B.ny[i] = nw.y;
        B.nz[i] = nw.z;
        B.vx[i] = v.x;
        B.vy[i] = v.y;
        B.vz[i] = v.z;
        B.nl[i] = nl;
        B.nh[i] = nh;
    }
    // 2. The highlight's lobe, scalar: its pow only where it can reach 1e-4
    // (geometryLobe's test), at few pixels of most batches.
    for (int i = 0; i < n; ++i) B.lobe[i] = shared::geometryLobe(B.nl[i], B.nh[i], s);
    // 3. The base colour, times the texture where there is one (texel reads, scalar).
    if (S.texture.enabled() && S.uv) {
        const glm::vec2* uvRow = S.uv + std::size_t(y) * std::size_t(S.width);
        for (int i = 0; i < n; ++i) {
            const glm::vec2 uv = uvRow[B.x[i]];
            const glm::vec3 base = S.baseColor * shared::textureSample(S.texture, uv.x, uv.y);
            B.br[i] = base.x;
            B.bg[i] = base.y;
            B.bb[i] = base.z;
        }
    } else {
        for (int i = 0; i < n; ++i) {
            B.br[i] = S.baseColor.x;
            B.bg[i] = S.baseColor.y;
            B.bb[i] = S.baseColor.z;
        }
    }
    // 4. The radiance.
    for (int i = 0; i < n; ++i) {
        const glm::vec3 c = shared::geometryRadianceWithLobe(
            glm::vec3(B.nx[i], B.ny[i], B.nz[i]), glm::vec3(B.vx[i], B.vy[i], B.vz[i]), light,
            glm::vec3(B.br[i], B.bg[i], B.bb[i]), S.roughness, S.metalness, env, B.lobe[i]);
        B.cr[i] = c.x;
        B.cg[i] = c.y;
        B.cb[i] = c.z;
    }
}

void shadeOpaqueSky(const OpaqueSetup& S, const shared::EnvironmentMap& env, int y, int n, Batch& B) {
    shadeOpaqueImpl<false>(S, env, y, n, B);
}

void shadeOpaqueEnv(const OpaqueSetup& S, const shared::EnvironmentMap& env, int y, int n, Batch& B) {
    shadeOpaqueImpl<true>(S, env, y, n, B);
}

// One object's raster (rasteriseMesh against `depth`) shaded into `color`
// (and `depth` when opaque) where nearer than `depth` and, when given,
// `alsoBehind` (the liquid's depth, for glass fronts); an opaque object's
// base colour times `baseMap` (drawnTexture) at the raster's coordinates.
void shadeRaster(const Camera& camera, const MeshRaster& r, const GeometryMaterial& mat, const GeometryTexture* baseMap,
                 const glm::vec3& light, const shared::EnvironmentMap& env, Blend blend, const Image<float>* alsoBehind,
                 Image<glm::vec4>& color, const Image<float>& depthIn, Image<float>* depthOut) {
    const int W = camera.width, H = camera.height;
    const glm::vec3 right = camera.right(), up = camera.trueUp(), back = camera.back();
    const float invF = 1.0f / camera.focalPx(), halfW = 0.5f * float(W), halfH = 0.5f * float(H);
    if (blend == Blend::Opaque) {
        OpaqueSetup S{right, up, back, light, mat.baseColor, invF, halfW, halfH, mat.roughness, mat.metalness,
                      shared::geometryExponent(mat.roughness), W, {}, nullptr};
        // The base colour map (drawnTexture), where the raster has texture coordinates.
        if (baseMap && r.uv.width == W && r.uv.height == H) {
            S.texture = {baseMap->rgb.data(), baseMap->width, baseMap->height};
            S.uv = r.uv.pixels.data();
        }
        const bool withEnv = env.width > 0;
        forEachRow(H, [&](int y) {
            const std::size_t row = std::size_t(y) * std::size_t(W);
            const float* z = &r.depth.pixels[row];
            const float* zIn = &depthIn.pixels[row];
            const glm::vec3* nv = &r.normal.pixels[row];
            glm::vec4* out = &color.pixels[row];
            float* zOut = &depthOut->pixels[row];
            Batch B;
            for (int x = 0; x < W;) {
                // Up to kBatch covered pixels nearer than the scene, listed
                // without branches: every x is written, only covered ones kept.
                int n = 0;
                for (; x < W && n < kBatch; ++x) {
                    B.x[n] = x;
                    n += z[x] < zIn[x] ? 1 : 0;
                }
                if (n == 0) break;
                for (int i = 0; i < n; ++i) {
                    const glm::vec3 a = nv[B.x[i]];
                    B.z[i] = z[B.x[i]];
                    B.nx[i] = a.x;
                    B.ny[i] = a.y;
                    B.nz[i] = a.z;
                }
                if (withEnv) shadeOpaqueEnv(S, env, y, n, B);
                else shadeOpaqueSky(S, env, y, n, B);
                for (int i = 0; i < n; ++i) {
                    out[B.x[i]] = glm::vec4(B.cr[i], B.cg[i], B.cb[i], 1.0f);
                    zOut[B.x[i]] = B.z[i];
                }
            }
        });
        return;
    }
    // Glass: per pixel (its three pows of the tint vary with the path).
    forEachRow(H, [&](int y) __attribute__((flatten)) {
        const glm::vec3 rowDir = (-(float(y) + 0.5f - halfH) * invF) * up - back;
        for (int x = 0; x < W; ++x) {
            const float z = r.depth.at(x, y);
            if (!(z < depthIn.at(x, y))) continue;  // nothing drawn here (+inf), or behind
            if (alsoBehind && !(z < alsoBehind->at(x, y))) continue;
            const glm::vec3 nv = r.normal.at(x, y);
            const glm::vec3 n = nv.x * right + nv.y * up + nv.z * back;
            const float vx = (float(x) + 0.5f - halfW) * invF;
            const glm::vec3 d = rowDir + vx * right;
            const float invLen = 1.0f / std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
            const glm::vec3 v = -d * invLen;
            glm::vec4& c = color.at(x, y);
            // Over a transparent background (no studio) the glass is seen
            // against black, its alpha made whole.
            const glm::vec3 below = glm::vec3(c) * c.a;
            c = glm::vec4(shared::glassRadiance(below, n, v, light, mat.ior, mat.tint, mat.thicknessM, env), 1.0f);
        }
    });
}

// `faces` of the object's mesh, with its texture coordinates when its
// material has a texture to draw with them.
MeshRef objectFaces(const GeometryObject& object, std::span<const std::uint32_t> faces) {
    const TriangleMesh& m = object.mesh;
    MeshRef ref{m.positions, m.normals, faces};
    if (drawnTexture(object)) ref.uvs = object.uvs;
    return ref;
}

}  // namespace

void drawGeometry(const Camera& camera, const SceneGeometry& geometry, const shared::Studio& studio,
                  Image<glm::vec4>& color, Image<float>& depth, const shared::EnvironmentMap& environment,
                  MeshRaster* reuse) {
    const glm::vec3 light = shared::sunDirection(studio.lightDirWorld);
    std::vector<std::uint32_t> scratch;
    MeshRaster own;
    MeshRaster& r = reuse ? *reuse : own;
    // The opaque objects, then glass's back faces over them.
    for (const bool glass : {false, true})
        for (const GeometryObject& object : geometry.objects) {
            if (!drawsObject(object) || object.material.glass != glass) continue;
            const TriangleMesh& m = object.mesh;
            rasteriseMesh(camera, objectFaces(object, facesSeenFrom(m, camera.eye, sceneFaces(object), &scratch)),
                          &depth, r);
            shadeRaster(camera, r, object.material, drawnTexture(object), light, environment,
                        glass ? Blend::Glass : Blend::Opaque, nullptr,
                        color,
                        depth, &depth);
        }
}

void drawGlassFronts(const Camera& camera, const SceneGeometry& geometry, const shared::Studio& studio,
                     const Image<float>& liquidDepth, const Image<float>& sceneDepth, Image<glm::vec4>& color,
                     const shared::EnvironmentMap& environment, MeshRaster* reuse) {
    const glm::vec3 light = shared::sunDirection(studio.lightDirWorld);
    std::vector<std::uint32_t> scratch;
    MeshRaster own;
    MeshRaster& r = reuse ? *reuse : own;
    for (const GeometryObject& object : geometry.objects) {
        if (!drawsObject(object) || !object.material.glass) continue;
        const TriangleMesh& m = object.mesh;
        rasteriseMesh(camera, objectFaces(object, facesSeenFrom(m, camera.eye, Faces::Front, &scratch)), &sceneDepth, r);
        shadeRaster(camera, r, object.material, nullptr, light, environment, Blend::Glass, &liquidDepth, color, sceneDepth,
                    nullptr);
    }
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runGeometry(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    if (!s.geometry) return;
    c.paintSceneGeometry(io.at.sceneColor, io.at.sceneDepth, [&](Image<glm::vec4>& color, Image<float>& depth) {
        drawGeometry(s.camera, *s.geometry, s.studio, color, depth, s.environment, &c.geometryRaster());
    });
}

void runGlass(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    if (!s.geometry) return;
    drawGlassFronts(s.camera, *s.geometry, s.studio, c.scalar(io.at.depth), c.scalar(io.at.sceneDepth),
                    c.colorToPaint(io.at.color), s.environment, &c.geometryRaster());
}

}  // namespace

extern const StageDriver kGeometryStage = {nullptr, runGeometry};
extern const StageDriver kGlassStage = {nullptr, runGlass};

}  // namespace meniscus::cpu
