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

// One object's raster (rasteriseMesh against `depth`) shaded into `color`
// (and `depth` when opaque) where nearer than `depth` and, when given,
// `alsoBehind` (the liquid's depth, for glass fronts); an opaque object's
// base colour times `baseMap` (drawnTexture) at the raster's coordinates.
void shadeRaster(const Camera& camera, const MeshRaster& r, const GeometryMaterial& mat, const GeometryTexture* baseMap,
                 const glm::vec3& light,
                 const shared::EnvironmentMap& env, Blend blend, const Image<float>* alsoBehind, Image<glm::vec4>& color, const Image<float>& depthIn,
                 Image<float>* depthOut) {
    const int W = camera.width, H = camera.height;
    const glm::vec3 right = camera.right(), up = camera.trueUp(), back = camera.back();
    const float invF = 1.0f / camera.focalPx(), halfW = 0.5f * float(W), halfH = 0.5f * float(H);
    // The base colour map (drawnTexture), where the raster has texture coordinates.
    shared::TextureMap texture;
    if (baseMap) texture = {baseMap->rgb.data(), baseMap->width, baseMap->height};
    const bool textured = texture.enabled() && r.uv.width == W && r.uv.height == H;
    // Flattened: the shading formulas inlined into the row's loop.
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
            if (blend == Blend::Opaque) {
                glm::vec3 base = mat.baseColor;
                if (textured) {
                    const glm::vec2 uv = r.uv.at(x, y);
                    base *= shared::textureSample(texture, uv.x, uv.y);
                }
                c = glm::vec4(shared::geometryRadiance(n, v, light, base, mat.roughness, mat.metalness, env), 1.0f);
                (*depthOut).at(x, y) = z;
            } else {
                // Over a transparent background (no studio) the glass is seen
                // against black, its alpha made whole.
                const glm::vec3 below = glm::vec3(c) * c.a;
                c = glm::vec4(shared::glassRadiance(below, n, v, light, mat.ior, mat.tint, mat.thicknessM, env), 1.0f);
            }
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
